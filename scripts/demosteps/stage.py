"""The stage: the characters, the take on both, a camera framing them, the look, the .blend.

The take is tracked onto the flat bunny and applied to the cracker box too; the camera is
pulled back until the characters' whole motion fits; Workbench renders them.
"""

from pathlib import Path

import bpy

# isort: split
import characters  # scripts/ is on sys.path when a script runs
import numpy as np
from blender_scene import frame_size, workbench
from mathutils import Euler, Vector

from demosteps import SAMPLE_CLIP
from demosteps.report import run_operator

TAKE_NAME = "Sample Take"
AXES = "XZ"  # both characters stand in the XZ plane, facing -Y

# Characters side by side: bunny on the left, box on the right (world X of their rest centres).
BUNNY_X = -1.6
BOX_X = 1.9

# Camera: nearly a front view, raised and turned a little so the box shows its depth; it is
# pulled back until the characters' whole motion fits, with this much margin around it.
CAMERA_ELEVATION_DEG = 12.0
CAMERA_AZIMUTH_DEG = 18.0
CAMERA_LENS_MM = 50.0
FRAMING_MARGIN = 1.12
# Render size (wide: the characters stand side by side) and Workbench look.
RENDER_SIZE = (640, 360)
RENDER_AA = "5"
WORLD_COLOUR = (0.045, 0.05, 0.06)
SUN_ROTATION_DEG = (50.0, 10.0, 30.0)


def make_characters(scene):
    """The flat cut-out bunny and the 3D cracker box, side by side in front view."""
    bunny = characters.make_cutout(collection=scene.collection)
    box = characters.make_extruded(collection=scene.collection)
    bunny.location.x = BUNNY_X
    box.location.x = BOX_X
    return bunny, box


def track_and_apply(scene, bunny, box, frames: int | None) -> str:
    """Track the clip onto the bunny, apply the take to the box too; returns the take's name."""
    s = scene.voodoo
    s.axes = AXES
    s.take_name = TAKE_NAME
    s.target = bunny
    run_operator(bpy.ops.voodoo.track_clip, max_frames=frames or 0)
    take = s.last_take
    view_layer = bpy.context.view_layer
    for obj in view_layer.objects:
        obj.select_set(obj == box)
    view_layer.objects.active = box
    run_operator(bpy.ops.voodoo.apply_take, take=take, selected=True)
    return take


def motion_corners(scene, objects) -> np.ndarray:
    """World corners (8, 3) of the box holding ``objects`` in every frame of the scene."""
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        for obj in objects:
            evaluated = obj.evaluated_get(depsgraph)
            mesh = evaluated.to_mesh()
            co = np.empty(3 * len(mesh.vertices))
            mesh.vertices.foreach_get("co", co)
            evaluated.to_mesh_clear()
            matrix = np.array(evaluated.matrix_world)
            world = co.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]
            lo, hi = np.minimum(lo, world.min(axis=0)), np.maximum(hi, world.max(axis=0))
    scene.frame_set(scene.frame_start)
    return np.array([[(lo, hi)[(i >> k) & 1][k] for k in range(3)] for i in range(8)])


def add_camera_and_light(scene, corners: np.ndarray):
    """A camera that frames ``corners`` (8, 3) with a margin, and a sun light."""
    data = bpy.data.cameras.new("Camera")
    data.lens = CAMERA_LENS_MM
    camera = bpy.data.objects.new("Camera", data)
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.rotation_euler = Euler(
        (np.radians(90.0 - CAMERA_ELEVATION_DEG), 0.0, np.radians(CAMERA_AZIMUTH_DEG))
    )
    centre = corners.mean(axis=0)
    padded = centre + FRAMING_MARGIN * (corners - centre)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    location, _ = camera.camera_fit_coords(depsgraph, padded.ravel().tolist())
    camera.location = location
    data.clip_end = 10.0 * (Vector(location) - Vector(centre)).length

    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", type="SUN"))
    sun.rotation_euler = Euler(np.radians(SUN_ROTATION_DEG).tolist())
    scene.collection.objects.link(sun)
    return camera


def setup_render(scene) -> None:
    """Workbench: material colours, studio light, shadows, cavity, outlines, a dark world."""
    workbench(scene, "STUDIO", "MATERIAL")
    frame_size(scene, RENDER_SIZE)  # and the Standard view: the materials' colours, unfiltered
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = "//render/"  # where an animation render from the file goes
    scene.display.render_aa = RENDER_AA
    shading = scene.display.shading
    shading.show_shadows = True
    shading.show_cavity = True
    shading.show_object_outline = True
    world = bpy.data.worlds.new("World")
    world.color = WORLD_COLOUR
    scene.world = world


def save_blend(path: Path, clip) -> None:
    """Save the scene, with the clip's path relative to the file where that is possible."""
    path.parent.mkdir(parents=True, exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=str(path), check_existing=False)
    try:
        clip.filepath = bpy.path.relpath(str(SAMPLE_CLIP))
    except ValueError:  # another drive (Windows): keep the absolute path
        return
    bpy.ops.wm.save_mainfile()
