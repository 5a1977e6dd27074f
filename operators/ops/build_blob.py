import bpy

from ...voodoo_addon.blob.build import BlobOptions, build_blob
from .. import drawing
from ..pixels import rgb_from_image
from ..storage import blob_users, remove_blob, store_blob, take_names
from .common import needs, reports_errors, settings


class VOODOO_OT_build_blob(bpy.types.Operator):
    """Build the active blob (mesh, texture, named modes) from the capture and the outline"""

    bl_idname = "voodoo.build_blob"
    bl_label = "Build Blob"
    bl_options = {"REGISTER", "UNDO"}

    name: bpy.props.StringProperty(name="Name", default="Doll")

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "capture", "outline")

    @reports_errors
    def execute(self, context):
        s = settings(context)
        frame = rgb_from_image(s.capture_image)
        options = BlobOptions(
            n_modes=s.n_modes,
            min_angle=s.min_angle,
            max_area=s.max_area or None,
            poly_degree=s.poly_degree,
        )
        blob = build_blob(frame, [tuple(p.co) for p in s.contour], options)
        old = s.blob
        mesh = store_blob(self.name, blob)
        s.blob = mesh
        if old is not None and not take_names(old) and not blob_users(old):
            remove_blob(old)  # a blob nothing was recorded with is only dead weight
            mesh.name = self.name
        s.modes.clear()
        for j, label in enumerate(blob.labels):
            item = s.modes.add()
            item.name = str(label)
            item.index = j
            item.stiffness = float(blob.mode_stiffness[j])
        s.active_mode = 0
        for w in blob.warnings:
            self.report({"WARNING"}, w)
        self.report(
            {"INFO"},
            f"Blob {mesh.name!r}: {blob.n_nodes} nodes, {len(blob.triangles)} triangles, "
            f"{blob.n_pixels} pixels, {blob.n_modes} modes.",
        )
        drawing.tag_redraw(context)
        return {"FINISHED"}


classes = (VOODOO_OT_build_blob,)
