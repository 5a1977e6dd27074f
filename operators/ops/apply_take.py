import bpy

from ..voodoo_addon.errors import VoodooError
from .apply import apply_take, attention_message
from .common import reports_errors, settings


class VOODOO_OT_apply_take(bpy.types.Operator):
    """Write a take onto the target as shape keys and transform keys in a new action"""

    bl_idname = "voodoo.apply_take"
    bl_label = "Apply Take"
    bl_options = {"REGISTER", "UNDO"}

    take: bpy.props.StringProperty(name="Take", description="Take to apply (default: the last)")
    selected: bpy.props.BoolProperty(name="Selected", description="Apply to the selected meshes")

    @reports_errors
    def execute(self, context):
        s = settings(context)
        if s.blob is None:
            raise VoodooError("No blob is built yet.")
        take = self.take or s.last_take
        if not take:
            raise VoodooError("No take yet: record one first.")
        targets = list(context.selected_objects) if self.selected else [s.target]
        if not targets or targets == [None]:
            raise VoodooError("No target: pick a mesh object to animate.")
        for obj in targets:
            out = apply_take(context.scene, obj, s.blob, take)
            msg = f"{obj.name}: take {take!r} as action {out['action'].name!r}"
            self.report({"INFO"}, msg)
            if out["lost"]:
                self.report({"WARNING"}, f"{len(out['lost'])} lost frame(s) not keyed.")
            note = attention_message(out["attention"])
            if note:
                self.report({"WARNING"}, note)
        return {"FINISHED"}


classes = (VOODOO_OT_apply_take,)
