import bpy

from ...voodoo_addon.errors import VoodooError
from ..recorder import interrupted_takes
from ..storage import recover_take
from .common import settings


class VOODOO_OT_recover_takes(bpy.types.Operator):
    """Store the takes that an interrupted recording (Blender closed or crashed) left on disk"""

    bl_idname = "voodoo.recover_takes"
    bl_label = "Recover Takes"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        if not interrupted_takes():
            cls.poll_message_set("No interrupted take of this file's blobs is on disk")
            return False
        return True

    def execute(self, context):
        names = []
        for path, blob_mesh in interrupted_takes():
            try:
                names.append(recover_take(path, blob_mesh))
            except VoodooError as exc:
                self.report({"WARNING"}, f"{path.name}: {exc}")
        if not names:
            self.report({"ERROR"}, "No take could be recovered.")
            return {"CANCELLED"}
        settings(context).last_take = names[-1]
        self.report({"INFO"}, f"Recovered {len(names)} take(s): {', '.join(names)}.")
        return {"FINISHED"}


classes = (VOODOO_OT_recover_takes,)
