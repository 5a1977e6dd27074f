"""Tracking quality where an animator looks: an F-curve on the target, markers on the timeline."""

import bpy
import numpy as np
from bpy_extras import anim_utils


def _quality_curve(obj, sub, prop="QUALITY_PROP"):
    store = sub("operators.storage")
    bag = anim_utils.action_get_channelbag_for_slot(
        obj.animation_data.action, obj.animation_data.action_slot
    )
    return bag.fcurves.find(f'["{getattr(store, prop)}"]')


def test_every_tracked_frame_keys_the_quality(prepared, sub, make):
    ctx = prepared
    s = ctx.scene.voodoo
    obj = make.flat_target()
    s.target = obj
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    store, animation = sub("operators.storage"), sub("operators.animation")
    stored = store.stored_take(s.blob, s.last_take)
    take, frames = stored.take, stored.frames
    fc = _quality_curve(obj, sub)
    assert fc is not None
    keys = np.array([k.co[:] for k in fc.keyframe_points])
    np.testing.assert_array_equal(keys[:, 0], frames)
    np.testing.assert_allclose(keys[:, 1], np.where(take.lost, 0.0, take.confidence), atol=1e-6)
    assert (keys[:, 1] > animation.ATTENTION_BELOW).all()  # a clean take: nothing to look at
    assert not [m for m in ctx.scene.timeline_markers if m.name.startswith(s.last_take)]
    ui = obj.id_properties_ui(store.QUALITY_PROP).as_dict()
    assert ui["min"] == 0.0 and ui["max"] == 1.0
    # The share of the doll in view, keyed beside it: all of it, on a flat card in view.
    fc = _quality_curve(obj, sub, "IN_VIEW_PROP")
    keys = np.array([k.co[:] for k in fc.keyframe_points])
    np.testing.assert_array_equal(keys[:, 0], frames)
    np.testing.assert_allclose(keys[:, 1], take.in_view(), atol=1e-6)
    assert (keys[:, 1] > 0.9).all()
    assert {k.interpolation for k in fc.keyframe_points} == {"CONSTANT"}
    ui = obj.id_properties_ui(store.IN_VIEW_PROP).as_dict()
    assert ui["min"] == 0.0 and ui["max"] == 1.0


def test_low_quality_stretches_get_one_marker_each(ctx, sub):
    animation = sub("operators.animation")
    scene = ctx.scene
    frames = np.arange(10, 30)
    quality = np.full(20, 0.9)
    quality[3:6] = 0.2  # frames 13-15
    quality[12] = 0.0  # frame 22 (lost)
    marked = animation.mark_attention(scene, "Take", frames, quality)
    assert marked == [(13, 15), (22, 22)]
    names = sorted((m.frame, m.name) for m in scene.timeline_markers)
    assert names == [(13, "Take: check 13-15"), (22, "Take: check frame 22")]
    # Applying the same take again replaces its markers; other markers stay.
    scene.timeline_markers.new("Mine", frame=5)
    animation.mark_attention(scene, "Take", frames, np.full(20, 0.9))
    assert [m.name for m in scene.timeline_markers] == ["Mine"]


def test_a_take_that_leaves_the_picture_is_marked_and_reported(ctx, make, exit_clip, sub):
    make.prepare(exit_clip)
    obj = make.flat_target(keyed=False)
    ctx.scene.voodoo.target = obj
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    take_name = ctx.scene.voodoo.last_take
    markers = [m for m in ctx.scene.timeline_markers if m.name.startswith(take_name)]
    assert markers, "the frames where the doll was gone are not marked"
    stored = sub("operators.storage").stored_take(ctx.scene.voodoo.blob, take_name)
    lost_frames = stored.frames[stored.take.lost]
    starts = sorted(m.frame for m in markers)
    assert min(lost_frames) >= starts[0]
    fc = _quality_curve(obj, sub)
    for f in lost_frames:
        assert fc.evaluate(float(f)) == 0.0
    # How much of the doll was in view: nothing while it is gone; less than all of it on
    # the frames where it was leaving the picture and still followed.
    in_view = _quality_curve(obj, sub, "IN_VIEW_PROP")
    for f in lost_frames:
        assert in_view.evaluate(float(f)) == 0.0
    tracked = stored.frames[~stored.take.lost]
    shares = np.array([in_view.evaluate(float(f)) for f in tracked])
    assert (shares < 0.9).any() and (shares > 0.0).all()
