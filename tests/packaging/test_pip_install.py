"""``pip install .`` gives the engine and a ``voodoo`` command that runs from any directory.

The checkout is built into a wheel by pip (PEP 517, pyproject.toml) and installed into a scratch
prefix without its dependencies (this test environment has them already: requirements.txt). The
commands then run in a scratch directory with only that prefix on the path, so the engine they
import is the installed one, never the checkout. (A fresh virtualenv with the dependencies from
the package index is the same install plus downloads; see the README.)
"""

import json
import os
import subprocess
import sys
import sysconfig
import tomllib
import zipfile
from email.parser import BytesParser
from pathlib import Path

import pytest
from packaging.requirements import Requirement

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "samples"

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(wheel file, scripts folder, environment) of the checkout installed into a prefix."""
    tmp = tmp_path_factory.mktemp("pip")
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "-q"]
    done = subprocess.run(
        [*pip, "wheel", "--no-deps", "-w", tmp / "wheel", ROOT], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr[-3000:]
    (wheel,) = (tmp / "wheel").glob("*.whl")
    prefix = tmp / "prefix"
    done = subprocess.run(
        [*pip, "install", "--no-deps", "--prefix", prefix, wheel], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr[-3000:]
    vars_ = {"base": str(prefix), "platbase": str(prefix)}
    site = Path(sysconfig.get_path("purelib", vars=vars_))
    scripts = Path(sysconfig.get_path("scripts", vars=vars_))
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    env["PYTHONPATH"] = str(site)
    return wheel, scripts, env


def run(cmd, env, cwd):
    return subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True, timeout=300)


def test_the_wheel_holds_the_engine_its_command_and_pins_but_no_devtools(installed):
    wheel, _, _ = installed
    with zipfile.ZipFile(wheel) as whl:
        names = whl.namelist()
        (meta,) = [n for n in names if n.endswith(".dist-info/METADATA")]
        metadata = BytesParser().parsebytes(whl.read(meta))
        (entry,) = [n for n in names if n.endswith(".dist-info/entry_points.txt")]
        entry_points = whl.read(entry).decode()
    engine = {str(p.relative_to(ROOT)) for p in (ROOT / "voodoo_addon").rglob("*.py")}
    devtools = {n for n in engine if n.startswith("voodoo_addon/devtools/")}
    assert devtools and not devtools & set(names)
    assert engine - devtools <= set(names)
    assert not [n for n in names if not n.startswith("voodoo_addon/") and ".dist-info/" not in n]
    assert "voodoo = voodoo_addon.cli:main" in entry_points
    manifest = tomllib.loads((ROOT / "blender_manifest.toml").read_text())
    assert metadata["Version"] == manifest["version"]
    pins = [
        Requirement(line.split("#")[0])
        for line in (ROOT / "requirements.txt").read_text().splitlines()
        if line.split("#")[0].strip()
    ]
    assert sorted(map(str, pins)) == sorted(
        map(str, map(Requirement, metadata.get_all("Requires-Dist")))
    )


def test_voodoo_tracks_and_checks_from_another_directory(installed, tmp_path):
    _, scripts, env = installed
    voodoo = str(scripts / "voodoo")
    where = run(
        [sys.executable, "-c", "import voodoo_addon; print(voodoo_addon.__file__)"], env, tmp_path
    )
    assert Path(where.stdout.strip()).is_relative_to(Path(env["PYTHONPATH"])), where

    clip, contour = SAMPLES / "sample_take.mp4", SAMPLES / "sample_take.json"
    done = run(
        [voodoo, "track", clip, "--contour", contour, "--out", "t.npz", "--frames", "30"],
        env,
        tmp_path,
    )
    assert done.returncode == 0, done.stderr
    assert "track: 30 frames" in done.stdout and (tmp_path / "t.npz").exists()

    done = run([voodoo, "check", clip, "t.npz", "--json"], env, tmp_path)
    assert done.returncode == 0, done.stderr
    score = json.loads(done.stdout)
    assert score["frames"] == 30 and score["consistency_mean"] > 0.9

    done = run([sys.executable, "-m", "voodoo_addon", "check", clip, "t.npz"], env, tmp_path)
    assert done.returncode == 0 and done.stdout.startswith("check: 30 frames"), done.stderr


@pytest.mark.parametrize("command", [["synth", "mixed", "--out", "x.avi"], ["bench", "--quick"]])
def test_development_commands_say_they_need_a_checkout(installed, tmp_path, command):
    _, scripts, env = installed
    done = run([str(scripts / "voodoo"), *command], env, tmp_path)
    assert done.returncode == 2
    assert done.stderr.startswith("error: ") and "checkout" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1, done.stderr
