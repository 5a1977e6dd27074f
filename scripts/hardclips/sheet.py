"""The painted sheet of a hard clip: a grid mesh with an unpainted back and rim, and its bends.

Frame 0 shows it flat in the XY plane at the origin, square to the camera above it; the ground
truth is a lattice of its grid vertices (every ``stride``-th along each axis).
"""

import math
from dataclasses import dataclass

import bpy

# isort: split
from blender_scene import grid_index, textured_grid  # scripts/ is on sys.path
from mathutils import Matrix

from hardclips.materials import BACK_COLOUR, paint_material, plain_material

TEXELS = 1024  # texture width; the height follows the sheet's aspect
FOAM_THICKNESS = 0.03


@dataclass
class Sheet:
    """The painted sheet: a grid mesh of ``segments`` cells and its ground-truth lattice."""

    obj: bpy.types.Object
    size: tuple[float, float]
    segments: tuple[int, int]
    stride: int  # keep every stride-th vertex along each axis for the lattice

    def grid_index(self):
        """Vertex index of each grid node, rows top-down in the image: (rows + 1, cols + 1)."""
        return grid_index(self.obj.data, self.size, self.segments)


def add_sheet(texture, size, segments, stride, roughness=0.85, thickness=FOAM_THICKNESS, **kw):
    """The painted sheet, flat in the XY plane at the origin, smooth shaded.

    ``texture(rng, width, height)`` paints it; ``thickness`` > 0 gives it an unpainted back and
    rim (a Solidify modifier, added by ``finish_sheet`` after the deformers).
    """
    rng = kw.pop("rng")
    pixels = texture(rng, TEXELS, round(TEXELS * size[1] / size[0]))
    obj = textured_grid("Sheet", size, segments, paint_material("Paint", pixels, roughness, **kw))
    obj.data.shade_smooth()
    obj["thickness"] = thickness
    return Sheet(obj, size, segments, stride)


def set_sheen(sheet, weight, roughness, tint=None):
    """Give the sheet's paint a sheen (velvety at grazing angles: cloth, fur)."""
    bsdf = sheet.obj.data.materials[0].node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Sheen Weight"].default_value = weight
    bsdf.inputs["Sheen Roughness"].default_value = roughness
    if tint is not None:
        bsdf.inputs["Sheen Tint"].default_value = tint


def finish_sheet(sheet):
    """Solidify the sheet (after its deformers) so that it has a back and a rim."""
    thickness = sheet.obj["thickness"]
    if thickness > 0:
        sheet.obj.data.materials.append(plain_material("Foam", BACK_COLOUR))
        solid = sheet.obj.modifiers.new("Thickness", "SOLIDIFY")
        solid.thickness = thickness
        solid.offset = -1.0  # the painted surface stays where it is; the back is behind it
        solid.material_offset = solid.material_offset_rim = 1
    return sheet


def deform_origin(sheet, location, rotation):
    """An empty parented to the sheet: the space a SimpleDeform modifier works in."""
    empty = bpy.data.objects.new("DeformOrigin", None)
    empty.parent = sheet.obj
    empty.location = location
    empty.rotation_euler = rotation
    bpy.context.scene.collection.objects.link(empty)
    return empty


def bend(sheet, name, origin, limits=(0.0, 1.0)):
    """A SimpleDeform BEND: the origin's local X bends around its local Z (towards local +Y)."""
    modifier = sheet.obj.modifiers.new(name, "SIMPLE_DEFORM")
    modifier.deform_method = "BEND"
    modifier.deform_axis = "Z"
    modifier.origin = origin
    modifier.limits = limits
    modifier.angle = 0.0
    return modifier


# Origin rotations for bend(): local X along world X and local +Y towards the camera (+Z)...
BEND_X_TOWARDS_CAMERA = (math.pi / 2, 0.0, 0.0)
# ...local X along world +Y (up in the image) and local +Y away from the camera (-Z).
BEND_Y_AWAY = Matrix(((0, 0, -1), (1, 0, 0), (0, -1, 0))).to_euler()


def deg(keys):
    return [(t, math.radians(v)) for t, v in keys]
