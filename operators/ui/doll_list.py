import bpy


class VOODOO_UL_dolls(bpy.types.UIList):
    """The scene's dolls: name (double-click to rename), blob and target"""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index):
        s = context.scene.voodoo
        shown = index == s.shown_doll
        blob = s.blob if shown else item.blob
        target = s.target if shown else item.target
        row = layout.row(align=True)
        row.prop(item, "name", text="", emboss=False, icon="OUTLINER_OB_ARMATURE")
        row.label(text=blob.name if blob is not None else "no blob", icon="MESH_GRID")
        row.label(text=target.name if target is not None else "no target", icon="OBJECT_DATA")


classes = (VOODOO_UL_dolls,)
