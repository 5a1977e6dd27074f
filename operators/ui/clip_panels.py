import bpy

from ..drawing import live_state
from ..recorder import interrupted_takes
from ..storage import blob_bytes, blob_meshes, blob_users
from .mode_list import draw_mode_list


class _ClipPanel:
    bl_space_type = "CLIP_EDITOR"
    bl_region_type = "UI"
    bl_category = "Voodoo"


class VOODOO_PT_source(_ClipPanel, bpy.types.Panel):
    """Where frames come from, and the captured frame to outline"""

    bl_label = "Source"

    def draw(self, context):
        s = context.scene.voodoo
        layout = self.layout
        layout.prop(s, "source", expand=True)
        if s.source == "CAMERA":
            layout.prop(s, "camera_index")
            layout.prop(s, "camera_seconds")
        layout.operator("voodoo.capture_frame", icon="IMAGE_DATA")
        if s.capture_image is not None:
            layout.label(
                text=f"Captured frame {s.capture_index} "
                f"({s.capture_image.size[0]}x{s.capture_image.size[1]})"
            )


class VOODOO_PT_dolls(_ClipPanel, bpy.types.Panel):
    """Several dolls in one scene, each with its own outline, blob, modes and target"""

    bl_label = "Dolls"

    def draw(self, context):
        s = context.scene.voodoo
        layout = self.layout
        if not len(s.dolls):
            row = layout.row()
            row.label(text="One doll")
            row.operator("voodoo.add_doll", text="", icon="ADD")
            return
        row = layout.row()
        row.template_list("VOODOO_UL_dolls", "", s, "dolls", s, "active_doll", rows=3)
        col = row.column(align=True)
        col.operator("voodoo.add_doll", text="", icon="ADD")
        col.operator("voodoo.remove_doll", text="", icon="REMOVE")
        layout.label(text="The panels below show the selected doll", icon="INFO")


class VOODOO_PT_outline(_ClipPanel, bpy.types.Panel):
    """The region of the object to track"""

    bl_label = "Outline"

    def draw(self, context):
        s = context.scene.voodoo
        col = self.layout.column(align=True)
        col.operator("voodoo.contour_from_mask", icon="MOD_MASK")
        col.operator("voodoo.contour_auto", icon="SHADERFX")
        col.operator("voodoo.sketch_contour", icon="GREASEPENCIL")
        col.operator("voodoo.clear_contour", icon="X")
        self.layout.label(text=f"{len(s.contour)} outline points")


class VOODOO_PT_blob(_ClipPanel, bpy.types.Panel):
    """Mesh and mode settings, and the blob's modes"""

    bl_label = "Blob"

    def draw(self, context):
        s = context.scene.voodoo
        layout = self.layout
        col = layout.column(align=True)
        col.prop(s, "n_modes")
        col.prop(s, "min_angle")
        col.prop(s, "max_area")
        col.prop(s, "poly_degree")
        layout.operator("voodoo.build_blob", icon="MESH_GRID")
        if s.blob is not None:
            layout.label(text=f"Blob: {s.blob.name}")
        draw_mode_list(layout, s)
        unused = [m for m in blob_meshes() if not blob_users(m)]
        if unused:
            size = sum(blob_bytes(m) for m in unused) / 1e6
            row = layout.row()
            row.label(text=f"{len(unused)} unused blob(s), {size:.1f} MB", icon="ERROR")
            row.operator("voodoo.remove_unused_blobs", text="", icon="TRASH")


class VOODOO_PT_record(_ClipPanel, bpy.types.Panel):
    """Recording takes"""

    bl_label = "Record"

    def draw(self, context):
        s = context.scene.voodoo
        layout = self.layout
        layout.prop(s, "take_name")
        layout.prop(s, "target")
        layout.prop(s, "warp")
        row = layout.row(align=True)
        row.label(text="Freeze")
        row.prop(s, "freeze_translation", toggle=True)
        row.prop(s, "freeze_rotation", toggle=True)
        row.prop(s, "freeze_scale", toggle=True)
        row = layout.row(align=True)
        row.prop(s, "osc_send", text="OSC", toggle=True)
        sub = row.row(align=True)
        sub.active = s.osc_send
        sub.prop(s, "osc_target", text="")
        sub.prop(s, "osc_bundle", text="", icon="PACKAGE")
        row = layout.row(align=True)
        row.operator("voodoo.record_take", icon="REC")
        both = row.operator("voodoo.record_take", text="Both Ways", icon="TRACKING_BACKWARDS")
        both.both_ways = True
        row = layout.row(align=True)
        row.operator("voodoo.track_clip", icon="TRACKING_FORWARDS")
        both = row.operator("voodoo.track_clip", text="Both Ways", icon="TRACKING_BACKWARDS")
        both.both_ways = True
        if live_state.get("rate"):
            text = f"Tracking {live_state['rate']:.0f} fps, latency "
            text += f"{1000 * live_state['latency']:.0f} ms"
            if live_state.get("behind"):
                text += f", {live_state['behind']} behind"
            layout.label(text=text, icon="TIME")
        if s.last_take:
            row = layout.row()
            row.label(text=f"Last take: {s.last_take}")
            row.operator("voodoo.track_clip", text="Resume", icon="PLAY").resume = True
        lost = interrupted_takes()
        if lost:
            layout.label(text=f"{len(lost)} interrupted take(s) on disk", icon="ERROR")
            layout.operator("voodoo.recover_takes", icon="RECOVER_LAST")


classes = (
    VOODOO_PT_source,
    VOODOO_PT_dolls,
    VOODOO_PT_outline,
    VOODOO_PT_blob,
    VOODOO_PT_record,
)
