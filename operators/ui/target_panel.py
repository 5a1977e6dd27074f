import bpy

from .mode_list import draw_mode_list


class VOODOO_PT_target(bpy.types.Panel):
    """The character the takes drive: mapping, modes to apply, smoothing"""

    bl_label = "Voodoo Target"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Voodoo"

    def draw(self, context):
        s = context.scene.voodoo
        layout = self.layout
        layout.prop(s, "target")
        layout.prop(s, "axes", expand=True)
        row = layout.row(align=True)
        row.label(text="Apply")
        row.prop(s, "apply_location", toggle=True)
        row.prop(s, "apply_rotation", toggle=True)
        row.prop(s, "apply_scale", toggle=True)
        draw_mode_list(layout, s)
        col = layout.column(align=True)
        col.operator("voodoo.apply_take", icon="ACTION")
        col.operator("voodoo.apply_take", text="Apply as New Layer", icon="NLA").new_layer = True
        col.operator("voodoo.smooth_take", icon="SMOOTHCURVE")
        if s.last_take:
            layout.label(text=f"Last take: {s.last_take}")


classes = (VOODOO_PT_target,)
