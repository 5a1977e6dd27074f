import bpy

from ...voodoo_addon.blob.outline import validate_contour
from ...voodoo_addon.errors import VoodooError
from .. import drawing
from ..pixels import region_to_pixel
from .common import needs, reports_errors, settings, store_contour


class VOODOO_OT_sketch_contour(bpy.types.Operator):
    """Click points around the object; Enter closes the outline, Backspace undoes, Esc cancels"""

    bl_idname = "voodoo.sketch_contour"
    bl_label = "Sketch Outline"
    bl_options = {"REGISTER", "UNDO"}

    coords: bpy.props.StringProperty(
        name="Coordinates", description="Scripted outline: 'x y, x y, ...' in pixels"
    )

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "capture")

    @reports_errors
    def execute(self, context):
        """Scripted use: the outline given in ``coords``."""
        try:
            pts = [tuple(float(v) for v in p.split()) for p in self.coords.split(",") if p.strip()]
        except ValueError:
            raise VoodooError("Coordinates must read 'x y, x y, ...'.") from None
        self._finish(context, pts)
        return {"FINISHED"}

    def invoke(self, context, event):
        if context.area is None or context.area.type != "CLIP_EDITOR":
            self.report({"ERROR"}, "Sketch in the Movie Clip Editor.")
            return {"CANCELLED"}
        self._saved = [tuple(p.co) for p in settings(context).contour]
        settings(context).contour.clear()
        context.window_manager.modal_handler_add(self)
        context.area.header_text_set("Click around the object; Enter closes, Esc cancels")
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        s = settings(context)
        if event.type == "LEFTMOUSE" and event.value == "PRESS":
            h = s.capture_image.size[1]
            s.contour.add().co = region_to_pixel(
                context.region, event.mouse_region_x, event.mouse_region_y, h
            )
        elif event.type == "BACK_SPACE" and event.value == "PRESS" and len(s.contour):
            s.contour.remove(len(s.contour) - 1)
        elif event.type in {"RET", "NUMPAD_ENTER", "RIGHTMOUSE"} and event.value == "PRESS":
            context.area.header_text_set(None)
            try:
                self._finish(context, [tuple(p.co) for p in s.contour])
            except VoodooError as exc:
                self.report({"ERROR"}, str(exc))
                store_contour(s, self._saved)
                return {"CANCELLED"}
            return {"FINISHED"}
        elif event.type == "ESC":
            context.area.header_text_set(None)
            store_contour(s, self._saved)
            return {"CANCELLED"}
        else:
            return {"PASS_THROUGH"}
        drawing.tag_redraw(context)
        return {"RUNNING_MODAL"}

    def _finish(self, context, pts):
        s = settings(context)
        size = tuple(s.capture_image.size)
        store_contour(s, validate_contour(pts, frame_size=size))
        drawing.tag_redraw(context)


classes = (VOODOO_OT_sketch_contour,)
