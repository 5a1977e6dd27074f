"""Settings saved with the .blend: ``scene.voodoo``, its mode list and its dolls."""

import bpy
from bpy.props import (
    BoolProperty,
    CollectionProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

from ..voodoo_addon.takes.rig import MAX_GAIN


def _modes_changed(self, context):
    from .apply import refresh_modes
    from .dolls import switching

    if not switching():
        refresh_modes(context.scene)


def _doll_chosen(self, context):
    from .dolls import show_doll

    show_doll(self, self.active_doll)


def _is_mesh(self, obj):
    return obj.type == "MESH"


class VOODOO_PG_point(bpy.types.PropertyGroup):
    """One outline point, pixel coordinates of the capture frame (x right, y down)."""

    co: FloatVectorProperty(name="Point", size=2)


class VOODOO_PG_mode(bpy.types.PropertyGroup):
    """One elastic mode of the blob (its ``name`` is the readable label)."""

    index: IntProperty(name="Index", description="Position of the mode in the blob")
    enabled: BoolProperty(
        name="Apply",
        description="Let this mode deform the target",
        default=True,
        update=_modes_changed,
    )
    gain: FloatProperty(
        name="Gain",
        description="Scale this mode's effect on the target",
        default=1.0,
        min=-MAX_GAIN,
        max=MAX_GAIN,
        soft_min=-3.0,
        soft_max=3.0,
        update=_modes_changed,
    )
    stiffness: FloatProperty(name="Stiffness", description="Modal stiffness (w^2)")


_AXES = [
    ("XZ", "XZ", "Front view: doll right is +X, doll up is +Z"),
    ("XY", "XY", "Top view: doll right is +X, doll up is +Y"),
    ("YZ", "YZ", "Side view: doll right is +Y, doll up is +Z"),
]


class VOODOO_PG_doll(bpy.types.PropertyGroup):
    """One doll of the scene (``name`` is its name): what the scene's own outline, blob,
    modes, target and apply settings hold while it is the doll shown (see ``dolls.py``).
    """

    contour: CollectionProperty(type=VOODOO_PG_point)
    blob: PointerProperty(name="Blob", type=bpy.types.Mesh)
    modes: CollectionProperty(type=VOODOO_PG_mode)
    active_mode: IntProperty(name="Active Mode")
    target: PointerProperty(name="Target", type=bpy.types.Object, poll=_is_mesh)
    axes: EnumProperty(name="Axes", items=_AXES, default="XZ")
    apply_location: BoolProperty(name="Location", default=True)
    apply_rotation: BoolProperty(name="Rotation", default=True)
    apply_scale: BoolProperty(name="Scale", default=True)


class VOODOO_PG_settings(bpy.types.PropertyGroup):
    """Everything the Voodoo panels show, stored per scene."""

    # Source and capture
    source: EnumProperty(
        name="Source",
        items=[
            ("CLIP", "Movie Clip", "Track the active movie clip"),
            ("CAMERA", "Camera", "Track a live camera; the footage is saved as a clip"),
        ],
        default="CLIP",
    )
    camera_index: IntProperty(name="Camera", description="Camera device number", min=0, max=63)
    camera_seconds: FloatProperty(
        name="Length",
        description="Longest live recording, seconds",
        default=10.0,
        min=0.5,
        max=600.0,
    )
    capture_image: PointerProperty(name="Capture", type=bpy.types.Image)
    capture_index: IntProperty(name="Capture Frame", description="Source frame of the capture")

    # Outline
    contour: CollectionProperty(type=VOODOO_PG_point)

    # Blob
    blob: PointerProperty(name="Blob", type=bpy.types.Mesh)
    n_modes: IntProperty(name="Modes", default=20, min=1, max=60)
    min_angle: FloatProperty(
        name="Min Angle",
        default=25.0,
        min=5.0,
        max=33.0,
        description="Smallest triangle angle, degrees",
    )
    max_area: FloatProperty(
        name="Max Area",
        default=0.0,
        min=0.0,
        description="Largest triangle in square pixels (0: about 80 triangles)",
    )
    poly_degree: IntProperty(
        name="Polynomial Degree",
        default=3,
        min=0,
        max=3,
        description="Modes from polynomial fields up to this degree first (0: plain FE modes)",
    )
    modes: CollectionProperty(type=VOODOO_PG_mode)
    active_mode: IntProperty(name="Active Mode")

    # Recording
    take_name: StringProperty(name="Take", default="Take")
    osc_send: BoolProperty(
        name="Stream over OSC",
        description="Send every tracked frame to another program while recording (OSC over UDP)",
        default=False,
    )
    osc_target: StringProperty(
        name="OSC Target",
        description="HOST:PORT of the program that receives the stream",
        default="127.0.0.1:9000",
    )
    osc_bundle: BoolProperty(
        name="Bundles",
        description="One OSC bundle per frame (off: its messages one by one)",
        default=True,
    )
    warp: EnumProperty(
        name="Warp",
        items=[
            ("AUTO", "Auto", "GPU on a hardware GPU, CPU on software rendering"),
            ("GPU", "GPU", "Warp with the gpu module (offscreen draw)"),
            ("CPU", "CPU", "Warp with OpenCV"),
        ],
        default="AUTO",
    )
    freeze_translation: BoolProperty(name="Translation", description="Track without translation")
    freeze_rotation: BoolProperty(name="Rotation", description="Track without rotation")
    freeze_scale: BoolProperty(name="Scale", description="Track without scale")
    last_take: StringProperty(name="Last Take")

    # Target and apply
    target: PointerProperty(name="Target", type=bpy.types.Object, poll=_is_mesh)
    axes: EnumProperty(
        name="Axes",
        description="Plane of the target the doll is laid onto",
        items=_AXES,
        default="XZ",
    )
    apply_location: BoolProperty(name="Location", default=True, update=_modes_changed)
    apply_rotation: BoolProperty(name="Rotation", default=True, update=_modes_changed)
    apply_scale: BoolProperty(name="Scale", default=True, update=_modes_changed)

    # Dolls: with none listed, the fields above are the scene's one doll
    dolls: CollectionProperty(type=VOODOO_PG_doll)
    active_doll: IntProperty(name="Doll", update=_doll_chosen)
    #: The doll whose settings the fields above hold (set by ``dolls.show_doll``).
    shown_doll: IntProperty(options={"HIDDEN"})


classes = (VOODOO_PG_point, VOODOO_PG_mode, VOODOO_PG_doll, VOODOO_PG_settings)


def register():
    bpy.types.Scene.voodoo = PointerProperty(type=VOODOO_PG_settings)


def unregister():
    del bpy.types.Scene.voodoo
