import bpy

from ..storage import blob_bytes, blob_meshes, blob_users, remove_blob, take_names


class VOODOO_OT_remove_unused_blobs(bpy.types.Operator):
    """Remove blobs that no scene uses and whose takes drive no object"""

    bl_idname = "voodoo.remove_unused_blobs"
    bl_label = "Remove Unused Blobs"
    bl_options = {"REGISTER", "UNDO"}

    with_takes: bpy.props.BoolProperty(
        name="Also With Takes",
        description="Also remove unused blobs that hold takes (the takes go with them)",
    )

    def execute(self, context):
        removed, freed, kept = 0, 0, 0
        for mesh in blob_meshes():
            if blob_users(mesh):
                continue
            if take_names(mesh) and not self.with_takes:
                kept += 1
                continue
            freed += blob_bytes(mesh)
            remove_blob(mesh)
            removed += 1
        msg = f"Removed {removed} unused blob(s), {freed / 1e6:.1f} MB."
        if kept:
            msg += (
                f" {kept} unused blob(s) hold takes and were kept (Also With Takes removes them)."
            )
        self.report({"INFO"}, msg)
        return {"FINISHED"}


classes = (VOODOO_OT_remove_unused_blobs,)
