"""The built Linux zip installs into the running Blender and runs on its bundled wheels alone.

The zip is (re)built once per session (``extension_zips`` in tests/conftest.py, as
``make extension``; wheels are downloaded once). It holds wheels for CPython 3.11 (Blender 5.0)
and 3.13 (5.1 and later): Blender must extract its own Python's ones only (this runs on 5.0
in .venv, on 5.1 and 5.2 in the CPython 3.13 root of scripts/blender_next.sh). A child Python
gets a path holding only bpy and numpy -- no scipy, OpenCV or triangle -- and a scratch
BLENDER_USER_RESOURCES; it installs the zip, records a take of the sample clip with the installed
add-on and uninstalls it (tests/blender/installed_extension.py). Everything Blender-side happens
in that child: this process never touches its own bpy here.
"""

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DRIVER = Path(__file__).with_name("installed_extension.py")
BUNDLED = ("scipy", "cv2", "triangle", "threadpoolctl", "numba", "llvmlite", "pythonosc")
PYTHON = f"python{sys.version_info.major}.{sys.version_info.minor}"  # Blender's, as it names it
CPYTHON = f"cp{sys.version_info.major}{sys.version_info.minor}"  # its wheel tag

pytestmark = pytest.mark.slow


def bpy_only_path(folder: Path) -> Path:
    """A folder of links to bpy and numpy (all bpy needs to import), and nothing else."""
    site = Path(importlib.util.find_spec("bpy").submodule_search_locations[0]).parent
    folder.mkdir()
    for name in ("bpy", "numpy", "numpy.libs"):  # numpy.libs: numpy's own OpenBLAS
        if (site / name).exists():
            (folder / name).symlink_to(site / name)
    return folder


def run_installed(zip_path: Path, scratch: Path) -> dict:
    """Run the driver in a Python limited to bpy and numpy; what it saw."""
    report = scratch / "seen.json"
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    env["PYTHONPATH"] = str(bpy_only_path(scratch / "path"))
    env["BLENDER_USER_RESOURCES"] = str(scratch / "user")
    samples = ROOT / "samples"
    cmd = [sys.executable, "-S", DRIVER, zip_path, samples / "sample_take.mp4"]
    cmd += [samples / "sample_take.json", report]
    done = subprocess.run(cmd, env=env, cwd=scratch, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    return json.loads(report.read_text())


def test_zip_installs_runs_on_bundled_wheels_and_uninstalls(tmp_path, extension_zips):
    seen = run_installed(extension_zips["linux-x64"], tmp_path)
    extensions = tmp_path / "user" / "extensions"
    site_packages = extensions / ".local" / "lib" / PYTHON / "site-packages"
    # the child could not import the dependencies until the extension brought them
    assert seen["importable_before"] == dict.fromkeys(BUNDLED, False)
    assert seen["enabled"]
    for name in BUNDLED:
        assert Path(seen["files"][name]).resolve().is_relative_to(site_packages.resolve()), name
    # one wheel of each was extracted, the one for this CPython (or the abi3 / pure-Python one)
    assert sorted(seen["wheel_tags"]) == [
        "llvmlite",
        "numba",
        "opencv_contrib_python_headless",
        "python_osc",
        "scipy",
        "threadpoolctl",
        "triangle",
    ]
    for name, tags in seen["wheel_tags"].items():
        pythons = {tag.split("-")[0] for tag in tags}
        assert pythons in ({CPYTHON}, {"cp37"}, {"py3"}), (name, tags)
    # the add-on did the whole job: one shape key per mode, keyed on every tracked frame
    assert seen["take"]["shape_keys"] > 0
    assert seen["take"]["keyed_frames"] == [20]
    # disabled, then uninstalled: its files and its wheels' packages are gone
    assert not seen["enabled_after_disable"]
    assert Path(seen["repo_directory"]) == extensions / "user_default"
    assert not (extensions / "user_default" / "voodoo_dolls").exists()
    left = sorted(p.name for p in site_packages.iterdir()) if site_packages.exists() else []
    assert not left, left
