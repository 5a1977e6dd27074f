"""Mask coordinates against Blender's own rasterisation, and the overlay's coordinates."""

import bpy
import cv2
import numpy as np
import pytest


def _render_mask(mask, size, path):
    """Rasterise a mask with the compositor (Mask node) at the clip's size."""
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.engine = "BLENDER_WORKBENCH"
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    tree = bpy.data.node_groups.new("Raster", "CompositorNodeTree")
    tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
    node = tree.nodes.new("CompositorNodeMask")
    node.mask = mask
    out = tree.nodes.new("NodeGroupOutput")
    tree.links.new(node.outputs[0], out.inputs[0])
    scene.compositing_node_group = tree
    scene.render.filepath = str(path)
    scene.render.image_settings.file_format = "PNG"
    bpy.ops.render.render(write_still=True)
    return cv2.imread(str(path), cv2.IMREAD_GRAYSCALE) > 127


@pytest.mark.parametrize("size", [(320, 240), (240, 320)])
def test_mask_outline_matches_blenders_raster(ctx, sub, size, tmp_path):
    pixels, clips = sub("operators.pixels"), sub("operators.clips")
    w, h = size
    # a curved blob with smooth (AUTO) handles, off-centre
    t = np.linspace(0, 2 * np.pi, 7, endpoint=False)
    r = 0.28 * min(w, h) * (1 + 0.25 * np.cos(3 * t))
    px = np.column_stack([0.55 * w + r * np.cos(t), 0.45 * h + 0.8 * r * np.sin(t)])
    co = pixels.pixels_to_mask(px, size)
    mask = bpy.data.masks.new("Curvy")
    spline = mask.layers.new(name="L").splines.new()
    spline.points.add(len(co) - 1)
    for p, (x, y) in zip(spline.points, co, strict=True):
        p.co = (x, y)
        p.handle_type = "AUTO"
    spline.use_cyclic = True
    mask.layers[0].splines[0].points[0].select_control_point = True
    bpy.context.view_layer.update()
    truth = _render_mask(mask, size, tmp_path / "mask.png")
    poly = clips.outline_from_mask(mask, size)
    ours = np.zeros((h, w), np.uint8)
    cv2.fillPoly(ours, [np.round(poly * 16).astype(np.int32)], 1, cv2.LINE_8, 4)
    ours = ours.astype(bool)
    iou = (ours & truth).sum() / (ours | truth).sum()
    assert iou > 0.98
    assert abs(ours.sum() - truth.sum()) < 0.015 * truth.sum()


def test_mask_pixel_round_trip(ctx, sub):
    pixels = sub("operators.pixels")
    px = np.random.default_rng(0).uniform(0, 300, (50, 2))
    for size in ((320, 240), (240, 320), (640, 640)):
        back = pixels.mask_to_pixels(pixels.pixels_to_mask(px, size), size)
        np.testing.assert_allclose(back, px, atol=1e-9)


def test_overlay_coordinates(ctx, sub):
    pixels = sub("operators.pixels")

    def view_to_region(x, y, clip=True):  # a view zoomed 2x, panned by (10, 20)
        return (10 + 2 * x, 20 + 2 * y)

    pts = np.array([[0.0, 0.0], [99.0, 49.0]])  # top-left and bottom-right pixel centres
    reg = pixels.pixels_to_region(pts, 50, view_to_region)
    np.testing.assert_allclose(reg, [[11.0, 20 + 2 * 49.5], [10 + 2 * 99.5, 21.0]])


def test_overlay_draw_handler_registered(addon, sub):
    drawing = sub("operators.drawing")
    assert drawing._handle is not None


def test_live_overlay_draws_every_doll_and_fades_the_part_out_of_view(ctx, sub):
    """While recording: each doll's mesh is drawn; a doll half out of view has its hidden
    triangles faint and the rest bright; a lost doll is drawn in the lost colour."""
    drawing = sub("operators.drawing")
    nodes = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0], [20.0, 5.0]])
    tris = np.array([[0, 1, 2], [0, 2, 3], [1, 4, 2]])
    half = np.array([True, True, False])
    state = {
        "meshes": [
            (nodes, tris, False, half),
            (nodes + 50, tris, False, np.ones(3, bool)),
            (nodes + 100, tris, True, None),
        ]
    }
    lines = drawing.live_meshes(state)
    colours = [c for _, _, c in lines]
    assert colours == [
        drawing.HIDDEN_COLOUR,
        drawing.TRACK_COLOUR,
        drawing.TRACK_COLOUR,
        drawing.LOST_COLOUR,
    ]
    hidden_edges = {tuple(e) for e in lines[0][1]}
    seen_edges = {tuple(e) for e in lines[1][1]}
    assert hidden_edges == {(1, 2), (1, 4), (2, 4)}  # the far triangle's edges
    assert (1, 4) not in seen_edges and (0, 2) in seen_edges
    assert lines[2][0][0, 0] == 50 and lines[3][0][0, 0] == 100
    # One doll's state, as before several dolls.
    one = drawing.live_meshes({"nodes": nodes, "triangles": tris, "lost": False})
    assert [c for _, _, c in one] == [drawing.TRACK_COLOUR] and len(one[0][1]) == 7


def test_after_a_take_the_overlay_shows_the_take_on_the_scene_frame(prepared, sub):
    """Scrubbing after a take: on a frame of the last take the overlay draws that frame's
    tracked mesh (a part out of view faint, a lost frame in the lost colour); off the take,
    nothing of it (the rest mesh is drawn instead). A take stored again under the same name
    is read again."""
    from dataclasses import replace

    ctx = prepared
    drawing, store = sub("operators.drawing"), sub("operators.storage")
    s = ctx.scene.voodoo
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    stored = store.stored_take(s.blob, s.last_take)
    row = 5
    ctx.scene.frame_set(int(stored.frames[row]))
    lines = drawing.take_meshes(ctx.scene)
    assert [c for _, _, c in lines] == [drawing.TRACK_COLOUR]
    np.testing.assert_array_equal(lines[0][0], stored.take.vertices[row])
    ctx.scene.frame_set(int(stored.frames[-1]) + 5)
    assert drawing.take_meshes(ctx.scene) == []

    # The same take stored again with part of frame 5 out of view and frame 6 lost.
    take = stored.take
    visible, lost = take.visible.copy(), take.lost.copy()
    visible[row, : visible.shape[1] // 2] = False
    lost[row + 1] = True
    store.store_take(
        s.blob, s.last_take, replace(take, visible=visible, lost=lost), stored.frames, None
    )
    ctx.scene.frame_set(int(stored.frames[row]))
    colours = [c for _, _, c in drawing.take_meshes(ctx.scene)]
    assert colours == [drawing.HIDDEN_COLOUR, drawing.TRACK_COLOUR]
    ctx.scene.frame_set(int(stored.frames[row + 1]))
    assert [c for _, _, c in drawing.take_meshes(ctx.scene)] == [drawing.LOST_COLOUR]
    s.last_take = "No such take"
    assert drawing.take_meshes(ctx.scene) == []


def test_the_draw_handler_draws_the_take_into_an_offscreen_buffer(prepared, sub, monkeypatch):
    """The handler itself, on Blender's GPU module (llvmpipe here), into an offscreen buffer
    standing in for the clip editor: after a take it draws the take's mesh on its frames and
    the rest mesh elsewhere, and raises nothing."""
    from types import SimpleNamespace

    import gpu
    from mathutils import Matrix

    ctx = prepared
    drawing = sub("operators.drawing")
    assert sub("operators.gpu_warp").ensure_gpu()  # headless: brings Blender's GPU up
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    clip = bpy.data.movieclips[0]
    w, h = clip.size
    drawn, draw_lines = [], drawing._draw_lines

    def recorded(coords, colour, shader):
        drawn.append(colour)
        draw_lines(coords, colour, shader)

    monkeypatch.setattr(drawing, "_draw_lines", recorded)
    fake = SimpleNamespace(
        context=SimpleNamespace(
            space_data=SimpleNamespace(clip=clip),
            scene=ctx.scene,
            region=SimpleNamespace(
                view2d=SimpleNamespace(view_to_region=lambda x, y, clip: (x, y))
            ),
        )
    )
    monkeypatch.setattr(drawing, "bpy", fake)
    offscreen = gpu.types.GPUOffScreen(w, h)
    try:
        with offscreen.bind(), gpu.matrix.push_pop(), gpu.matrix.push_pop_projection():
            # A pixel-space projection, as Blender sets for a POST_PIXEL handler.
            gpu.matrix.load_identity()
            gpu.matrix.load_projection_matrix(
                Matrix(((2 / w, 0, 0, -1), (0, 2 / h, 0, -1), (0, 0, 1, 0), (0, 0, 0, 1)))
            )
            fb = gpu.state.active_framebuffer_get()
            fb.clear(color=(0.0, 0.0, 0.0, 0.0))
            ctx.scene.frame_set(ctx.scene.frame_start + 2)
            drawing.draw_overlay()
            pixels = np.array(fb.read_color(0, 0, w, h, 4, 0, "FLOAT").to_list())
            on_take = list(drawn)
            drawn.clear()
            ctx.scene.frame_set(ctx.scene.frame_end + 50)
            drawing.draw_overlay()
    finally:
        offscreen.free()
    assert drawing.TRACK_COLOUR in on_take and drawing.MESH_COLOUR not in on_take
    assert drawing.MESH_COLOUR in drawn and drawing.TRACK_COLOUR not in drawn
    # The lines are really drawn: green-dominant pixels where the take's mesh lies.
    green = (pixels[..., 1] > 0.5) & (pixels[..., 0] < 0.5)
    assert green.sum() > 100
