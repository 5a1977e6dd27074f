"""Lamps and materials of the hard clips: studio lights, the painted front, the foam behind."""

import bpy

# isort: split
from blender_scene import packed_image, textured_material  # scripts/ is on sys.path
from mathutils import Vector

BACK_COLOUR = (0.80, 0.76, 0.66, 1.0)  # unpainted foam: the sheet's back and rim


def add_light(name, kind, location, energy, size, target=(0.0, 0.0, 0.0), **settings):
    """A lamp at ``location`` aimed at ``target`` (``size``: area side or lamp radius)."""
    light = bpy.data.lights.new(name, kind)
    light.energy = energy
    if kind == "AREA":
        light.size = size
    else:
        light.shadow_soft_size = size
    for key, value in settings.items():
        setattr(light, key, value)
    obj = bpy.data.objects.new(name, light)
    obj.location = location
    obj.rotation_euler = (Vector(target) - Vector(location)).to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.collection.objects.link(obj)
    return obj


def studio_lights(key=700.0, fill=120.0):
    """A soft key from the upper left and a weaker fill from the lower right."""
    add_light("Key", "AREA", (-3.5, 3.0, 6.0), key, 2.5)
    add_light("Fill", "AREA", (4.0, -3.0, 4.0), fill, 3.0)


def paint_material(name, pixels, roughness, specular=0.3, coat=0.0):
    """A Principled material: ``pixels`` on the front, unpainted foam behind."""
    material = textured_material(name, packed_image(name, pixels))
    nodes, links = material.node_tree.nodes, material.node_tree.links
    bsdf = nodes["Principled BSDF"]
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Specular IOR Level"].default_value = specular
    bsdf.inputs["Coat Weight"].default_value = coat
    texture = nodes.active
    backfacing = nodes.new("ShaderNodeNewGeometry")
    mix = nodes.new("ShaderNodeMix")
    mix.data_type = "RGBA"
    socket = {s.identifier: s for s in (*mix.inputs, *mix.outputs)}  # names repeat, ids do not
    links.new(backfacing.outputs["Backfacing"], socket["Factor_Float"])
    links.new(texture.outputs["Color"], socket["A_Color"])
    socket["B_Color"].default_value = BACK_COLOUR
    links.new(socket["Result_Color"], bsdf.inputs["Base Color"])
    return material


def plain_material(name, colour, roughness=0.9):
    material = bpy.data.materials.new(name)
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = colour
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Specular IOR Level"].default_value = 0.2
    return material
