import bpy

from .. import drawing
from ..dolls import remove_doll
from ..recorder import recording_now
from .common import reports_errors, settings


class VOODOO_OT_remove_doll(bpy.types.Operator):
    """Remove the selected doll (its blob, takes and animation stay in the file)"""

    bl_idname = "voodoo.remove_doll"
    bl_label = "Remove Doll"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        if len(settings(context).dolls) < 2:
            cls.poll_message_set("The last doll cannot be removed")
            return False
        return True

    @reports_errors
    def execute(self, context):
        if recording_now():
            self.report({"ERROR"}, "A take is being recorded: stop it before removing a doll")
            return {"CANCELLED"}
        name = remove_doll(settings(context))
        drawing.tag_redraw(context)
        self.report({"INFO"}, f"Doll {name!r} removed")
        return {"FINISHED"}


classes = (VOODOO_OT_remove_doll,)
