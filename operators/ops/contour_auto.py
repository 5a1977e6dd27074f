import bpy

from ..voodoo_addon.blob.segment import segment_contour
from ..voodoo_addon.errors import VoodooError
from .common import reports_errors, settings, store_contour
from .frames import rgb_from_image


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

    def invoke(self, context, event):
        region = context.region
        space = context.space_data
        if space is not None and space.type == "CLIP_EDITOR" and region.type == "WINDOW":
            x, y = region.view2d.region_to_view(event.mouse_region_x, event.mouse_region_y)
            h = settings(context).capture_image.size[1] if settings(context).capture_image else 0
            if h:
                self.point = (x - 0.5, h - y - 0.5)
        return self.execute(context)

    @reports_errors
    def execute(self, context):
        s = settings(context)
        if s.capture_image is None:
            raise VoodooError("Capture a frame first.")
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
