"""Blender-level fixtures: the real bpy module, headless, with the add-on enabled the way a
user enables an extension (a scratch extensions repository pointing at this checkout).

bpy is imported once per process; every test starts from an empty home file (the add-on stays
enabled), and datablock references must not outlive a test.
"""

import importlib
import json
import os
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
REPO_MODULE = "voodoo_test"
ADDON_ID = "voodoo_dolls"
ADDON = f"bl_ext.{REPO_MODULE}.{ADDON_ID}"

_scratch = Path(tempfile.mkdtemp(prefix="voodoo-bl-"))
os.environ["BLENDER_USER_RESOURCES"] = str(_scratch / "user")

bpy = pytest.importorskip("bpy")
import addon_utils  # noqa: E402  (only importable once bpy is)

pytestmark = pytest.mark.blender


@pytest.fixture(scope="session")
def addon():
    """The enabled add-on package (``bl_ext.voodoo_test.voodoo_dolls``)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    repo_dir = _scratch / "repo"
    repo_dir.mkdir(parents=True, exist_ok=True)
    link = repo_dir / ADDON_ID
    if not link.exists():
        link.symlink_to(ROOT, target_is_directory=True)
    bpy.context.preferences.extensions.repos.new(
        name=REPO_MODULE, module=REPO_MODULE, custom_directory=str(repo_dir), source="USER"
    )
    mod = addon_utils.enable(ADDON, default_set=True, handle_error=None)
    assert mod is not None, "the add-on did not enable"
    yield mod
    addon_utils.disable(ADDON, default_set=True)


@pytest.fixture
def ctx(addon):
    """A fresh, empty scene with the add-on enabled; returns bpy.context."""
    bpy.ops.wm.read_homefile(use_empty=True)
    return bpy.context


@pytest.fixture
def sub(addon):
    """Import a submodule of the add-on: ``sub("operators.recorder")``."""
    return lambda name: importlib.import_module(f"{ADDON}.{name}")


def _scenario_clip(name: str, frames: int) -> dict:
    """A lossless synthetic take of a named scenario, and its outline on frame 0."""
    sys.path.insert(0, str(ROOT))
    from voodoo_addon.devtools.scenarios import scenario_take
    from voodoo_addon.devtools.synthetic import write_frames

    pictures, contour, truth = scenario_take(name, frames=frames, size=(320, 240))
    path = _scratch / f"{name}.avi"
    write_frames(path, pictures)
    return {"path": path, "contour": contour, "frames": pictures, "truth": truth}


@pytest.fixture(scope="session")
def clip_file():
    """A short take of a bending, turning doll."""
    return _scenario_clip("mixed", 20)


@pytest.fixture(scope="session")
def exit_clip():
    """A take in which the doll leaves the picture for a few frames."""
    return _scenario_clip("exit", 24)


def add_mask(points_px, size, name="Outline"):
    """A Blender mask with one closed spline through pixel points (straight segments)."""
    from importlib import import_module

    pixels = import_module(f"{ADDON}.operators.pixels")
    co = pixels.pixels_to_mask(np.asarray(points_px, dtype=float), size)
    mask = bpy.data.masks.new(name)
    layer = mask.layers.new(name="Layer")
    spline = layer.splines.new()
    spline.points.add(len(co) - 1)
    for p, (x, y) in zip(spline.points, co, strict=True):
        p.co = (x, y)
        p.handle_type = "VECTOR"
        p.handle_left = (x, y)
        p.handle_right = (x, y)
    spline.use_cyclic = True
    return mask


def prepare(clip_info) -> None:
    """Load a clip, capture its first frame, outline it from a mask, build the blob."""
    scene = bpy.context.scene
    clip = bpy.data.movieclips.load(str(clip_info["path"]))
    scene.active_clip = clip
    scene.frame_set(clip.frame_start)
    assert bpy.ops.voodoo.capture_frame() == {"FINISHED"}
    add_mask(clip_info["contour"], tuple(clip.size))
    assert bpy.ops.voodoo.contour_from_mask() == {"FINISHED"}
    assert bpy.ops.voodoo.build_blob(name="Doll") == {"FINISHED"}


@pytest.fixture
def prepared(ctx, clip_file):
    """Clip loaded, frame captured, outline from a mask, blob built: the state before a take."""
    prepare(clip_file)
    return ctx


def flat_target(name="Flat", keyed=True):
    """A subdivided square in the XZ plane (a flat cut-out), optionally with its own animation."""
    import bmesh

    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=16, y_segments=16, size=1.0)
    for v in bm.verts:
        v.co = (v.co.x, 0.0, v.co.y)
    bm.to_mesh(mesh)
    bm.free()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    if keyed:
        obj.location = (0, 0, 0)
        obj.keyframe_insert("location", frame=1)
        obj.location = (2, 0, 0)
        obj.keyframe_insert("location", frame=30)
    return obj


def solid_target(name="Box"):
    """A 3D extruded character (closed, with depth along Y) from the sample characters."""
    spec = importlib.util.spec_from_file_location(
        "voodoo_characters", ROOT / "scripts" / "characters.py"
    )
    chars = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(chars)
    return chars.make_extruded(name=name, collection=bpy.context.scene.collection)


def read_json(path):
    return json.loads(Path(path).read_text())


@pytest.fixture
def make(addon):
    """Scene builders for the tests: ``make.flat_target()``, ``make.solid_target()``,
    ``make.add_mask(points, size)``, ``make.prepare(clip)`` (blob built on a clip fixture)."""
    from types import SimpleNamespace

    return SimpleNamespace(
        flat_target=flat_target, solid_target=solid_target, add_mask=add_mask, prepare=prepare
    )
