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
