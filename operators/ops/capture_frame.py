import bpy

from ...voodoo_addon.media.sources import open_source
from ..clips import active_clip, open_clip, source_index
from ..pixels import image_from_rgb
from ..storage import footage_dir
from .common import needs, reports_errors, settings


class VOODOO_OT_capture_frame(bpy.types.Operator):
    """Grab the current frame of the clip (or the camera) to outline the object on"""

    bl_idname = "voodoo.capture_frame"
    bl_label = "Capture Frame"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "source")

    @reports_errors
    def execute(self, context):
        s = settings(context)
        if s.source == "CAMERA":
            with open_source(int(s.camera_index)) as src:
                frame = src.read()
            index = 0
        else:
            clip = active_clip(context)
            with open_clip(clip) as src:
                index = source_index(clip, context.scene.frame_current)
                frame = src.read_at(index)
        old = s.capture_image
        s.capture_image = image_from_rgb("Voodoo Capture", frame.image)
        s.capture_index = index
        if old is not None and old.users == 0:
            bpy.data.images.remove(old)
        if s.source == "CAMERA":
            self._show_as_clip(context, s.capture_image)
        h, w = frame.image.shape[:2]
        self.report({"INFO"}, f"Captured frame {index} ({w}x{h}); now outline the object.")
        return {"FINISHED"}

    def _show_as_clip(self, context, image):
        """Camera captures become a one-frame clip, so a Mask can be drawn over them."""
        folder = footage_dir()
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / "capture.png"
        image.save(filepath=str(path))
        clip = bpy.data.movieclips.load(str(path), check_existing=False)
        context.scene.active_clip = clip
        space = getattr(context, "space_data", None)
        if space is not None and space.type == "CLIP_EDITOR":
            space.clip = clip


classes = (VOODOO_OT_capture_frame,)
