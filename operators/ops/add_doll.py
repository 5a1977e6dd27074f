import bpy

from .. import drawing
from ..dolls import add_doll
from .common import reports_errors, settings


class VOODOO_OT_add_doll(bpy.types.Operator):
    """Add a doll with its own outline, blob, modes and target (the doll so far is the first)"""

    bl_idname = "voodoo.add_doll"
    bl_label = "Add Doll"
    bl_options = {"REGISTER", "UNDO"}

    name: bpy.props.StringProperty(name="Name", default="Doll")

    @reports_errors
    def execute(self, context):
        name = add_doll(settings(context), self.name)
        drawing.tag_redraw(context)
        self.report({"INFO"}, f"Doll {name!r} added: outline it and build its blob")
        return {"FINISHED"}


classes = (VOODOO_OT_add_doll,)
