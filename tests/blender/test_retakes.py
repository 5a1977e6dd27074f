"""Re-takes and re-applies: one action per take, one undo step per apply, the rest pose of the
take, no dead blobs, crash recovery, and preconditions that grey the buttons out."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import bpy
import numpy as np
import pytest
from bpy_extras import anim_utils

ROOT = Path(__file__).resolve().parents[2]


def _track(ctx, target, **kw):
    ctx.scene.voodoo.target = target
    assert bpy.ops.voodoo.track_clip(**kw) == {"FINISHED"}
    return ctx.scene.voodoo.last_take


def _take_actions(take_name):
    return [a for a in bpy.data.actions if a.get("voodoo_take") == take_name]


def _curves(obj):
    """Every curve that animates the target: (owner, path, index) -> (mute, values)."""
    out = {}
    for owner in (obj, obj.data.shape_keys):
        ad = owner.animation_data
        if ad is None or ad.action is None:
            continue
        bag = anim_utils.action_get_channelbag_for_slot(ad.action, ad.action_slot)
        for fc in bag.fcurves:
            values = tuple(round(k.co[1], 6) for k in fc.keyframe_points)
            out[(type(owner).__name__, fc.data_path, fc.array_index)] = (fc.mute, values)
    return out


def test_ten_reapplies_leave_one_action_and_each_undoes_in_one_step(prepared, make):
    ctx = prepared
    s = ctx.scene.voodoo
    obj = make.flat_target(keyed=False)
    take = _track(ctx, obj)
    bpy.ops.ed.undo_push(message="tracked")  # background Blender starts its undo stack here
    rng = np.random.default_rng(7)
    states = []
    for i in range(10):
        for m in s.modes:
            m.enabled = bool(rng.uniform() < 0.6)
            m.gain = float(rng.choice([0.5, 1.0, 2.0]))
        s.apply_rotation = bool(i % 2)
        # as a click does: the operator pushes its undo step
        assert bpy.ops.voodoo.apply_take("EXEC_DEFAULT", True) == {"FINISHED"}
        obj = bpy.data.objects["Flat"]
        states.append(_curves(obj))
        assert len(_take_actions(take)) == 1
        assert len(obj.animation_data.nla_tracks) == 0
    assert states[-1] != states[-2]
    # one undo step takes back exactly one apply
    for back in (8, 7):
        assert bpy.ops.ed.undo() == {"FINISHED"}
        obj = bpy.data.objects["Flat"]
        assert _curves(obj) == states[back]
        assert len(_take_actions(take)) == 1


def test_rest_pose_comes_from_the_takes_rest_frame(prepared, make):
    """The target moves in its own animation; the take was recorded from frame 1, so its rest
    is where the target stood on frame 1, whichever frame the scene is on at Apply."""
    ctx = prepared
    obj = make.flat_target(keyed=True)  # x: 0 on frame 1, 2 on frame 30
    ctx.scene.frame_set(1)
    _track(ctx, obj)
    link = obj["voodoo"]
    rest = np.array(link["rest_matrix"]).reshape(4, 4)
    assert abs(rest[0, 3]) < 1e-6
    ctx.scene.frame_set(25)
    assert bpy.ops.voodoo.apply_take(new_layer=True) == {"FINISHED"}
    again = np.array(obj["voodoo"]["rest_matrix"]).reshape(4, 4)
    np.testing.assert_allclose(again, rest, atol=1e-6)


def test_apply_to_selected_skips_what_is_not_a_mesh(prepared, make):
    ctx = prepared
    obj = make.flat_target(keyed=False)
    _track(ctx, obj)
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    ctx.scene.collection.objects.link(cam)
    box = make.solid_target()
    for o in (cam, box):
        o.select_set(True)
    obj.select_set(False)
    assert bpy.ops.voodoo.apply_take(selected=True) == {"FINISHED"}
    assert box.animation_data.action is not None
    assert cam.animation_data is None


def test_a_nan_gain_is_refused_and_changes_nothing(prepared, make):
    ctx = prepared
    obj = make.flat_target(keyed=False)
    _track(ctx, obj)
    before = _curves(obj)
    ctx.scene.voodoo.modes[0]["gain"] = float("nan")  # a script bypasses the slider
    with pytest.raises(RuntimeError, match="gain"):
        bpy.ops.voodoo.apply_take()
    assert _curves(obj) == before
    for fc_values in _curves(obj).values():
        assert np.isfinite(fc_values[1]).all()


def test_building_again_removes_the_blob_it_replaces_unless_takes_use_it(prepared, make, sub):
    ctx = prepared
    store = sub("operators.storage")
    s = ctx.scene.voodoo
    first = store.blob_id(s.blob)
    assert bpy.ops.voodoo.build_blob(name="Doll") == {"FINISHED"}
    assert [store.blob_id(m) for m in store.blob_meshes()] == [store.blob_id(s.blob)]
    assert store.blob_id(s.blob) != first  # the replaced blob had no take, no user: gone
    _track(ctx, make.flat_target(keyed=False))
    with_take = store.blob_id(s.blob)
    assert bpy.ops.voodoo.build_blob(name="Doll") == {"FINISHED"}
    ids = [store.blob_id(m) for m in store.blob_meshes()]
    assert with_take in ids and len(ids) == 2  # its take drives the target: kept
    # drop the target: that blob is unused but holds a take
    bpy.data.objects.remove(bpy.data.objects["Flat"])
    assert bpy.ops.voodoo.remove_unused_blobs() == {"FINISHED"}
    assert with_take in [store.blob_id(m) for m in store.blob_meshes()]
    assert bpy.ops.voodoo.remove_unused_blobs(with_takes=True) == {"FINISHED"}
    assert [store.blob_id(m) for m in store.blob_meshes()] == [store.blob_id(s.blob)]


def test_buttons_are_greyed_out_with_a_reason(ctx):
    """Without clip, blob or target the operators' poll fails with the reason Blender shows."""
    cases = {
        bpy.ops.voodoo.capture_frame: "Open a movie clip",
        bpy.ops.voodoo.build_blob: "Capture a frame first",
        bpy.ops.voodoo.smooth_take: "no applied take",
        bpy.ops.voodoo.track_clip: "Build a blob first",
        bpy.ops.voodoo.apply_take: "Build a blob first",
        bpy.ops.voodoo.select_modes: "Build a blob",
    }
    for op, reason in cases.items():
        assert not op.poll()
        with pytest.raises(RuntimeError, match=reason):
            op()


CRASH = """
import os, sys
sys.path.insert(0, {root!r}); sys.path.insert(0, {scripts!r})
import bpy, bmesh
from blender_addon import enable_from_checkout
module = enable_from_checkout(scratch={scratch!r})
import importlib
scene = bpy.context.scene
clip = bpy.data.movieclips.load({clip!r})
scene.active_clip = clip
scene.frame_set(clip.frame_start)
assert bpy.ops.voodoo.capture_frame() == {{"FINISHED"}}
s = scene.voodoo
for x, y in {contour!r}:
    s.contour.add().co = (x, y)
assert bpy.ops.voodoo.build_blob(name="Doll") == {{"FINISHED"}}
mesh = bpy.data.meshes.new("Flat")
bm = bmesh.new(); bmesh.ops.create_grid(bm, x_segments=4, y_segments=4, size=1.0)
for v in bm.verts: v.co = (v.co.x, 0.0, v.co.y)
bm.to_mesh(mesh); bm.free()
obj = bpy.data.objects.new("Flat", mesh); scene.collection.objects.link(obj)
s.target = obj
s.take_name = "Crashed"
bpy.ops.wm.save_as_mainfile(filepath={blend!r})
rec = importlib.import_module(module + ".operators.recorder").Recorder(bpy.context, live=True)
for _ in range({n}):
    assert rec.step()
os._exit(0)  # Blender dies mid-take: no finish, no save
"""


def test_a_crash_mid_take_keeps_every_recorded_frame(ctx, clip_file, sub, tmp_path):
    blend = tmp_path / "crash.blend"
    script = CRASH.format(
        root=str(ROOT),
        scripts=str(ROOT / "scripts"),
        scratch=str(tmp_path / "ext"),
        clip=str(clip_file["path"]),
        contour=[tuple(map(float, p)) for p in clip_file["contour"]],
        blend=str(blend),
        n=7,
    )
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    run = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(script)],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    s = bpy.context.scene.voodoo
    recorder = sub("operators.recorder")
    found = recorder.interrupted_takes()
    assert len(found) == 1
    assert bpy.ops.voodoo.recover_takes() == {"FINISHED"}
    store = sub("operators.storage")
    kept = store.stored_take(s.blob, "Crashed")
    assert len(kept.take) == 7 and not kept.take.lost.any()
    assert kept.frames.tolist() == list(range(1, 8))
    assert recorder.interrupted_takes() == []
    assert not bpy.ops.voodoo.recover_takes.poll()
    # the recovered take applies like any other
    s.last_take = "Crashed"
    assert bpy.ops.voodoo.apply_take() == {"FINISHED"}
    assert len(_take_actions("Crashed")) == 1


def test_a_take_tracked_both_ways_is_a_new_take_with_its_own_action(prepared, sub, make):
    """Track Whole Clip, Both Ways: the clip is tracked again backwards from its end and the
    surer pass kept frame by frame. It is stored as a new take beside the forward one (whose
    action stays), over the same frames, as near the truth, with the work of both passes."""
    ctx = prepared
    store = sub("operators.storage")
    s = ctx.scene.voodoo
    obj = make.flat_target(keyed=False)
    first = _track(ctx, obj)
    forward = store.stored_take(s.blob, first).take
    first_action = obj.animation_data.action
    both_name = _track(ctx, obj, both_ways=True)
    assert both_name != first
    both = store.stored_take(s.blob, both_name).take
    np.testing.assert_array_equal(both.frame_indices, forward.frame_indices)
    assert not both.lost.any() and np.isfinite(both.params).all()
    assert np.all(both.iterations > forward.iterations)  # the backward pass's work is in it
    # The doll is followed throughout by either pass: the merge stays within a pixel.
    assert np.linalg.norm(both.vertices - forward.vertices, axis=2).mean() < 1.0
    assert _take_actions(first) == [first_action]
    assert obj.animation_data.action is not first_action
    assert obj.animation_data.action.get("voodoo_take") == both_name


def test_record_take_both_ways_from_a_script_tracks_the_take_both_ways(prepared, sub, make):
    """Record Take has Both Ways too (the button beside it, an operator option): from a
    script it records the whole clip, then tracks it again backwards."""
    ctx = prepared
    store = sub("operators.storage")
    s = ctx.scene.voodoo
    s.target = make.flat_target(keyed=False)
    assert bpy.ops.voodoo.record_take() == {"FINISHED"}
    forward = store.stored_take(s.blob, s.last_take).take
    assert bpy.ops.voodoo.record_take(both_ways=True) == {"FINISHED"}
    both = store.stored_take(s.blob, s.last_take).take
    np.testing.assert_array_equal(both.frame_indices, forward.frame_indices)
    assert np.all(both.iterations > forward.iterations)  # the backward pass's work is in it
    assert s.target.animation_data.action.get("voodoo_take") == s.last_take


def test_a_take_tracked_both_ways_survives_save_and_reload(prepared, sub, make, tmp_path):
    ctx = prepared
    store = sub("operators.storage")
    s = ctx.scene.voodoo
    name = _track(ctx, make.flat_target(keyed=False), both_ways=True)
    take = store.stored_take(s.blob, name).take
    path = tmp_path / "both.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(path))
    store._cache.clear()  # really parse what was saved
    s = bpy.context.scene.voodoo
    again = store.stored_take(s.blob, name).take
    np.testing.assert_array_equal(again.params, take.params)
    np.testing.assert_array_equal(again.iterations, take.iterations)
    assert bpy.data.objects["Flat"].animation_data.action.get("voodoo_take") == name
