"""The engine never needs Blender: it imports and works with bpy & co. blocked."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ENGINE = Path(__file__).resolve().parents[2] / "voodoo_addon"
BLENDER_MODULES = ("bpy", "gpu", "mathutils", "bmesh", "bpy_extras", "bl_math", "aud", "blf")

SCRIPT = r"""
import importlib, importlib.abc, pkgutil, sys

BLOCKED = {blocked!r}

class Block(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in BLOCKED:
            raise ImportError(f"{{name}} is blocked in this test")
        return None

sys.meta_path.insert(0, Block())
for name in BLOCKED:
    sys.modules.pop(name, None)

import numpy as np
import voodoo_addon
names = sorted(m.name for m in pkgutil.walk_packages(voodoo_addon.__path__, "voodoo_addon."))
assert len(names) >= 20, names
for name in names:
    if name == "voodoo_addon.__main__":
        continue  # running it would parse this process's argv
    importlib.import_module(name)

from voodoo_addon.blob.build import BlobOptions, build_blob
from voodoo_addon.devtools.scenarios import scenario_take
from voodoo_addon.tracking import Tracker

frames, contour, truth = scenario_take("translate", frames=3, size=(160, 120), blob_pixels=2500)
blob = build_blob(frames[0], contour, BlobOptions(n_modes=6))
res = Tracker(blob).track(frames[1])
assert not res.lost and res.confidence > 0.5, res

# The blocker works: bpy really is unavailable here.
try:
    import bpy  # noqa: F401
except ImportError:
    pass
else:
    raise SystemExit("bpy imported despite the blocker")
leaked = sorted(m for m in sys.modules if m.split(".")[0] in BLOCKED)
assert not leaked, leaked
print("OK", len(names), blob.n_nodes)
"""


def test_engine_imports_and_works_without_blender(repo_root):
    proc = subprocess.run(
        [sys.executable, "-c", SCRIPT.format(blocked=set(BLENDER_MODULES))],
        cwd=repo_root,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("OK")


def _imports(path: Path):
    tree = ast.parse(path.read_text(), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield 0, alias.name
        elif isinstance(node, ast.ImportFrom):
            yield node.level, node.module or ""


ENGINE_FILES = sorted(ENGINE.rglob("*.py"))


@pytest.mark.parametrize(
    "path", ENGINE_FILES, ids=[str(p.relative_to(ENGINE)) for p in ENGINE_FILES]
)
def test_engine_source_has_no_blender_or_absolute_self_imports(path):
    for level, module in _imports(path):
        top = module.split(".")[0]
        if level == 0:
            assert top not in BLENDER_MODULES, f"{path.name} imports {module}"
            # Relative imports only inside the engine (docs/design.md, *Layout rules*).
            assert top != "voodoo_addon", f"{path.name} imports {module} absolutely"
