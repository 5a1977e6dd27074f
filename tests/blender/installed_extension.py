"""Driven by test_install.py, in a Python that can import bpy and numpy and nothing else.

Installs the extension zip the way a user does, records a short take of the sample clip with
the installed add-on, uninstalls it, and writes what it saw to a JSON file for the test to
check. Usage: ``python -S installed_extension.py ZIP CLIP OUTLINE_JSON REPORT_JSON``.
"""

import importlib.util
import json
import sys
from pathlib import Path

import bpy
from bpy_extras import anim_utils

ADDON = "bl_ext.user_default.voodoo_dolls"
BUNDLED = ("scipy", "cv2", "triangle", "threadpoolctl", "numba", "llvmlite", "pythonosc")
FRAMES = 20


def run(op, **kwargs) -> None:
    """Call an operator; fail loudly unless it finished."""
    result = op(**kwargs)
    if result != {"FINISHED"}:
        raise RuntimeError(f"{op.idname_py()} returned {result}")


def importable() -> dict:
    """Which of the bundled packages this Python can find."""
    return {name: importlib.util.find_spec(name) is not None for name in BUNDLED}


def user_repo():
    """The ``user_default`` extensions repository of the scratch user resources."""
    return next(r for r in bpy.context.preferences.extensions.repos if r.module == "user_default")


def flat_target():
    """A subdivided square in the XZ plane for the take to animate."""
    import bmesh  # only importable once bpy is

    mesh = bpy.data.meshes.new("Flat")
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=8, y_segments=8, size=1.0)
    for v in bm.verts:
        v.co = (v.co.x, 0.0, v.co.y)
    bm.to_mesh(mesh)
    bm.free()
    obj = bpy.data.objects.new("Flat", mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def record_take(clip_path: str, outline: list) -> dict:
    """Capture, outline, build, track and apply with the installed add-on; what was keyed."""
    scene = bpy.context.scene
    clip = bpy.data.movieclips.load(clip_path)
    scene.active_clip = clip
    scene.frame_set(clip.frame_start)
    run(bpy.ops.voodoo.capture_frame)
    run(bpy.ops.voodoo.sketch_contour, coords=", ".join(f"{x} {y}" for x, y in outline))
    run(bpy.ops.voodoo.build_blob, name="Doll")
    run(bpy.ops.voodoo.track_clip, max_frames=FRAMES)
    scene.voodoo.target = target = flat_target()
    run(bpy.ops.voodoo.apply_take)
    keys = target.data.shape_keys
    bag = anim_utils.action_get_channelbag_for_slot(
        keys.animation_data.action, keys.animation_data.action_slot
    )
    return {
        "shape_keys": len(keys.key_blocks) - 1,
        "keyed_frames": sorted({len(fc.keyframe_points) for fc in bag.fcurves}),
    }


def wheel_tags(site_packages: Path) -> dict:
    """The distributions Blender extracted into its site-packages: name -> their wheels' tags."""
    return {
        info.name.split("-")[0]: [
            line.split(":", 1)[1].strip()
            for line in (info / "WHEEL").read_text().splitlines()
            if line.startswith("Tag:")
        ]
        for info in site_packages.glob("*.dist-info")
    }


def main(zip_path: str, clip_path: str, outline_path: str) -> dict:
    seen = {"importable_before": importable()}
    run(
        bpy.ops.extensions.package_install_files,
        filepath=zip_path,
        repo="user_default",
        enable_on_install=True,
    )
    seen["enabled"] = ADDON in bpy.context.preferences.addons
    seen["take"] = record_take(clip_path, json.loads(Path(outline_path).read_text())["points"])
    seen["files"] = {name: sys.modules[name].__file__ for name in BUNDLED}
    seen["wheel_tags"] = wheel_tags(Path(sys.modules["scipy"].__file__).parents[1])
    run(bpy.ops.preferences.addon_disable, module=ADDON)
    seen["enabled_after_disable"] = ADDON in bpy.context.preferences.addons
    run(
        bpy.ops.extensions.package_uninstall,
        repo_directory=user_repo().directory,
        pkg_id="voodoo_dolls",
    )
    seen["repo_directory"] = user_repo().directory
    return seen


if __name__ == "__main__":
    *args, report = sys.argv[1:]
    Path(report).write_text(json.dumps(main(*args)))
