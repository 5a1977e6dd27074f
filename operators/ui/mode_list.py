import bpy


class VOODOO_UL_modes(bpy.types.UIList):
    """The blob's modes: apply checkbox, readable name, gain"""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index):
        row = layout.row(align=True)
        row.prop(item, "enabled", text="")
        sub = row.row()
        sub.active = item.enabled
        sub.label(text=item.name)
        sub.prop(item, "gain", text="", slider=False, emboss=True)


def draw_mode_list(layout, s) -> None:
    """The mode list with its preset buttons (shared by both editors' panels)."""
    if not len(s.modes):
        layout.label(text="Build a blob to list its modes.", icon="INFO")
        return
    layout.template_list("VOODOO_UL_modes", "", s, "modes", s, "active_mode", rows=6)
    row = layout.row(align=True)
    for preset, text in (("ALL", "All"), ("NONE", "None"), ("BENDING", "Bending Only")):
        row.operator("voodoo.select_modes", text=text).preset = preset


classes = (VOODOO_UL_modes,)
