"""The panels draw only real properties and operators.

The bpy module has no window to draw into, so each panel's ``draw`` runs against a layout that
records and checks what it is given.
"""

from types import SimpleNamespace

import bpy
import pytest


class RecordingLayout:
    """Stands in for bpy.types.UILayout; checks every property and operator it is given."""

    def __init__(self, log):
        self.log = log
        self.active = True
        self.enabled = True

    def _child(self, *args, **kwargs):
        return RecordingLayout(self.log)

    row = column = box = split = _child

    def prop(self, data, name, **kwargs):
        assert name in data.bl_rna.properties, f"{type(data).__name__} has no property {name!r}"
        self.log.append(("prop", name))

    def operator(self, idname, **kwargs):
        module, name = idname.split(".")
        assert hasattr(getattr(bpy.ops, module), name), f"no operator {idname}"
        self.log.append(("operator", idname))
        return OperatorButton(self.log, idname)  # the panel may set operator properties

    def label(self, **kwargs):
        self.log.append(("label", kwargs.get("text", "")))

    def template_list(self, list_type, list_id, data, prop, active_data, active_prop, **kw):
        assert hasattr(bpy.types, list_type), f"no UIList {list_type}"
        assert prop in data.bl_rna.properties and active_prop in active_data.bl_rna.properties
        self.log.append(("list", prop))


class OperatorButton:
    """Stands in for the operator properties a button is drawn with; checks each one set."""

    def __init__(self, log, idname):
        module, name = idname.split(".")
        rna = getattr(getattr(bpy.ops, module), name).get_rna_type()
        object.__setattr__(self, "_known", set(rna.properties.keys()))
        object.__setattr__(self, "_log", log)
        object.__setattr__(self, "_idname", idname)

    def __setattr__(self, name, value):
        assert name in self._known, f"{self._idname} has no property {name!r}"
        self._log.append(("set", self._idname, name, value))


@pytest.mark.parametrize("source", ["CLIP", "CAMERA"])
def test_panels_draw_real_properties_and_operators(prepared, sub, source):
    ctx = prepared
    ctx.scene.voodoo.source = source
    ctx.scene.voodoo.last_take = "Take"
    panels = [
        cls
        for name in ("ui.clip_panels", "ui.target_panel")
        for cls in sub(f"operators.{name}").classes
    ]
    log = []
    for cls in panels:
        cls.draw(SimpleNamespace(layout=RecordingLayout(log)), ctx)
    operators = {entry[1] for entry in log if entry[0] == "operator"}
    assert {
        "voodoo.capture_frame",
        "voodoo.contour_from_mask",
        "voodoo.contour_auto",
        "voodoo.sketch_contour",
        "voodoo.build_blob",
        "voodoo.record_take",
        "voodoo.track_clip",
        "voodoo.apply_take",
        "voodoo.select_modes",
        "voodoo.smooth_take",
    } <= operators
    assert ("list", "modes") in log
    assert (("prop", "camera_index") in log) == (source == "CAMERA")
    # Both Ways beside Record Take and Track Whole Clip; Resume after a take.
    assert ("set", "voodoo.record_take", "both_ways", True) in log
    assert ("set", "voodoo.track_clip", "both_ways", True) in log
    assert ("set", "voodoo.track_clip", "resume", True) in log


def test_mode_list_rows(prepared, sub):
    ui_modes = sub("operators.ui.mode_list")
    log = []
    s = prepared.scene.voodoo
    row_layout = RecordingLayout(log)
    ui_modes.VOODOO_UL_modes.draw_item(
        None, prepared, row_layout, s, s.modes[0], 0, s, "active_mode", 0
    )
    assert ("prop", "enabled") in log and ("prop", "gain") in log
    assert ("label", s.modes[0].name) in log


def test_the_dolls_panel_lists_dolls_with_add_and_remove(prepared, sub):
    s = prepared.scene.voodoo
    panels = sub("operators.ui.clip_panels")
    log = []
    panels.VOODOO_PT_dolls.draw(SimpleNamespace(layout=RecordingLayout(log)), prepared)
    assert ("operator", "voodoo.add_doll") in log and ("list", "dolls") not in log
    assert bpy.ops.voodoo.add_doll(name="Tail") == {"FINISHED"}
    log = []
    panels.VOODOO_PT_dolls.draw(SimpleNamespace(layout=RecordingLayout(log)), prepared)
    assert ("list", "dolls") in log and ("operator", "voodoo.remove_doll") in log
    rows = []
    for i, doll in enumerate(s.dolls):
        sub("operators.ui.doll_list").VOODOO_UL_dolls.draw_item(
            None, prepared, RecordingLayout(rows), s, doll, 0, s, "active_doll", i
        )
    assert ("prop", "name") in rows and ("label", "Doll") in rows and ("label", "no blob") in rows
