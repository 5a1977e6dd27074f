"""The README's scripting example runs as written (in a fresh Python, like a user would)."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _example() -> str:
    text = (ROOT / "README.md").read_text()
    block = re.search(
        r"<!-- example:begin -->\s*```python\n(.*?)```\s*<!-- example:end -->", text, re.S
    )
    assert block, "README lost its example markers"
    return block.group(1)


@pytest.mark.slow
def test_readme_example_runs(tmp_path):
    for name in ("scripts", "samples"):
        (tmp_path / name).symlink_to(ROOT / name, target_is_directory=True)
    (tmp_path / "example.py").write_text(_example())
    env = {k: v for k, v in os.environ.items() if k != "BLENDER_USER_RESOURCES"}
    out = subprocess.run(
        [sys.executable, "example.py"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stdout[-2000:] + out.stderr[-2000:]
    assert "bend-x" in out.stdout
    assert "Take 'Take': 60 frames, applied" in out.stdout
    assert (tmp_path / "out" / "example.blend").stat().st_size > 10000
