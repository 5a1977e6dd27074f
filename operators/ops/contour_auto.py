import bpy

from ...voodoo_addon.blob.segment import segment_contour
from ..pixels import region_to_pixel, rgb_from_image
from .common import needs, reports_errors, settings, store_contour


class VOODOO_OT_contour_auto(bpy.types.Operator):
    """Find the object's outline around a point (click in the Clip Editor) or in a box"""

    bl_idname = "voodoo.contour_auto"
    bl_label = "Automatic Outline"
    bl_options = {"REGISTER", "UNDO"}

    use_box: bpy.props.BoolProperty(name="Box", description="Segment inside a box, not at a point")
    point: bpy.props.FloatVectorProperty(
        name="Point",
        size=2,
        description="Pixel on the object (x right, y down); -1: centre",
        default=(-1.0, -1.0),
    )
    box: bpy.props.FloatVectorProperty(
        name="Box", size=4, description="x0, y0, x1, y1 in pixels", default=(0, 0, 0, 0)
    )

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "capture")

    def invoke(self, context, event):
        region = context.region
        space = context.space_data
        if space is not None and space.type == "CLIP_EDITOR" and region.type == "WINDOW":
            h = settings(context).capture_image.size[1]
            self.point = region_to_pixel(region, event.mouse_region_x, event.mouse_region_y, h)
        return self.execute(context)

    @reports_errors
    def execute(self, context):
        s = settings(context)
        frame = rgb_from_image(s.capture_image)
        h, w = frame.shape[:2]
        if self.use_box:
            points = segment_contour(frame, box=tuple(self.box))
        else:
            point = tuple(self.point)
            if point[0] < 0 or point[1] < 0:
                point = ((w - 1) / 2.0, (h - 1) / 2.0)
            points = segment_contour(frame, point=point)
        store_contour(s, points)
        self.report({"INFO"}, f"Automatic outline of {len(points)} points.")
        return {"FINISHED"}


classes = (VOODOO_OT_contour_auto,)
