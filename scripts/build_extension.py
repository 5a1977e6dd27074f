"""Build the extension zips: fetch the manifest's wheels, then run Blender's extension builder.

``blender_manifest.toml`` is the single source of truth: every path in its ``wheels`` list is
downloaded with pip (exact file names, so nothing can drift), wheels it no longer lists are
removed from ``./wheels``, and Blender's own ``blender_ext.py`` (shipped in the bpy wheel) builds
one zip per platform into ``dist/`` and validates each of them. Each zip holds its platform's wheels
for every Python the manifest bundles (3.11 for Blender 5.0, 3.13 for 5.1 and later); Blender
extracts the ones matching its own Python when the extension is installed.

Usage: ``python scripts/build_extension.py`` (``make extension``).
"""

import importlib.util
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
WHEELS = ROOT / "wheels"
DIST = ROOT / "dist"
OLDEST_PYTHON = "3.11"  # Blender 5.0's CPython: pip's target for pure-Python and abi3 wheels


def manifest() -> dict:
    """The parsed ``blender_manifest.toml``."""
    return tomllib.loads((ROOT / "blender_manifest.toml").read_text())


def wheel_files(data: dict) -> list[Path]:
    """The wheel files the manifest bundles (its ``wheels`` paths under the root)."""
    return [ROOT / path for path in data.get("wheels", [])]


def python_version(python_tag: str, abi: str) -> str:
    """The Python that pip should download a wheel for, from its Python and ABI tags.

    ``cp313``/``cp313`` gives ``3.13``; ``py3``/``none`` and ``cp37``/``abi3`` (any later CPython)
    give the oldest Python that Blender 5.x runs.
    """
    if python_tag.startswith("cp") and abi == python_tag:
        return f"{python_tag[2]}.{python_tag[3:]}"
    return OLDEST_PYTHON


def pip_download_args(filename: str) -> list[str]:
    """Pip arguments that select exactly the wheel ``filename`` (name, version and tags)."""
    name, version, python_tag, abi, platforms = filename.removesuffix(".whl").split("-")
    args = ["--python-version", python_version(python_tag, abi), "--implementation", "cp"]
    args += ["--abi", abi]
    for platform in platforms.split("."):
        args += ["--platform", platform]
    return [*args, f"{name}=={version}"]


def download(wheel: Path) -> None:
    """Download one wheel to its manifest path with pip; fail unless pip fetched that exact file."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "pip", "download", "--quiet", "--only-binary=:all:"]
        cmd += ["--no-deps", "--dest", tmp, *pip_download_args(wheel.name)]
        subprocess.run(cmd, check=True)
        got = Path(tmp) / wheel.name
        if not got.exists():
            found = ", ".join(p.name for p in Path(tmp).iterdir())
            sys.exit(f"pip fetched {found or 'nothing'} instead of {wheel.name}")
        shutil.move(got, wheel)


def fetch_wheels(wheels: list[Path]) -> None:
    """Download the wheels that are missing and remove the ones the manifest no longer lists."""
    WHEELS.mkdir(exist_ok=True)
    for stale in sorted(set(WHEELS.glob("*.whl")) - set(wheels)):
        print(f"removing {stale.name} (not in the manifest)")
        stale.unlink()
    for wheel in wheels:
        if not wheel.exists():
            print(f"downloading {wheel.name}")
            download(wheel)


def blender_ext() -> tuple[Path, Path]:
    """Blender's extension command-line tool and its list of valid tags, from the bpy wheel."""
    bpy_dir = Path(importlib.util.find_spec("bpy").submodule_search_locations[0])
    (scripts,) = bpy_dir.glob("*/scripts")
    return (
        scripts / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py",
        scripts / "modules" / "_bpy_internal" / "extensions" / "tags.py",
    )


def build(data: dict) -> list[Path]:
    """Build one zip per platform into ``dist/``, validate each; returns the zips."""
    tool, tags = blender_ext()
    DIST.mkdir(exist_ok=True)
    for old in DIST.glob(f"{data['id']}-*.zip"):
        old.unlink()
    subprocess.run(
        [sys.executable, tool, "build", "--source-dir", ROOT, "--output-dir", DIST]
        + ["--split-platforms", "--valid-tags", tags],
        check=True,
    )
    zips = sorted(DIST.glob(f"{data['id']}-*.zip"))
    if len(zips) != len(data["platforms"]):
        sys.exit(f"expected one zip per platform in {DIST}, found {len(zips)}")
    for zip_path in zips:
        subprocess.run(
            [sys.executable, tool, "validate", "--valid-tags", tags, zip_path], check=True
        )
    return zips


def main() -> None:
    """Fetch the wheels, build and validate the zips, print them with their sizes."""
    data = manifest()
    fetch_wheels(wheel_files(data))
    for zip_path in build(data):
        print(f"{zip_path.stat().st_size / 2**20:8.1f} MiB  {zip_path.relative_to(ROOT)}")


if __name__ == "__main__":
    try:
        main()
    except subprocess.CalledProcessError as error:
        sys.exit(f"failed ({error.returncode}): {' '.join(map(str, error.cmd))}")
