"""Drawing over the Movie Clip Editor: the outline, the blob mesh and the tracked mesh.

A ``POST_PIXEL`` draw handler maps engine pixels to the region with the region's View2D
(:func:`.pixels.pixels_to_region`), so the overlay follows pan and zoom.
"""

import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from .pixels import pixels_to_region
from .storage import is_blob, stored_blob

OUTLINE_COLOUR = (1.0, 0.45, 0.1, 1.0)
MESH_COLOUR = (1.0, 0.85, 0.2, 0.8)
TRACK_COLOUR = (0.2, 1.0, 0.4, 0.9)
LOST_COLOUR = (1.0, 0.2, 0.2, 0.9)

#: What the recorder shows live: {"nodes": (m, 2), "triangles": (t, 3), "lost": bool}.
live_state: dict = {}
_handle = None


def _edges(triangles: np.ndarray) -> np.ndarray:
    e = np.vstack([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    return np.unique(np.sort(e, axis=1), axis=0)


def _draw_lines(coords, colour, shader):
    batch = batch_for_shader(shader, "LINES", {"pos": coords.astype(np.float32)})
    shader.uniform_float("color", colour)
    batch.draw(shader)


def draw_overlay():
    """The draw handler: outline, rest mesh (when not recording) and live tracked mesh."""
    context = bpy.context
    space = context.space_data
    scene = context.scene
    settings = getattr(scene, "voodoo", None)
    if settings is None or space is None or space.clip is None:
        return
    height = space.clip.size[1]
    v2r = context.region.view2d.view_to_region
    shader = gpu.shader.from_builtin("UNIFORM_COLOR")
    shader.bind()
    gpu.state.blend_set("ALPHA")
    gpu.state.line_width_set(1.5)
    if len(settings.contour) >= 2:
        pts = np.array([p.co for p in settings.contour])
        reg = pixels_to_region(pts, height, v2r)
        seg = np.stack([reg, np.roll(reg, -1, axis=0)], axis=1).reshape(-1, 2)
        _draw_lines(seg, OUTLINE_COLOUR, shader)
    mesh = None
    if live_state:
        colour = LOST_COLOUR if live_state.get("lost") else TRACK_COLOUR
        mesh = (live_state["nodes"], live_state["triangles"], colour)
    elif is_blob(settings.blob):
        try:
            blob = stored_blob(settings.blob)
            mesh = (blob.vertices, blob.triangles, MESH_COLOUR)
        except Exception:  # noqa: BLE001 - drawing must never raise
            mesh = None
    if mesh is not None:
        nodes, tris, colour = mesh
        reg = pixels_to_region(np.asarray(nodes), height, v2r)
        _draw_lines(reg[_edges(np.asarray(tris)).ravel()], colour, shader)
    gpu.state.blend_set("NONE")
    gpu.state.line_width_set(1.0)


def tag_redraw(context=None) -> None:
    wm = (context or bpy.context).window_manager
    for window in wm.windows:
        for area in window.screen.areas:
            if area.type == "CLIP_EDITOR":
                area.tag_redraw()


def register():
    global _handle
    if _handle is None:
        _handle = bpy.types.SpaceClipEditor.draw_handler_add(
            draw_overlay, (), "WINDOW", "POST_PIXEL"
        )


def unregister():
    global _handle
    if _handle is not None:
        bpy.types.SpaceClipEditor.draw_handler_remove(_handle, "WINDOW")
        _handle = None
    live_state.clear()
