"""The README's scripting example is examples/track_and_apply.py, shown as it is, and it runs.

The file runs in a fresh Python (with the real bpy, as a user would), from a folder other than
the checkout; the README block between its example markers must be that file, character for
character, so the two cannot drift apart.
"""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "track_and_apply.py"


def _readme_example() -> str:
    text = (ROOT / "README.md").read_text()
    block = re.search(
        r"<!-- example:begin -->\s*```python\n(.*?)```\s*<!-- example:end -->", text, re.S
    )
    assert block, "README lost its example markers"
    return block.group(1)


def test_readme_shows_the_example_file_as_it_is():
    assert _readme_example() == EXAMPLE.read_text()
    assert "examples/track_and_apply.py" in (ROOT / "README.md").read_text()


@pytest.mark.slow
def test_example_runs(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "BLENDER_USER_RESOURCES"}
    out = subprocess.run(
        [sys.executable, EXAMPLE, "result/example.blend"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stdout[-2000:] + out.stderr[-2000:]
    assert "bend-x" in out.stdout
    assert "Take 'Take': 60 frames, applied" in out.stdout
    assert (tmp_path / "result" / "example.blend").stat().st_size > 10000
