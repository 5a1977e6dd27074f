"""scripts/blender_next.sh, which runs the suite in Blender 5.1 and 5.2, fails clearly and cleanly.

Its success is the rest of ``make test`` (the suite passing in the root it makes); here, what
it does when it cannot do its job: a clear message, a non-zero exit, nothing left mounted and
no half-made root taken for a whole one. These run on the host only (not inside that root,
which has no debootstrap) and need root, as the script does.
"""

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "blender_next.sh"

pytestmark = pytest.mark.skipif(
    os.environ.get("VOODOO_IN_NEXT_ROOT") == "1" or os.geteuid() != 0,
    reason="runs on the host, as root (it makes the CPython 3.13 root)",
)


def run(*args, env=None, user=None):
    cmd = [str(SCRIPT), *args]
    if user is not None:  # drop root: setpriv is in util-linux, like unshare
        cmd = ["setpriv", f"--reuid={user}", f"--regid={user}", "--clear-groups", *cmd]
    full_env = {**os.environ, **(env or {})}
    return subprocess.run(cmd, env=full_env, capture_output=True, text=True, timeout=600)


def mounts_under(folder: Path) -> list[str]:
    lines = Path("/proc/mounts").read_text().splitlines()
    return [line.split()[1] for line in lines if line.split()[1].startswith(str(folder))]


def test_without_a_version_it_says_how_to_call_it():
    done = run()
    assert done.returncode == 1
    assert "usage: scripts/blender_next.sh BPY_VERSION" in done.stderr


def test_without_root_it_says_it_needs_root(tmp_path):
    cache = tmp_path / "cache"
    done = run("5.2.3", env={"VOODOO_NEXT_CACHE": str(cache)}, user=65534)
    assert done.returncode == 1
    assert "needs root" in done.stderr and "Blender 5.2.3" in done.stderr
    assert not cache.exists()


def test_an_unreachable_archive_fails_clearly_and_leaves_no_root(tmp_path):
    cache = tmp_path / "cache"
    env = {"VOODOO_NEXT_CACHE": str(cache), "VOODOO_DEBIAN_MIRROR": "http://127.0.0.1:9/debian"}
    done = run("5.2.3", "--co", env=env)
    assert done.returncode == 1
    assert "debootstrap could not make the Debian 13 root from http://127.0.0.1:9/debian" in (
        done.stderr
    )
    assert "VOODOO_DEBIAN_MIRROR" in done.stderr
    assert not (cache / "trixie").exists()  # only a .partial, never taken for a root
    assert mounts_under(cache) == []
