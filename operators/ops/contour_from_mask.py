import bpy

from ...voodoo_addon.blob.outline import simplify_contour, validate_contour
from ..clips import outline_from_mask
from .common import needs, reports_errors, settings, store_contour


class VOODOO_OT_contour_from_mask(bpy.types.Operator):
    """Use the Mask drawn over the clip as the outline of the blob"""

    bl_idname = "voodoo.contour_from_mask"
    bl_label = "Outline from Mask"
    bl_options = {"REGISTER", "UNDO"}

    mask: bpy.props.StringProperty(name="Mask", description="Mask to use (default: the editor's)")

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "capture")

    @reports_errors
    def execute(self, context):
        s = settings(context)
        mask = bpy.data.masks.get(self.mask) if self.mask else None
        if mask is None:
            space = getattr(context, "space_data", None)
            mask = getattr(space, "mask", None) if space is not None else None
        if mask is None and len(bpy.data.masks) == 1:
            mask = bpy.data.masks[0]
        size = tuple(s.capture_image.size)
        points = outline_from_mask(mask, size)
        points = validate_contour(simplify_contour(points, 0.5), frame_size=size)
        store_contour(s, points)
        self.report({"INFO"}, f"Outline of {len(points)} points from mask {mask.name!r}.")
        return {"FINISHED"}


classes = (VOODOO_OT_contour_from_mask,)
