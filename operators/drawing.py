"""Drawing over the Movie Clip Editor: the outline, the blob mesh and the tracked mesh.

A ``POST_PIXEL`` draw handler maps engine pixels to the region with the region's View2D
(:func:`.pixels.pixels_to_region`), so the overlay follows pan and zoom. While a take is
recorded it shows the live tracked meshes; after, on a frame of the last take, that take's
meshes (scrubbing shows what was tracked, the part out of view faint, a lost frame red);
elsewhere the blob's rest mesh.
"""

import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from ..voodoo_addon.blob.mesh import mesh_edges
from .dolls import doll_settings
from .pixels import pixels_to_region
from .storage import is_blob, shown_take, stored_blob

OUTLINE_COLOUR = (1.0, 0.45, 0.1, 1.0)
MESH_COLOUR = (1.0, 0.85, 0.2, 0.8)
TRACK_COLOUR = (0.2, 1.0, 0.4, 0.9)
#: The part of a tracked doll out of view (folded under, turned away, covered): faint.
HIDDEN_COLOUR = (0.2, 1.0, 0.4, 0.3)
LOST_COLOUR = (1.0, 0.2, 0.2, 0.9)
#: Width of the overlay's lines, pixels.
LINE_WIDTH = 1.5

#: What the recorder shows live: {"meshes": [(nodes (m, 2), triangles (t, 3), lost,
#: visible (t,) bool or None), one per doll], ...}; or one doll's "nodes", "triangles",
#: "lost".
live_state: dict = {}
_handle = None


def _draw_lines(coords, colour, shader):
    batch = batch_for_shader(shader, "LINES", {"pos": coords.astype(np.float32)})
    shader.uniform_float("color", colour)
    batch.draw(shader)


def live_meshes(state: dict) -> list:
    """The lines of the live state: (nodes (m, 2), edges (e, 2), colour) to draw.

    Every doll's tracked mesh: the triangles in view in :data:`TRACK_COLOUR`, those out of
    view faint (:data:`HIDDEN_COLOUR`), a lost doll's in :data:`LOST_COLOUR`.
    """
    meshes = state.get("meshes")
    if not meshes:
        meshes = [(state["nodes"], state["triangles"], state.get("lost", False), None)]
    out = []
    for nodes, triangles, lost, visible in meshes:
        tris = np.asarray(triangles)
        if lost or visible is None or np.all(visible):
            out.append((nodes, mesh_edges(tris), LOST_COLOUR if lost else TRACK_COLOUR))
            continue
        seen = np.asarray(visible, bool)
        out.append((nodes, mesh_edges(tris[~seen]), HIDDEN_COLOUR))
        if seen.any():
            out.append((nodes, mesh_edges(tris[seen]), TRACK_COLOUR))
    return out


def take_meshes(scene) -> list:
    """The lines of the last take on the scene's frame, as :func:`live_meshes` gives them.

    Every doll whose blob keeps a take of the scene's last take's name with a row on the
    current frame; empty when none has (no take, or a frame outside it).
    """
    s = scene.voodoo
    if not s.last_take:
        return []
    meshes = []
    for _, doll in doll_settings(s):
        stored = shown_take(doll.blob, s.last_take)
        if stored is None:
            continue
        rows = np.flatnonzero(stored.frames == scene.frame_current)
        if not len(rows):
            continue
        take, row = stored.take, int(rows[-1])
        meshes.append((take.vertices[row], take.triangles, bool(take.lost[row]), take.visible[row]))
    return live_meshes({"meshes": meshes}) if meshes else []


def draw_overlay():
    """The draw handler: the outline, then the live meshes, the last take's or the rest mesh."""
    context = bpy.context
    space = context.space_data
    scene = context.scene
    settings = getattr(scene, "voodoo", None)
    if settings is None or space is None or space.clip is None:
        return
    height = space.clip.size[1]
    v2r = context.region.view2d.view_to_region
    # Wide lines need the polyline shader (drawing them with UNIFORM_COLOR is deprecated).
    shader = gpu.shader.from_builtin("POLYLINE_UNIFORM_COLOR")
    shader.bind()
    shader.uniform_float("viewportSize", gpu.state.viewport_get()[2:])
    shader.uniform_float("lineWidth", LINE_WIDTH)
    gpu.state.blend_set("ALPHA")
    if len(settings.contour) >= 2:
        pts = np.array([p.co for p in settings.contour])
        reg = pixels_to_region(pts, height, v2r)
        seg = np.stack([reg, np.roll(reg, -1, axis=0)], axis=1).reshape(-1, 2)
        _draw_lines(seg, OUTLINE_COLOUR, shader)
    lines = []
    if live_state:
        lines = live_meshes(live_state)
    else:
        try:
            lines = take_meshes(scene)
        except Exception:  # noqa: BLE001 - drawing must never raise
            lines = []
    if not lines and not live_state and is_blob(settings.blob):
        try:
            blob = stored_blob(settings.blob)
            lines = [(blob.vertices, mesh_edges(blob.triangles), MESH_COLOUR)]
        except Exception:  # noqa: BLE001 - drawing must never raise
            lines = []
    for nodes, edges, colour in lines:
        reg = pixels_to_region(np.asarray(nodes), height, v2r)
        _draw_lines(reg[edges.ravel()], colour, shader)
    gpu.state.blend_set("NONE")


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
