"""Enable this checkout as a Blender extension inside the bpy module (tests, demo, scripts).

The add-on is loaded the way a user's extension is: a scratch extensions repository holds a
link named after the extension id that points at the checkout, and the add-on is enabled as
``bl_ext.<repo>.voodoo_dolls``. Set ``BLENDER_USER_RESOURCES`` to a scratch folder *before*
importing bpy so the user's own Blender settings are never touched.
"""

import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ADDON_ID = "voodoo_dolls"


def enable_from_checkout(repo_module: str = "voodoo_checkout", scratch: Path | None = None) -> str:
    """Enable the checkout's add-on; returns its module name (``bl_ext.<repo>.<id>``)."""
    import addon_utils
    import bpy

    repo_dir = Path(scratch or tempfile.mkdtemp(prefix="voodoo-repo-")) / "repo"
    repo_dir.mkdir(parents=True, exist_ok=True)
    link = repo_dir / ADDON_ID
    if not link.exists():
        link.symlink_to(ROOT, target_is_directory=True)
    repos = bpy.context.preferences.extensions.repos
    if repos.get(repo_module) is None:
        repos.new(
            name=repo_module, module=repo_module, custom_directory=str(repo_dir), source="USER"
        )
    module = f"bl_ext.{repo_module}.{ADDON_ID}"
    if addon_utils.enable(module, default_set=True, handle_error=None) is None:
        raise RuntimeError(f"could not enable {module}")
    return module


def sample_blob_scene(name: str = "Doll") -> None:
    """An empty scene with the sample take as its clip and a blob built on its first frame.

    The add-on must be enabled (:func:`enable_from_checkout`).
    """
    import json

    import bpy

    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.active_clip = bpy.data.movieclips.load(str(ROOT / "samples" / "sample_take.mp4"))
    bpy.ops.voodoo.capture_frame()
    points = json.loads((ROOT / "samples" / "sample_take.json").read_text())["points"]
    bpy.ops.voodoo.sketch_contour(coords=", ".join(f"{x} {y}" for x, y in points))
    bpy.ops.voodoo.build_blob(name=name)
