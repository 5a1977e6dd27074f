import bpy

from ..voodoo_addon.blob.build import BlobOptions, build_blob
from ..voodoo_addon.errors import VoodooError
from . import overlay
from .common import reports_errors, settings
from .frames import rgb_from_image
from .store import store_blob


class VOODOO_OT_build_blob(bpy.types.Operator):
    """Build the active blob (mesh, texture, named modes) from the capture and the outline"""

    bl_idname = "voodoo.build_blob"
    bl_label = "Build Blob"
    bl_options = {"REGISTER", "UNDO"}

    name: bpy.props.StringProperty(name="Name", default="Doll")

    @reports_errors
    def execute(self, context):
        s = settings(context)
        if s.capture_image is None:
            raise VoodooError("Capture a frame first.")
        if len(s.contour) < 3:
            raise VoodooError("Outline the object first (mask, automatic, or sketch).")
        frame = rgb_from_image(s.capture_image)
        options = BlobOptions(
            n_modes=s.n_modes,
            min_angle=s.min_angle,
            max_area=s.max_area or None,
            poly_degree=s.poly_degree,
        )
        blob = build_blob(frame, [tuple(p.co) for p in s.contour], options)
        mesh = store_blob(self.name, blob)
        s.blob = mesh
        s.modes.clear()
        for j, label in enumerate(blob.labels):
            item = s.modes.add()
            item.name = str(label)
            item.index = j
            item.stiffness = float(blob.stiffness_penalty[j])
        s.active_mode = 0
        for w in blob.warnings:
            self.report({"WARNING"}, w)
        self.report(
            {"INFO"},
            f"Blob {mesh.name!r}: {blob.n_nodes} nodes, {len(blob.triangles)} triangles, "
            f"{blob.n_pixels} pixels, {blob.n_modes} modes.",
        )
        overlay.tag_redraw(context)
        return {"FINISHED"}


classes = (VOODOO_OT_build_blob,)
