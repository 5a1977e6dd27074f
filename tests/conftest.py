"""Fixtures shared by the test folders.

``extension_zips`` builds the extension from this checkout once per test session (the same as
``make extension``) for the packaging test and the install test. It needs Blender's extension
builder, which ships in the bpy wheel: without bpy (the NumPy 2 engine run) it skips.
"""

import importlib.util
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def extension_zips() -> dict[str, Path]:
    """Build the extension zips; Blender platform name (``linux-x64``) -> its zip."""
    if importlib.util.find_spec("bpy") is None:
        pytest.skip("Blender's extension builder comes with bpy, which is not installed")
    script = ROOT / "scripts" / "build_extension.py"
    done = subprocess.run([sys.executable, script], capture_output=True, text=True, timeout=1200)
    assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-4000:]
    manifest = tomllib.loads((ROOT / "blender_manifest.toml").read_text())
    stem = f"{manifest['id']}-{manifest['version']}"
    return {p: ROOT / "dist" / f"{stem}-{p.replace('-', '_')}.zip" for p in manifest["platforms"]}
