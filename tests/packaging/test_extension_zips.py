"""Every built extension zip installs on every Blender it claims, with each dependency once.

The zips are built from this checkout (``extension_zips`` in tests/conftest.py, as
``make extension`` does). Blender 5.0 runs CPython 3.11 with NumPy 1.26; Blender 5.1 and 5.2 run
CPython 3.13 with NumPy 2.x (bpy 5.1 and 5.2 require ``numpy>=2.2,<3``). For every zip, every
platform it claims and every Python its wheels claim, the wheels Blender would extract are found
twice, independently:

- with Blender's own code, from the bpy wheel: the manifest is read and validated by its
  extension tool ``blender_ext.py`` (as Blender reads an archive: ``[build.generated]``
  applied), the install-time compatibility check is ``repository_filter_skip`` and the
  install-time wheel choice is ``_extensions_wheel_filter_for_this_system`` of
  ``bl_extension_ops.py``, run here with the platform and Python of the Blender being checked;
- with the wheel standard: the wheels whose tags are among those ``packaging.tags`` lists as
  supported by that CPython on that platform (glibc 2.28 on Linux, macOS 13 on Apple silicon:
  what Blender 5.x and the OpenCV wheels need).

Both must pick exactly one wheel of each engine dependency (requirements.txt less numpy, which
Blender ships), the same ones, each an intact wheel whose own metadata accepts that Python and
the NumPy that Blender line ships.
"""

import ast
import builtins
import importlib.util
import re
import subprocess
import sys
import tomllib
import zipfile
from email.parser import BytesParser
from functools import cache
from pathlib import Path
from types import SimpleNamespace

import pytest
from packaging.requirements import Requirement
from packaging.specifiers import SpecifierSet
from packaging.tags import compatible_tags, cpython_tags, mac_platforms
from packaging.utils import canonicalize_name, parse_wheel_filename
from packaging.version import Version

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.slow  # builds the zips (wheels are downloaded once, into ./wheels)

#: The Blender lines the extension supports: (Blender version, its CPython, the NumPy versions
#: its line ships or accepts: 1.26.4 for 5.0; for 5.1 and later the lowest bpy accepts and the
#: one the suite runs on in Blender 5.1 and 5.2, see requirements-next.txt).
BLENDERS = {
    "5.0": ((5, 0, 1), (3, 11), ("1.26.4",)),
    "5.1": ((5, 1, 2), (3, 13), ("2.2.0", "2.3.5")),
    "5.2": ((5, 2, 3), (3, 13), ("2.2.0", "2.3.5")),
}

#: Blender platform -> (its Python's ``sysconfig.get_platform()``, the wheel platform tags the
#: standard says that Python accepts there, most specific first).
PLATFORMS = {
    "linux-x64": (
        "linux-x86_64",
        [f"manylinux_2_{minor}_x86_64" for minor in range(28, 4, -1)]
        + ["manylinux2014_x86_64", "manylinux2010_x86_64", "manylinux1_x86_64", "linux_x86_64"],
    ),
    "windows-x64": ("win-amd64", ["win_amd64"]),
    # Blender's wheel filter ignores the macOS version (see the function), only the architecture
    "macos-arm64": ("macosx-11.0-arm64", list(mac_platforms((13, 0), "arm64"))),
}


def blender_scripts() -> Path:
    (scripts,) = Path(importlib.util.find_spec("bpy").submodule_search_locations[0]).glob(
        "*/scripts"
    )
    return scripts


@cache
def blender_ext():
    """Blender's extension command-line tool, imported as a module (it runs nothing on import)."""
    path = blender_scripts() / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py"
    spec = importlib.util.spec_from_file_location("voodoo_test_blender_ext", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@cache
def _wheel_filter_code():
    path = blender_scripts() / "addons_core" / "bl_pkg" / "bl_extension_ops.py"
    tree = ast.parse(path.read_text())
    (function,) = [
        node
        for node in tree.body
        if isinstance(node, ast.FunctionDef)
        and node.name == "_extensions_wheel_filter_for_this_system"
    ]
    return compile(ast.Module(body=[function], type_ignores=[]), str(path), "exec")


def blender_picks(wheels: list[str], platform: str, python: tuple[int, int]) -> list[str]:
    """The wheels that Blender, on ``platform`` with CPython ``python``, extracts on install.

    Runs Blender's own function (from the bpy wheel's ``bl_extension_ops.py``) with the modules
    it imports inside it -- ``sysconfig``, ``sys`` and its helpers -- answering for that system.
    """
    system = {
        "sysconfig": SimpleNamespace(get_platform=lambda: PLATFORMS[platform][0]),
        "sys": SimpleNamespace(version_info=(*python, 0, "final", 0)),
    }

    def import_(name, globals=None, locals=None, fromlist=(), level=0):
        if level == 1 and name == "bl_extension_utils":
            return blender_ext()  # where bl_extension_utils takes these helpers from
        if level == 0 and name in system:
            return system[name]
        return builtins.__import__(name, globals, locals, fromlist, level)

    namespace = {
        "__builtins__": {**vars(builtins), "__import__": import_},
        "bpy": SimpleNamespace(app=SimpleNamespace(debug_python=False)),
    }
    exec(_wheel_filter_code(), namespace)
    return namespace["_extensions_wheel_filter_for_this_system"](wheels)


def standard_picks(wheels: list[str], platform: str, python: tuple[int, int]) -> list[str]:
    """The wheels whose tags the wheel standard accepts for CPython ``python`` on ``platform``."""
    platforms = PLATFORMS[platform][1]
    supported = {
        *cpython_tags(python, platforms=platforms),
        *compatible_tags(python, f"cp{python[0]}{python[1]}", platforms=platforms),
    }
    return [w for w in wheels if parse_wheel_filename(Path(w).name)[3] & supported]


def dependencies() -> dict[str, Version]:
    """The engine's pinned dependencies that the extension bundles: name -> version."""
    pins = {}
    for line in (ROOT / "requirements.txt").read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        req = Requirement(line)
        if req.name == "numpy":  # ships with Blender
            continue
        (spec,) = req.specifier
        assert spec.operator == "==", f"{line}: pin it exactly"
        pins[canonicalize_name(req.name)] = Version(spec.version)
    return pins


def manifest_of(zip_path: Path):
    """The zip's manifest as Blender reads and validates an archive (strict)."""
    manifest = blender_ext().pkg_manifest_from_archive_and_validate(str(zip_path), strict=True)
    assert not isinstance(manifest, str), f"{zip_path.name}: {manifest}"
    return manifest


def wheel_metadata(zip_path: Path, wheel: str):
    """The METADATA of a wheel inside the extension zip (the wheel opened as a zip itself)."""
    with zipfile.ZipFile(zip_path) as outer, outer.open(wheel.removeprefix("./")) as inner:
        with zipfile.ZipFile(inner) as whl:
            assert whl.testzip() is None, f"{wheel} is damaged"
            (meta,) = [n for n in whl.namelist() if re.fullmatch(r"[^/]+\.dist-info/METADATA", n)]
            return BytesParser().parsebytes(whl.read(meta))


def test_one_zip_per_platform_each_accepted_by_blenders_validator(extension_zips):
    tool = blender_scripts() / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py"
    tags = blender_scripts() / "modules" / "_bpy_internal" / "extensions" / "tags.py"
    assert set(extension_zips) == set(PLATFORMS)  # no macOS Intel: Blender 5.x has no build
    for source in [ROOT, *extension_zips.values()]:
        done = subprocess.run(
            [sys.executable, tool, "validate", "--valid-tags", tags, source],
            capture_output=True,
            text=True,
        )
        assert done.returncode == 0, f"{source}: {done.stdout}{done.stderr}"
    for platform, zip_path in extension_zips.items():
        manifest = manifest_of(zip_path)
        assert manifest.platforms == [platform]
        with zipfile.ZipFile(zip_path) as z:
            in_zip = {n for n in z.namelist() if n.endswith(".whl")}
        assert in_zip == {w.removeprefix("./") for w in manifest.wheels}, "wheels not listed"


def test_every_zip_claims_the_pythons_of_blender_5_0_and_5_1_on(extension_zips):
    for zip_path in extension_zips.values():
        claimed = blender_ext().python_versions_from_wheels(manifest_of(zip_path).wheels)
        assert claimed == {(3, 11), (3, 13)}, zip_path.name


@pytest.mark.parametrize("blender", sorted(BLENDERS))
@pytest.mark.parametrize("platform", sorted(PLATFORMS))
def test_each_dependency_has_exactly_one_matching_wheel(extension_zips, platform, blender):
    version, python, numpys = BLENDERS[blender]
    zip_path = extension_zips[platform]
    manifest = manifest_of(zip_path)

    # Blender installs it at all (platform, Python and Blender version)
    item = {
        "blender_version_min": manifest.blender_version_min,
        "platforms": manifest.platforms,
        "python_versions": [
            ".".join(map(str, v))
            for v in blender_ext().python_versions_from_wheels(manifest.wheels)
        ],
    }
    refused = []
    skip = blender_ext().repository_filter_skip(
        item=item,
        filter_blender_version=version,
        filter_python_version=(*python, 0),
        filter_platform=platform,
        skip_message_fn=refused.append,
        error_fn=refused.append,
    )
    assert not skip, refused

    # ... and extracts exactly one wheel of each dependency, the one the standard picks too
    picked = blender_picks(manifest.wheels, platform, python)
    assert sorted(picked) == sorted(standard_picks(manifest.wheels, platform, python))
    names = [canonicalize_name(parse_wheel_filename(Path(w).name)[0]) for w in picked]
    assert sorted(names) == sorted(dependencies()), (platform, python, picked)

    # each an intact wheel, the pinned version, for this Python and the NumPy Blender ships
    env = {
        "python_version": f"{python[0]}.{python[1]}",
        "python_full_version": f"{python[0]}.{python[1]}.0",
        "platform_system": {"linux": "Linux", "windows": "Windows", "macos": "Darwin"}[
            platform.split("-")[0]
        ],
        "sys_platform": {"linux": "linux", "windows": "win32", "macos": "darwin"}[
            platform.split("-")[0]
        ],
        "platform_machine": {"x64": "x86_64", "arm64": "arm64"}[platform.split("-")[1]],
        "extra": "",
    }
    for wheel in picked:
        meta = wheel_metadata(zip_path, wheel)
        name, wheel_version, *_ = parse_wheel_filename(Path(wheel).name)
        assert canonicalize_name(meta["Name"]) == name and Version(meta["Version"]) == wheel_version
        assert dependencies()[name] == wheel_version, f"{wheel} is not the pinned version"
        if meta["Requires-Python"]:
            assert SpecifierSet(meta["Requires-Python"]).contains(env["python_full_version"])
        for line in meta.get_all("Requires-Dist") or []:
            req = Requirement(line)
            if req.name != "numpy" or (req.marker and not req.marker.evaluate(env)):
                continue
            for numpy in numpys:
                assert req.specifier.contains(numpy), f"{wheel} wants numpy{req.specifier}"


def test_a_zip_of_python_3_11_wheels_only_would_be_refused_by_blender_5_1(extension_zips):
    """The check above can fail: the old zip (cp311 wheels only) does not install on 5.1."""
    wheels = [w for w in manifest_of(extension_zips["linux-x64"]).wheels if "cp313" not in w]
    pythons = [".".join(map(str, v)) for v in blender_ext().python_versions_from_wheels(wheels)]
    refused = []
    assert blender_ext().repository_filter_skip(
        item={
            "blender_version_min": "5.0.0",
            "platforms": ["linux-x64"],
            "python_versions": pythons,
        },
        filter_blender_version=(5, 1, 2),
        filter_python_version=(3, 13, 0),
        filter_platform="linux-x64",
        skip_message_fn=refused.append,
        error_fn=refused.append,
    )
    assert "3.13" in refused[0]
    picked = blender_picks(wheels, "linux-x64", (3, 13))
    assert not any(w.split("/")[-1].startswith(("scipy", "triangle")) for w in picked)


def test_the_manifest_bundles_exactly_the_pinned_requirements():
    manifest = tomllib.loads((ROOT / "blender_manifest.toml").read_text())
    bundled = {}
    for wheel in manifest["wheels"]:
        name, version, *_ = parse_wheel_filename(Path(wheel).name)
        bundled.setdefault(name, set()).add(version)
    assert bundled == {name: {version} for name, version in dependencies().items()}


def test_the_readme_licences_name_every_bundled_wheel():
    text = (ROOT / "README.md").read_text()
    section = re.search(r"^## Licences\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    assert section, "README has no Licences section"
    body = section.group(1).lower()
    manifest = tomllib.loads((ROOT / "blender_manifest.toml").read_text())
    for wheel in manifest["wheels"]:
        name, version, *_ = parse_wheel_filename(Path(wheel).name)
        assert f"{name} {version}" in body.replace("`", ""), f"{name} {version} not in Licences"
    assert "commercial" in body  # Triangle's licence: said plainly


def test_the_zips_ship_no_development_tools(extension_zips):
    """Only the add-on and its engine: no tests, scripts, samples, devtools or build files."""
    for zip_path in extension_zips.values():
        with zipfile.ZipFile(zip_path) as z:
            names = [n for n in z.namelist() if not n.startswith("wheels/")]
        tops = {n.split("/")[0] for n in names}
        assert tops <= {
            "__init__.py",
            "blender_manifest.toml",
            "README.md",
            "LICENSE",
            "operators",
            "voodoo_addon",
        }, tops
        assert not [n for n in names if "/devtools/" in n or "__pycache__" in n], zip_path
        assert "voodoo_addon/tracking/tracker.py" in names
        assert "operators/ops/apply_take.py" in names
