"""Blobs and takes live in the .blend: save, reopen, and keep tracking."""

import bpy
import numpy as np
from bpy_extras import anim_utils


def test_blob_and_take_survive_save_and_reload(prepared, sub, make, tmp_path):
    ctx = prepared
    s = ctx.scene.voodoo
    store = sub("operators.storage")
    obj = make.flat_target(keyed=False)
    s.target = obj
    assert bpy.ops.voodoo.track_clip(max_frames=10) == {"FINISHED"}
    blob = store.stored_blob(s.blob)
    take = store.stored_take(s.blob, s.last_take).take
    labels = [m.name for m in s.modes]
    path = tmp_path / "doll.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))

    bpy.ops.wm.read_homefile(use_empty=True)
    assert bpy.context.scene.voodoo.blob is None
    bpy.ops.wm.open_mainfile(filepath=str(path))
    s = bpy.context.scene.voodoo
    store._cache.clear()  # really parse what was saved
    again = store.stored_blob(s.blob)
    for name in ("vertices", "triangles", "modes", "texture", "pixel_weights", "labels", "mass"):
        np.testing.assert_array_equal(getattr(again, name), getattr(blob, name))
    took = store.stored_take(s.blob, s.last_take).take
    np.testing.assert_array_equal(took.params, take.params)
    np.testing.assert_array_equal(took.vertices, take.vertices)
    assert [m.name for m in s.modes] == labels
    obj = bpy.data.objects["Flat"]
    assert obj.animation_data.action.name.startswith(s.last_take)
    assert len(obj.data.shape_keys.key_blocks) == 1 + len(labels)
    assert store.IN_VIEW_PROP in obj and store.QUALITY_PROP in obj  # the readouts reload too
    assert s.capture_image is not None and s.capture_image.packed_file is not None

    # tracking continues where the take ended, from its last pose, and the take grows
    first = s.last_take
    action = obj.animation_data.action
    assert bpy.ops.voodoo.track_clip(resume=True) == {"FINISHED"}
    assert s.last_take == first
    grown = store.stored_take(s.blob, first)
    cont = grown.take
    np.testing.assert_array_equal(cont.params[: len(take)], take.params)
    assert cont.frame_indices.tolist() == list(range(20)) and not cont.lost.any()
    # the take's action now covers the whole take, rewritten in place (no new layer)
    assert obj.animation_data.action == action
    assert len(obj.animation_data.nla_tracks) == 0
    bag = anim_utils.action_get_channelbag_for_slot(action, obj.animation_data.action_slot)
    loc = bag.fcurves.find("location")
    assert [int(k.co[0]) for k in loc.keyframe_points] == grown.frames.tolist()
    # the share in view, keyed over the whole grown take as well
    view = bag.fcurves.find(f'["{store.IN_VIEW_PROP}"]')
    assert [int(k.co[0]) for k in view.keyframe_points] == grown.frames.tolist()
    np.testing.assert_allclose([k.co[1] for k in view.keyframe_points], cont.in_view(), atol=1e-6)
    # ... landing where an uninterrupted take is
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    full = store.stored_take(s.blob, s.last_take).take
    for i in range(len(take), 20):
        err = np.linalg.norm(cont.vertices[i] - full.vertices[i], axis=1).mean()
        assert err < 0.1
