"""The sample take's scene: a painted foam slab moved, turned, bent and squeezed before a camera.

An orthographic camera looks straight down at the slab, which lies in the XY plane on a darker
backdrop; the motion is a schedule in seconds keyed on the slab and on two SimpleDeform
modifiers. Rendered with Workbench (flat texture colours) into an H.264 MP4.
"""

import math

import bpy

# isort: split
from blender_scene import (  # scripts/ is on sys.path when a script runs
    camera_above,
    frame_size,
    h264_output,
    keyframe,
    packed_image,
    textured_grid,
    textured_material,
    workbench,
)
from foam_paint import backdrop_texture, painted_foam_texture

WIDTH, HEIGHT = 640, 480
FPS = 30
SEED = 1998

# Orthographic camera looking down -Z: ORTHO_SCALE world units span the frame width.
ORTHO_SCALE = 8.0
CAMERA_HEIGHT = 10.0

# The slab lies in the XY plane at the origin; SLAB_SIZE[0] is 40% of the frame width.
SLAB_SIZE = (3.2, 2.2)
SLAB_SEGMENTS = (64, 44)
SLAB_TEXTURE_SIZE = (512, 352)

# The backdrop: a darker, faintly mottled plane behind the slab.
BACKDROP_SIZE = (10.0, 8.0)
BACKDROP_DEPTH = -0.5
BACKDROP_TEXTURE_SIZE = (320, 256)

# Motion schedule: channel -> [(time in seconds, value)]. Bezier-eased between keys (Blender's
# default auto-clamped handles): smooth, and flat at every hold and turning point. Locations in
# world units (1 unit = 80 px), turns and bends in degrees, taper as the modifier's factor.
MOTION = {
    "x": [(0.0, 0.0), (0.3, 0.0), (1.3, 0.6), (2.5, -0.5), (3.7, 0.3), (4.7, -0.1)],
    "y": [(0.0, 0.0), (0.3, 0.0), (1.1, 0.3), (2.2, -0.3), (3.4, 0.2), (4.6, 0.0)],
    "turn": [
        (0.0, 0.0),
        (0.5, 0.0),
        (1.5, 25.0),
        (2.2, 25.0),
        (3.6, -30.0),
        (4.2, -15.0),
        (5.0, 15.0),
    ],
    "scale_x": [
        (0.0, 1.0),
        (1.0, 1.0),
        (1.8, 1.2),
        (2.6, 1.0),
        (3.4, 0.82),
        (4.2, 0.9),
        (5.0, 1.0),
    ],
    "scale_y": [
        (0.0, 1.0),
        (1.0, 1.0),
        (1.8, 1.2),
        (2.6, 1.0),
        (3.4, 1.12),
        (4.2, 0.9),
        (5.0, 1.0),
    ],
    "bend": [
        (0.0, 0.0),
        (0.6, 0.0),
        (1.5, 55.0),
        (2.9, -55.0),
        (3.6, 0.0),
        (4.3, 40.0),
        (5.0, 0.0),
    ],
    "taper": [(0.0, 0.0), (2.5, 0.0), (3.2, 0.16), (3.9, -0.14), (4.6, 0.0)],
}


def add_deformers(slab):
    """SimpleDeform modifiers: a taper along X, then an in-plane bend about the Z axis."""
    taper = slab.modifiers.new("Taper", "SIMPLE_DEFORM")
    taper.deform_method = "TAPER"
    taper.deform_axis = "X"
    bend = slab.modifiers.new("Bend", "SIMPLE_DEFORM")
    bend.deform_method = "BEND"
    bend.deform_axis = "Z"


def motion_channels():
    """Map each MOTION channel to (data path, array index, conversion to Blender units)."""
    return {
        "x": ("location", 0, float),
        "y": ("location", 1, float),
        "turn": ("rotation_euler", 2, math.radians),
        "scale_x": ("scale", 0, float),
        "scale_y": ("scale", 1, float),
        "bend": ('modifiers["Bend"].angle', 0, math.radians),
        "taper": ('modifiers["Taper"].factor', 0, float),
    }


def animate(slab):
    """Keyframe the MOTION schedule on the slab (scene frame 1 is time 0)."""
    channels = {
        (data_path, index): [(seconds, convert(value)) for seconds, value in MOTION[channel]]
        for channel, (data_path, index, convert) in motion_channels().items()
    }
    keyframe(slab, channels, FPS, action_name="SlabMotion")


def build_scene(rng):
    """Reset Blender and build backdrop, animated slab and camera. Returns the slab object."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    foam = packed_image("PaintedFoam", painted_foam_texture(rng, *SLAB_TEXTURE_SIZE))
    backdrop = packed_image("Backdrop", backdrop_texture(rng, *BACKDROP_TEXTURE_SIZE))
    textured_grid(
        "Backdrop",
        BACKDROP_SIZE,
        (1, 1),
        textured_material("Backdrop", backdrop),
        depth=BACKDROP_DEPTH,
    )
    slab = textured_grid(
        "FoamSlab", SLAB_SIZE, SLAB_SEGMENTS, textured_material("PaintedFoam", foam)
    )
    add_deformers(slab)
    animate(slab)
    camera_above(CAMERA_HEIGHT, type="ORTHO", ortho_scale=ORTHO_SCALE)
    return slab


def configure_render(scene, n_frames, video_path):
    """Workbench, flat texture colours, Standard view, H.264 MP4 without B-frames."""
    workbench(scene, "FLAT", "TEXTURE")
    frame_size(scene, (WIDTH, HEIGHT), FPS)
    scene.frame_start, scene.frame_end = 1, n_frames
    h264_output(scene, video_path, FPS)
