import bpy

from ...voodoo_addon.errors import VoodooError
from ..animation import active_channelbag
from ..storage import IN_VIEW_PROP, QUALITY_PROP, read_link
from .common import needs, reports_errors, settings

#: Curves of a take that read out how it was tracked, not how the doll moved: not smoothed.
READOUTS = tuple(f'["{prop}"]' for prop in (QUALITY_PROP, IN_VIEW_PROP))


def _take_curves(obj):
    """F-curves of the take action on an object and on its shape-key datablock.

    Returns (motion curves, readout curves: the tracking quality and the share in view).
    """
    bags = (active_channelbag(obj), active_channelbag(obj.data.shape_keys))
    curves = [fc for bag in bags if bag is not None for fc in bag.fcurves]
    motion = [fc for fc in curves if fc.data_path not in READOUTS]
    return motion, [fc for fc in curves if fc.data_path in READOUTS]


class VOODOO_OT_smooth_take(bpy.types.Operator):
    """Smooth the target's take curves with Blender's Butterworth filter (keys stay editable)"""

    bl_idname = "voodoo.smooth_take"
    bl_label = "Smooth Take"
    bl_options = {"REGISTER", "UNDO"}

    cutoff: bpy.props.FloatProperty(
        name="Cutoff",
        description="Frequencies above this many Hz are removed",
        default=3.0,
        min=0.1,
        max=30.0,
    )

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "applied")

    @reports_errors
    def execute(self, context):
        s = settings(context)
        obj = s.target if s.target is not None else context.active_object
        if read_link(obj) is None:
            raise VoodooError("The target has no applied take to smooth.")
        curves, readouts = _take_curves(obj)
        if not curves:
            raise VoodooError(f"{obj.name!r} has no take curves (was its action replaced?).")
        window = context.window or context.window_manager.windows[0]
        area = context.area if context.area is not None else window.screen.areas[0]
        old_type = area.type
        selection = [(o, o.select_get()) for o in context.view_layer.objects]
        old_active = context.view_layer.objects.active
        try:
            area.type = "GRAPH_EDITOR"
            for o, _ in selection:
                o.select_set(o == obj)
            context.view_layer.objects.active = obj
            for fc, chosen in [(fc, True) for fc in curves] + [(fc, False) for fc in readouts]:
                fc.select = chosen
                fc.hide = False
                for k in fc.keyframe_points:
                    k.select_control_point = chosen
            region = next(r for r in area.regions if r.type == "WINDOW")
            with context.temp_override(window=window, area=area, region=region):
                result = bpy.ops.graph.butterworth_smooth(cutoff_frequency=self.cutoff)
        finally:
            area.type = old_type
            for o, was in selection:
                o.select_set(was)
            context.view_layer.objects.active = old_active
        if "FINISHED" not in result:
            raise VoodooError("Blender's smoothing did not run on the take's curves.")
        self.report({"INFO"}, f"Smoothed {len(curves)} curves of {obj.name!r}.")
        return {"FINISHED"}


classes = (VOODOO_OT_smooth_take,)
