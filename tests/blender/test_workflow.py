"""The whole sequence through the operators: capture, mask -> outline, build, track, apply."""

import bpy
import numpy as np
import pytest


def _evaluated_world(obj):
    deps = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(deps)
    mesh = ev.to_mesh()
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    ev.to_mesh_clear()
    m = np.array(ev.matrix_world)
    return co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]


def _prediction(sub, obj, row):
    """What the engine says the target looks like at a take row."""
    store = sub("operators.storage")
    apply = sub("operators.apply")
    rt = sub("voodoo_addon.takes.rig")
    s = bpy.context.scene.voodoo
    link = obj[store.LINK_KEY]
    blob = store.stored_blob(s.blob)
    take = store.stored_take(s.blob, link["take"]).take
    modes = [m for m in s.modes if m.enabled]
    rig = rt.Rig(
        blob,
        apply.layout_for(blob, take),
        apply.rest_vertices(obj),
        modes=[m.index for m in modes],
        use=(s.apply_location, s.apply_rotation, s.apply_scale),
        mapping=rt.mapping_from_list(link["axes"], link["mapping"]),
    )
    values, delta = rig.pose(take.params[row])
    rest_matrix = np.array(link["rest_matrix"]).reshape(4, 4)
    gains = np.array([m.gain for m in modes])
    offsets = rig.offsets * gains[:, None, None]
    return rt.predict_vertices(rig.rest, offsets, values, rest_matrix @ delta), take


def _track(ctx, target):
    ctx.scene.voodoo.target = target
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    return ctx.scene.voodoo.last_take


def test_flat_cutout_take(prepared, sub, make):
    ctx = prepared
    s = ctx.scene.voodoo
    obj = make.flat_target()
    old_action = obj.animation_data.action
    take_name = _track(ctx, obj)
    # one shape key per selected mode (plus the Basis)
    names = [kb.name for kb in obj.data.shape_keys.key_blocks]
    assert names[0] == "Basis"
    assert names[1:] == [f"Doll:{m.name}" for m in s.modes if m.enabled]
    # a new action named after the take, with an object slot and a key slot
    action = obj.animation_data.action
    assert action is not old_action and action.name == take_name
    assert obj.data.shape_keys.animation_data.action is action
    assert {slot.target_id_type for slot in action.slots} == {"OBJECT", "KEY"}
    # the animation that was there survives in the NLA
    strips = [st for tr in obj.animation_data.nla_tracks for st in tr.strips]
    assert [st.action for st in strips] == [old_action]
    # keys on every tracked frame
    store = sub("operators.storage")
    take = store.stored_take(s.blob, take_name).take
    frames = store.stored_take(s.blob, take_name).frames
    assert not take.lost.any()
    from bpy_extras import anim_utils

    for id_data in (obj, obj.data.shape_keys):
        bag = anim_utils.action_get_channelbag_for_slot(action, id_data.animation_data.action_slot)
        assert len(bag.fcurves) > 0
        for fc in bag.fcurves:
            keyed = [int(round(k.co[0])) for k in fc.keyframe_points]
            assert keyed == frames.tolist()
    # Blender evaluates exactly what the engine predicts
    for row in (5, 12, len(frames) - 1):
        ctx.scene.frame_set(int(frames[row]))
        predicted, _ = _prediction(sub, obj, row)
        got = _evaluated_world(obj)
        scale = np.abs(predicted).max()
        assert np.abs(got - predicted).max() < 1e-4 * scale


def test_doll_shaped_target_follows_tracked_nodes(prepared, sub):
    """A character whose vertices sit on the doll's nodes moves exactly like the tracked nodes."""
    ctx = prepared
    s = ctx.scene.voodoo
    store = sub("operators.storage")
    rt = sub("voodoo_addon.takes.rig")
    blob = store.stored_blob(s.blob)
    # the doll laid onto the XZ plane at 1 unit = 50 px, centred at the origin
    v = np.zeros((blob.n_nodes, 3))
    centre = 0.5 * (blob.vertices.min(axis=0) + blob.vertices.max(axis=0))
    v[:, 0] = (blob.vertices[:, 0] - centre[0]) / 50.0
    v[:, 2] = -(blob.vertices[:, 1] - centre[1]) / 50.0
    mesh = bpy.data.meshes.new("DollShape")
    mesh.from_pydata(v.tolist(), [], blob.triangles.tolist())
    obj = bpy.data.objects.new("DollShape", mesh)
    ctx.scene.collection.objects.link(obj)
    take_name = _track(ctx, obj)
    take = store.stored_take(s.blob, take_name).take
    mapping = rt.mapping_from_list("XZ", obj["voodoo"]["mapping"])
    assert mapping.scale == pytest.approx(1 / 50.0)
    frames = sub("operators.storage").stored_take(s.blob, take_name).frames
    for row in (4, 10, 19):
        ctx.scene.frame_set(int(frames[row]))
        expected = mapping.to_target(take.vertices[row])
        got = _evaluated_world(obj)
        assert np.abs(got - expected).max() < 2e-4  # units; a node is 1/50 unit per pixel


def test_solid_3d_target(prepared, sub, make):
    ctx = prepared
    s = ctx.scene.voodoo
    obj = make.solid_target()
    rest = np.array([v.co for v in obj.data.vertices])
    take_name = _track(ctx, obj)
    keys = obj.data.shape_keys.key_blocks
    assert len(keys) == 1 + sum(m.enabled for m in s.modes)
    # shapes deform the XZ plane only: depth (Y) is untouched
    for kb in keys[1:]:
        co = np.array([p.co for p in kb.data])
        assert np.abs(co[:, 1] - rest[:, 1]).max() < 1e-6
        assert np.abs(co[:, [0, 2]] - rest[:, [0, 2]]).max() > 1e-4
    frames = sub("operators.storage").stored_take(s.blob, take_name).frames
    ctx.scene.frame_set(int(frames[15]))
    predicted, _ = _prediction(sub, obj, 15)
    assert np.abs(_evaluated_world(obj) - predicted).max() < 1e-4 * np.abs(predicted).max()


def test_mode_subset_toggle_and_gain(prepared, sub, make):
    ctx = prepared
    s = ctx.scene.voodoo
    assert bpy.ops.voodoo.select_modes(preset="BENDING") == {"FINISHED"}
    bending = [m.name for m in s.modes if m.enabled]
    assert bending and all("bend" in n for n in bending)
    assert not (s.apply_location or s.apply_rotation or s.apply_scale)
    obj = make.flat_target(keyed=False)
    _track(ctx, obj)
    keys = obj.data.shape_keys.key_blocks
    assert [kb.name for kb in keys[1:]] == [f"Doll:{n}" for n in bending]
    # transform curves hold the rest pose with one key: no rigid motion reaches the target,
    # nothing freezes at the current frame's pose and no earlier layer shows through (the
    # tracking-quality curve is not motion and keeps every frame)
    from bpy_extras import anim_utils

    bag = anim_utils.action_get_channelbag_for_slot(
        obj.animation_data.action, obj.animation_data.action_slot
    )
    motion = [fc for fc in bag.fcurves if not fc.data_path.startswith('["')]
    assert len(motion) == 9 and all(len(fc.keyframe_points) == 1 for fc in motion)
    assert all(not fc.mute for fc in motion)
    # switching on a mode that was not applied writes it from the stored take, no tracking
    other = next(m for m in s.modes if not m.enabled)
    other.enabled = True
    kb = keys.get(f"Doll:{other.name}")
    assert kb is not None and not kb.mute
    key_bag = anim_utils.action_get_channelbag_for_slot(
        obj.data.shape_keys.animation_data.action, obj.data.shape_keys.animation_data.action_slot
    )
    fc = key_bag.fcurves.find(f'key_blocks["{kb.name}"].value')
    assert fc is not None and len(fc.keyframe_points) == 20 and not fc.mute
    # switching it off mutes both the key and its curve
    other.enabled = False
    assert kb.mute and fc.mute
    # gain scales the shape's offset
    mode = (
        s.modes[bending[0]]
        if bending[0] in s.modes
        else next(m for m in s.modes if m.name == bending[0])
    )
    basis = np.array([p.co for p in keys[0].data])
    before = np.array([p.co for p in keys[f"Doll:{mode.name}"].data]) - basis
    mode.gain = 2.0
    after = np.array([p.co for p in keys[f"Doll:{mode.name}"].data]) - basis
    assert np.allclose(after, 2.0 * before, atol=1e-6)
    # a rigid switch rewrites that part of the transform from the take; "All" restores all
    s.apply_rotation = True
    rotation = [fc for fc in bag.fcurves if fc.data_path.startswith("rotation")]
    assert rotation and all(len(fc.keyframe_points) == 20 for fc in rotation)
    assert bpy.ops.voodoo.select_modes(preset="ALL") == {"FINISHED"}
    assert s.apply_location and s.apply_rotation and s.apply_scale
    assert all(len(fc.keyframe_points) == 20 for fc in bag.fcurves)


def test_applying_again_updates_in_place_or_adds_a_layer(prepared, make):
    ctx = prepared
    obj = make.flat_target(keyed=False)
    _track(ctx, obj)
    first = obj.animation_data.action
    assert bpy.ops.voodoo.apply_take() == {"FINISHED"}
    assert obj.animation_data.action is first  # the same take's action, rewritten
    assert len(obj.animation_data.nla_tracks) == 0
    assert bpy.ops.voodoo.apply_take(new_layer=True) == {"FINISHED"}
    second = obj.animation_data.action
    assert second is not first
    assert first in [st.action for tr in obj.animation_data.nla_tracks for st in tr.strips]


def test_smoothing_uses_blenders_filter(prepared, sub, make):
    ctx = prepared
    obj = make.flat_target(keyed=False)
    _track(ctx, obj)
    from bpy_extras import anim_utils

    key = obj.data.shape_keys
    bag = anim_utils.action_get_channelbag_for_slot(
        key.animation_data.action, key.animation_data.action_slot
    )
    fc = bag.fcurves[0]
    before = np.array([k.co[1] for k in fc.keyframe_points])
    rng = np.random.default_rng(1)
    for k, jitter in zip(fc.keyframe_points, rng.normal(0, 0.3, len(before)), strict=True):
        k.co[1] += jitter
    noisy = np.array([k.co[1] for k in fc.keyframe_points])
    # The curves that read out how the take was tracked are measurements: left as they are.
    store = sub("operators.storage")
    obj_bag = anim_utils.action_get_channelbag_for_slot(
        obj.animation_data.action, obj.animation_data.action_slot
    )
    readouts = [obj_bag.fcurves.find(f'["{p}"]') for p in (store.QUALITY_PROP, store.IN_VIEW_PROP)]
    for curve in readouts:  # a jagged readout, which a filter would round off
        for i, k in enumerate(curve.keyframe_points):
            k.co[1] = float(i % 2)
    read = [[k.co[1] for k in curve.keyframe_points] for curve in readouts]
    assert bpy.ops.voodoo.smooth_take(cutoff=2.0) == {"FINISHED"}
    smooth = np.array([k.co[1] for k in fc.keyframe_points])
    assert len(smooth) == len(before)  # still ordinary, editable keys
    assert np.abs(np.diff(smooth, 2)).mean() < 0.5 * np.abs(np.diff(noisy, 2)).mean()
    assert [[k.co[1] for k in curve.keyframe_points] for curve in readouts] == read


def test_live_recorder_poses_a_stand_in(prepared, sub, make):
    """The modal operator's per-frame step, called directly (no event loop in bpy)."""
    ctx = prepared
    obj = make.flat_target(keyed=False)
    ctx.scene.voodoo.target = obj
    rec = sub("operators.recorder").Recorder(ctx, max_frames=6, live=True)
    names_during = set()
    while rec.step():
        names_during |= {o.name for o in ctx.scene.objects}
    assert f"{obj.name} (recording)" in names_during
    assert ctx.scene.frame_current == 6  # the scene follows the take
    info = rec.finish()
    assert info["frames"] == 6 and info["applied"]
    assert {o.name for o in ctx.scene.objects} == {obj.name}
    assert obj.visible_get()


def test_automatic_and_sketched_outlines(ctx, clip_file):
    clip = bpy.data.movieclips.load(str(clip_file["path"]))
    ctx.scene.active_clip = clip
    bpy.ops.voodoo.capture_frame()
    s = ctx.scene.voodoo
    # a click in the middle of the foam finds the whole foam block
    assert bpy.ops.voodoo.contour_auto(point=(160.0, 120.0)) == {"FINISHED"}
    pts = np.array([p.co for p in s.contour])
    x, y = pts[:, 0], pts[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    assert 8000 < area < 16000  # the foam ellipse (about 11.4k px), not the blob region
    # a scripted sketch replaces it, validated against the frame
    assert bpy.ops.voodoo.sketch_contour(coords="120 90, 200 90, 200 150, 120 150") == {"FINISHED"}
    assert {tuple(p.co) for p in s.contour} == {(120, 90), (120, 150), (200, 150), (200, 90)}
    with pytest.raises(RuntimeError, match="outside the 320x240 frame"):
        bpy.ops.voodoo.sketch_contour(coords="120 90, 400 90, 200 150")
    assert len(s.contour) == 4  # unchanged


def test_record_take_from_a_script_tracks_the_clip(prepared, make):
    ctx = prepared
    ctx.scene.voodoo.target = make.flat_target(keyed=False)
    # without an event loop the modal operator runs as the batch operator
    assert bpy.ops.voodoo.record_take() == {"FINISHED"}
    assert ctx.scene.voodoo.last_take == "Take"


def test_live_camera_take_is_time_stamped_and_saved(
    prepared, sub, make, clip_file, monkeypatch, tmp_path
):
    """A camera at 15 fps into a 30 fps scene: frames land on every other scene frame, the
    footage is kept as a clip. (No webcam here: a source that behaves like one stands in.)"""
    ctx = prepared
    engine_sources = sub("voodoo_addon.media.sources")
    recorder = sub("operators.recorder")

    class FakeCamera(engine_sources.ArraySource):
        live = True

        def read(self):
            frame = super().read()
            if frame is None:
                return None
            return engine_sources.Frame(frame.image, frame.index, frame.index / 15.0)

    monkeypatch.setattr(
        recorder, "open_source", lambda spec: FakeCamera(clip_file["frames"], fps=15.0)
    )
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "camera.blend"))  # footage goes beside it
    s = ctx.scene.voodoo
    s.source = "CAMERA"
    s.camera_seconds = 0.6  # 9 frames at 15 fps
    s.target = make.flat_target(keyed=False)
    ctx.scene.render.fps = 30
    ctx.scene.frame_set(10)
    rec = recorder.Recorder(ctx, live=False)
    while rec.step():
        pass
    info = rec.finish()
    assert info["frames"] == 9
    frames = sub("operators.storage").stored_take(s.blob, info["take"]).frames
    assert frames.tolist() == list(range(10, 28, 2))
    clip = info["clip"]
    assert clip.frame_start == 10 and clip.frame_duration == 9
    assert (tmp_path / "voodoo_footage" / f"{info['take']}.avi").exists()


def test_both_ways_on_a_camera_take_tracks_its_footage_backwards(
    prepared, sub, make, clip_file, monkeypatch, tmp_path
):
    """A camera at 60 fps into a 30 fps scene: the take keeps one camera frame per scene
    frame, the footage every one. Asked for both ways, the footage is tracked backwards
    over every frame, and the take, merged on its own rows, is stored and applied."""
    ctx = prepared
    _fast_camera(sub, monkeypatch, clip_file["frames"], fps=60.0)
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "camera_both.blend"))
    s = ctx.scene.voodoo
    s.source, s.camera_seconds = "CAMERA", 0.3  # 18 camera frames
    s.target = make.flat_target(keyed=False)
    ctx.scene.render.fps = 30
    rec = sub("operators.recorder").Recorder(ctx, live=False, both_ways=True)
    while rec.step(wait=True):
        pass
    tracked = [results["Doll"].iterations for *_, results in rec.rows]
    indices = [index for index, *_ in rec.rows]
    info = rec.finish()
    assert info["applied"] and not info["notes"], info["notes"]
    assert info["frames"] == len(tracked) < 18  # one row per scene frame...
    assert indices[-1] - indices[0] + 1 > len(indices)  # ...so the take skips frames
    take = sub("operators.storage").stored_take(s.blob, info["take"]).take
    assert take.frame_indices.tolist() == indices
    assert np.all(take.iterations >= tracked) and np.any(take.iterations > tracked)
    assert not take.lost.any() and np.isfinite(take.params).all()


def test_both_ways_on_a_camera_take_whose_footage_cannot_be_read_keeps_it_as_tracked(
    prepared, sub, make, clip_file, monkeypatch, tmp_path
):
    """The footage cannot be read again (here: a decoder that refuses it): the camera's
    take is kept as tracked (its own iterations, one pass), with a note saying so."""
    ctx = prepared
    recorder = sub("operators.recorder")
    _fast_camera(sub, monkeypatch, clip_file["frames"], fps=30.0)

    def unreadable(path):
        raise recorder.VoodooError(f"Cannot open {path} as a video (unknown format or codec).")

    monkeypatch.setattr(recorder, "CaptureSource", unreadable)
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "camera_unreadable.blend"))
    s = ctx.scene.voodoo
    s.source, s.camera_seconds = "CAMERA", 0.3
    s.target = make.flat_target(keyed=False)
    rec = recorder.Recorder(ctx, live=False, both_ways=True)
    while rec.step(wait=True):
        pass
    tracked = [results["Doll"].iterations for *_, results in rec.rows]
    info = rec.finish()
    assert info["frames"] == len(tracked) > 0 and info["applied"]
    assert any("kept as tracked forward" in n for n in info["notes"]), info["notes"]
    take = sub("operators.storage").stored_take(s.blob, info["take"]).take
    assert take.iterations.tolist() == tracked


def test_both_ways_stopped_with_escape_or_by_a_deleted_target_keeps_what_was_tracked(
    prepared, sub, make
):
    """Esc during Track Whole Clip: Both Ways keeps the frames tracked so far, tracked both
    ways; a target deleted mid-way ends the take, kept both ways and not applied."""
    from types import SimpleNamespace

    ctx = prepared
    store = sub("operators.storage")
    recorder = sub("operators.recorder")
    ctx.scene.voodoo.target = make.flat_target(keyed=False)
    op, _ = _modal_harness(sub, live=False, tick_seconds=0.0)
    op._recorder = rec = recorder.Recorder(ctx, live=False, both_ways=True)
    timer = SimpleNamespace(type="TIMER")
    for _ in range(4):
        assert op.modal(ctx, timer) == {"RUNNING_MODAL"}
    forward = [results["Doll"].iterations for *_, results in rec.rows]
    assert op.modal(ctx, SimpleNamespace(type="ESC")) == {"FINISHED"}
    take = store.stored_take(ctx.scene.voodoo.blob, rec.take_name).take
    assert len(take) == 4 and not take.lost.any()
    assert np.all(take.iterations > forward)  # the backward pass's work is in it

    rec = recorder.Recorder(ctx, live=False, both_ways=True)
    assert rec.step() and rec.step() and rec.step()
    bpy.data.objects.remove(bpy.data.objects["Flat"])
    assert rec.step() is False
    info = rec.finish()
    assert info["frames"] == 3 and not info["applied"]
    assert any("deleted during the take" in n for n in info["notes"])
    take = store.stored_take(ctx.scene.voodoo.blob, info["take"]).take
    assert len(take) == 3 and np.isfinite(take.params).all()


def _fast_camera(sub, monkeypatch, frames, fps):
    """A live source far faster than tracking: a frame every 5 ms, time-stamped as a camera
    at ``fps`` would, while every frame takes the tracker 15 ms more than it needs."""
    import time

    engine_sources = sub("voodoo_addon.media.sources")
    recorder = sub("operators.recorder")

    class FastCamera(engine_sources.ArraySource):
        live = True

        def read(self):
            time.sleep(0.005)
            frame = super().read()
            if frame is None:
                return None
            return engine_sources.Frame(frame.pixels, frame.index, frame.index / fps)

    class SlowTracker(recorder.Tracker):
        def track(self, frame):
            time.sleep(0.015)
            return super().track(frame)

    monkeypatch.setattr(recorder, "open_source", lambda spec: FastCamera(frames, fps=fps))
    monkeypatch.setattr(recorder, "Tracker", SlowTracker)


def test_a_live_take_behind_the_camera_still_tracks_every_frame(
    prepared, sub, make, clip_file, monkeypatch, tmp_path
):
    """The camera delivers frames several times faster than they are tracked: the live view
    falls behind and skips, the take holds all 60 frames, each tracked, in order."""
    ctx = prepared
    _fast_camera(sub, monkeypatch, clip_file["frames"] * 3, fps=30.0)  # 60 frames
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "fast.blend"))
    s = ctx.scene.voodoo
    s.source, s.camera_seconds = "CAMERA", 2.0  # 60 frames at 30 fps
    s.target = make.flat_target(keyed=False)
    ctx.scene.render.fps = 30
    ctx.scene.frame_set(1)
    rec = sub("operators.recorder").Recorder(ctx, live=True)
    most_behind, shown = 0, set()
    while rec.step(wait=True):
        most_behind = max(most_behind, rec.behind)
        shown.add(ctx.scene.frame_current)
    info = rec.finish()
    assert most_behind > 10  # the camera was far ahead of the tracker
    assert len(shown) < 60  # so the live view skipped frames...
    assert info["frames"] == 60  # ...and the take did not
    stored = sub("operators.storage").stored_take(s.blob, info["take"])
    assert stored.frames.tolist() == list(range(1, 61))
    assert stored.take.frame_indices.tolist() == list(range(60))
    assert not stored.take.lost.any() and np.isfinite(stored.take.params).all()
    assert info["clip"].frame_duration == 60  # and the footage holds every frame
    assert rec.rate > 0 and rec.latency > 0


def test_escape_stops_the_camera_then_tracks_what_it_recorded(
    prepared, sub, make, clip_file, monkeypatch, tmp_path
):
    """Esc while the camera runs ends the recording, not the take: the frames already
    recorded are tracked on the next ticks (progress shown), then the take is applied; a
    second Esc while completing keeps what is tracked and says what was not."""
    from types import SimpleNamespace

    ctx = prepared
    _fast_camera(sub, monkeypatch, clip_file["frames"] * 3, fps=30.0)
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "esc.blend"))
    s = ctx.scene.voodoo
    s.source, s.camera_seconds = "CAMERA", 2.0
    s.target = make.flat_target(keyed=False)
    ctx.scene.render.fps = 30  # a scene frame per camera frame
    timer, esc = SimpleNamespace(type="TIMER"), SimpleNamespace(type="ESC")

    def record_a_while():
        op, reports = _modal_harness(sub, live=True)
        rec = op._recorder = sub("operators.recorder").Recorder(ctx, live=True)
        while len(rec.rows) < 3:
            assert op.modal(ctx, timer) == {"RUNNING_MODAL"}
        assert rec.recording
        assert op.modal(ctx, esc) == {"RUNNING_MODAL"}  # the camera stops...
        while rec.recording:
            pass
        assert rec.behind > 0 and 0.0 < rec.progress < 1.0  # ...frames wait to be tracked
        return op, rec, reports

    op, rec, reports = record_a_while()
    recorded = len(rec.rows) + rec.behind
    assert recorded < 60  # stopped before the end
    while (out := op.modal(ctx, timer)) == {"RUNNING_MODAL"}:
        pass
    assert out == {"FINISHED"}
    assert len(sub("operators.storage").stored_take(s.blob, s.last_take).take) == recorded
    assert any("applied as action" in m for _, m in reports)
    # Esc again while completing: what is tracked is kept, the rest is named
    s.take_name = "Second"
    op, rec, reports = record_a_while()
    left = rec.behind
    assert op.modal(ctx, esc) == {"FINISHED"}
    assert len(sub("operators.storage").stored_take(s.blob, "Second").take) == len(rec.rows)
    assert any(f"{left} recorded frame(s) were not tracked" in m for _, m in reports)


def _modal_harness(sub, live, tick_seconds=0.0):
    """The take operators' modal mechanics on a stand-in for the operator instance (the bpy
    module has no event loop to run the real one)."""
    take_loop = sub("operators.ops.take_loop")
    reports = []

    class Harness(take_loop.TakeLoop):
        bl_label = "Take"

        def report(self, kind, message):
            reports.append((tuple(kind), message))

    op = Harness()
    op.live, op.tick_seconds = live, tick_seconds
    return op, reports


def test_modal_recording_steps_on_timer_and_keeps_the_take_on_escape(prepared, sub, make):
    """Drive the modal loop with the events Blender would send."""
    from types import SimpleNamespace

    ctx = prepared
    ctx.scene.voodoo.target = make.flat_target(keyed=False)
    op, reports = _modal_harness(sub, live=True)
    op._recorder = sub("operators.recorder").Recorder(ctx, live=True)
    timer = SimpleNamespace(type="TIMER")
    assert op.modal(ctx, SimpleNamespace(type="MOUSEMOVE")) == {"PASS_THROUGH"}
    for _ in range(5):
        assert op.modal(ctx, timer) == {"RUNNING_MODAL"}
    assert len(op._recorder.rows) == 5
    assert op.modal(ctx, SimpleNamespace(type="ESC")) == {"FINISHED"}
    take = ctx.scene.voodoo.last_take
    assert take == "Take"
    stored = sub("operators.storage").stored_take(ctx.scene.voodoo.blob, take).take
    assert len(stored) == 5  # what was recorded before Esc is kept, and applied
    assert any("applied as action" in m for _, m in reports)
    assert ctx.scene.voodoo.target.animation_data.action.name == "Take"


def test_track_whole_clip_runs_in_ticks_and_stops_on_escape(prepared, sub, make):
    """Track Whole Clip tracks several frames per timer tick and keeps the take on Esc."""
    from types import SimpleNamespace

    ctx = prepared
    ctx.scene.voodoo.target = make.flat_target(keyed=False)
    op, reports = _modal_harness(sub, live=False, tick_seconds=0.0)
    op._recorder = sub("operators.recorder").Recorder(ctx, live=False)
    timer = SimpleNamespace(type="TIMER")
    for _ in range(3):
        assert op.modal(ctx, timer) == {"RUNNING_MODAL"}
    assert op._recorder.progress == pytest.approx(3 / 20)
    assert op.modal(ctx, SimpleNamespace(type="ESC")) == {"FINISHED"}
    stored = sub("operators.storage").stored_take(ctx.scene.voodoo.blob, "Take")
    assert len(stored.take) == 3
    # a long tick tracks the rest of the clip in one go
    op, _ = _modal_harness(sub, live=False, tick_seconds=60.0)
    op._recorder = sub("operators.recorder").Recorder(ctx, live=False)
    assert op.modal(ctx, timer) == {"FINISHED"}
    assert len(sub("operators.storage").stored_take(ctx.scene.voodoo.blob, "Take.002").take) == 20
