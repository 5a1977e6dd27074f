"""Blender scene building blocks shared by the scripts that render and run clips.

``make_sample.py`` (the sample take) and ``render_hard_clips.py`` (the hard clips) build their
scenes from these: render size and Workbench settings, H.264 output through Blender's FFmpeg,
packed procedural textures on UV-mapped grids, a camera above the origin looking down, motion
keyed in seconds, and the ground truth's pixel projection, grid lattice and outline shape.
``demo.py`` takes the render settings. Pixel coordinates are OpenCV's: origin at the centre of
the top-left pixel, x right, y down.
"""

import math

import bpy  # first: importing bpy makes bmesh and bpy_extras importable

# isort: split
import bmesh
import numpy as np
from bpy_extras import anim_utils
from bpy_extras.object_utils import world_to_camera_view
from characters import resample_closed  # scripts/ is on sys.path when a script runs

ARC_SAMPLES = 32  # per rounded corner of an outline, before even resampling


# --- render settings ------------------------------------------------------------------------


def frame_size(scene, size, fps=None):
    """Render ``size`` (width, height) pixels at 100 %, colours unfiltered (Standard view).

    ``fps``, when given, sets the frame rate (a whole number of frames per second).
    """
    render = scene.render
    render.resolution_x, render.resolution_y = size
    render.resolution_percentage = 100
    if fps is not None:
        render.fps, render.fps_base = fps, 1.0
    scene.view_settings.view_transform = "Standard"


def workbench(scene, light, color_type):
    """Render with Workbench: ``light`` ("FLAT", "STUDIO"), ``color_type`` ("TEXTURE", ...)."""
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.light = light
    scene.display.shading.color_type = color_type


def h264_output(scene, video_path, fps, crf="MEDIUM"):
    """Write the animation as an H.264 MP4 to ``video_path``: one key frame a second, no B-frames.

    ``crf`` is the FFmpeg constant rate factor (Blender's names: "MEDIUM", "LOW", ...).
    """
    render = scene.render
    settings = render.image_settings
    settings.media_type = "VIDEO"
    settings.file_format = "FFMPEG"
    settings.color_mode = "RGB"
    ffmpeg = render.ffmpeg
    ffmpeg.format, ffmpeg.codec = "MPEG4", "H264"
    ffmpeg.constant_rate_factor = crf
    ffmpeg.ffmpeg_preset = "GOOD"
    ffmpeg.gopsize = fps
    ffmpeg.use_max_b_frames, ffmpeg.max_b_frames = True, 0
    render.use_file_extension = False
    render.filepath = str(video_path)


# --- textured geometry ----------------------------------------------------------------------


def packed_image(name, pixels):
    """A packed Blender image holding ``pixels`` (H, W, 3) float in [0, 1], rows top-down."""
    height, width = pixels.shape[:2]
    image = bpy.data.images.new(name, width, height, alpha=False)
    rgba = np.ones((height, width, 4), dtype=np.float32)
    rgba[..., :3] = pixels[::-1]  # Blender stores rows bottom-up
    image.pixels.foreach_set(rgba.ravel())
    image.pack()
    return image


def textured_material(name, image):
    """A material whose base colour is ``image`` (what Workbench shows in TEXTURE mode)."""
    material = bpy.data.materials.new(name)
    nodes = material.node_tree.nodes
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    nodes.active = texture
    bsdf = nodes["Principled BSDF"]
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    return material


def textured_grid(name, size, segments, material, depth=0.0):
    """A subdivided rectangle in the XY plane at height ``depth``, UV-mapped over [0, 1]^2."""
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")  # create_grid fills the UV layer that exists
    bmesh.ops.create_grid(
        bm, x_segments=segments[0], y_segments=segments[1], size=0.5, calc_uvs=True
    )
    for vert in bm.verts:
        vert.co = (vert.co.x * size[0], vert.co.y * size[1], depth)
    bm.to_mesh(mesh)
    bm.free()
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def grid_index(mesh, size, segments):
    """Vertex index of each node of a ``textured_grid`` mesh, rows top-down in the image.

    Returns
    -------
    (segments[1] + 1, segments[0] + 1) int
    """
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    col = np.round((co[:, 0] / size[0] + 0.5) * segments[0]).astype(int)
    row = np.round((0.5 - co[:, 1] / size[1]) * segments[1]).astype(int)
    index = np.full((segments[1] + 1, segments[0] + 1), -1)
    index[row, col] = np.arange(len(co))
    assert (index >= 0).all(), "the mesh is not a regular grid"
    return index


# --- camera and motion ----------------------------------------------------------------------


def camera_above(height, **settings):
    """The scene's camera at (0, 0, ``height``) looking down -Z: image x = X, image y = -Y.

    ``settings`` are set on the camera data in order (``type``, ``lens``, ``ortho_scale``, ...).
    """
    camera = bpy.data.cameras.new("Camera")
    for key, value in settings.items():
        setattr(camera, key, value)
    obj = bpy.data.objects.new("Camera", camera)
    obj.location = (0.0, 0.0, height)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.scene.camera = obj
    return obj


def keyframe(target, channels, fps, action_name=None):
    """Keyframe ``{(data path, index): [(seconds, value), ...]}`` on ``target``.

    Scene frame 1 is time 0; the keys are Bezier-eased (Blender's default auto-clamped handles).
    The action is ``action_name`` (default: the target's name + "Motion").
    """
    action = bpy.data.actions.new(action_name or f"{target.name}Motion")
    slot = action.slots.new(id_type=target.id_type, name=target.name)
    target.animation_data_create()
    target.animation_data.action = action
    target.animation_data.action_slot = slot
    channelbag = anim_utils.action_ensure_channelbag_for_slot(action, slot)
    for (data_path, index), keys in channels.items():
        fcurve = channelbag.fcurves.new(data_path, index=index)
        for seconds, value in keys:
            fcurve.keyframe_points.insert(1 + seconds * fps, value)
        fcurve.update()
    return action


# --- pixels ---------------------------------------------------------------------------------


def pixel_position(scene, camera, point):
    """Where the world ``point`` (a Vector) is in the rendered image: ``(x, y, depth)``.

    ``x, y`` are OpenCV pixel coordinates at the scene's render size; ``depth`` is the distance
    in front of the camera along its view axis (> 0 in front of it).
    """
    ndc = world_to_camera_view(scene, camera, point)  # x right, y up, in [0, 1]
    width, height = scene.render.resolution_x, scene.render.resolution_y
    return ndc.x * width - 0.5, (1.0 - ndc.y) * height - 0.5, ndc.z


def rounded_rectangle(centre, half_size, radius, spacing):
    """Points evenly about ``spacing`` apart around a rounded rectangle.

    The outline runs clockwise on screen (angle increasing with y down); its straight sides are
    the gaps between the four corner arcs.

    Returns
    -------
    (n_points, 2) float64
    """
    angles = (np.arange(4 * ARC_SAMPLES) + 0.5) * (math.pi / 2 / ARC_SAMPLES)
    directions = np.column_stack([np.cos(angles), np.sin(angles)])  # (4 * ARC_SAMPLES, 2)
    arc_centres = (np.asarray(half_size) - radius) * np.sign(directions)
    return np.asarray(centre) + resample_closed(arc_centres + radius * directions, spacing)
