import bpy

from ..apply import refresh_modes
from .common import needs, reports_errors, settings

PRESETS = [
    ("ALL", "All", "Apply every mode and the rigid motion"),
    ("NONE", "None", "Apply no mode (rigid motion only)"),
    ("BENDING", "Bending Only", "Bends only: no other mode, no translation, rotation or scale"),
    ("INVERT", "Invert", "Swap applied and muted modes"),
]


class VOODOO_OT_select_modes(bpy.types.Operator):
    """Pick which modes drive the target (curves are muted, not deleted: no re-tracking)"""

    bl_idname = "voodoo.select_modes"
    bl_label = "Select Modes"
    bl_options = {"REGISTER", "UNDO"}

    preset: bpy.props.EnumProperty(name="Preset", items=PRESETS, default="ALL")

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "modes")

    @reports_errors
    def execute(self, context):
        s = settings(context)
        for m in s.modes:
            if self.preset == "ALL":
                m["enabled"] = True
            elif self.preset == "NONE":
                m["enabled"] = False
            elif self.preset == "INVERT":
                m["enabled"] = not m.enabled
            else:
                m["enabled"] = "bend" in m.name
        if self.preset in {"BENDING", "ALL"}:
            rigid = self.preset == "ALL"
            s["apply_location"] = s["apply_rotation"] = s["apply_scale"] = rigid
        refresh_modes(context.scene)  # once, not per toggle
        return {"FINISHED"}


classes = (VOODOO_OT_select_modes,)
