import bpy

from ...voodoo_addon.errors import VoodooError
from ..animation import attention_message
from ..apply import apply_take
from .common import needs, reports_errors, settings


class VOODOO_OT_apply_take(bpy.types.Operator):
    """Write a take onto the target as shape keys and transform keys in the take's action"""

    bl_idname = "voodoo.apply_take"
    bl_label = "Apply Take"
    bl_options = {"REGISTER", "UNDO"}

    take: bpy.props.StringProperty(name="Take", description="Take to apply (default: the last)")
    selected: bpy.props.BoolProperty(name="Selected", description="Apply to the selected meshes")
    new_layer: bpy.props.BoolProperty(
        name="New Layer",
        description="Keep the take's earlier apply on the NLA and write a new action over it "
        "(default: update the take's action in place)",
    )

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "blob", "take")

    @reports_errors
    def execute(self, context):
        s = settings(context)
        take = self.take or s.last_take
        if self.selected:
            chosen = list(context.selected_objects)
            targets = [o for o in chosen if o.type == "MESH"]
            for other in chosen:
                if other.type != "MESH":
                    self.report({"INFO"}, f"{other.name!r} is not a mesh; skipped.")
            if not targets:
                raise VoodooError("No mesh is selected: select the meshes to animate.")
        elif s.target is None:
            raise VoodooError("No target: pick a mesh object to animate.")
        else:
            targets = [s.target]
        for obj in targets:
            doll = s.dolls[s.shown_doll].name if len(s.dolls) > 1 else None
            out = apply_take(context.scene, obj, s.blob, take, new_layer=self.new_layer, doll=doll)
            how = "updated in place" if out["in_place"] else "applied"
            self.report(
                {"INFO"}, f"{obj.name}: take {take!r} {how} as action {out['action'].name!r}"
            )
            if out["lost"]:
                self.report({"WARNING"}, f"{len(out['lost'])} lost frame(s) not keyed.")
            note = attention_message(out["attention"])
            if note:
                self.report({"WARNING"}, note)
        return {"FINISHED"}


classes = (VOODOO_OT_apply_take,)
