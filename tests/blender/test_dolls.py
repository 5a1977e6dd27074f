"""Several dolls in one scene: listed, each with its own outline, blob, modes and target.

The panels work on the doll selected in the list; choosing another doll keeps the first
one's settings and shows the other's. Adding, renaming and removing are undoable.
"""

import json
from pathlib import Path

import bpy
import numpy as np
import pytest


def _outline(s):
    return np.array([p.co[:] for p in s.contour])


def _second_doll(s, clip_file, make):
    """Add a doll and build its blob on a smaller outline of the same clip."""
    assert bpy.ops.voodoo.add_doll(name="Tail") == {"FINISHED"}
    contour = np.asarray(clip_file["contour"], float)
    centre = contour.mean(axis=0)
    small = centre + 0.6 * (contour - centre)
    make.add_mask(small, tuple(bpy.context.scene.active_clip.size), name="Tail outline")
    assert bpy.ops.voodoo.contour_from_mask(mask="Tail outline") == {"FINISHED"}
    assert bpy.ops.voodoo.build_blob(name="Tail") == {"FINISHED"}
    return small


def test_each_doll_keeps_its_own_outline_blob_modes_and_target(prepared, clip_file, make, sub):
    s = prepared.scene.voodoo
    first_blob, first_outline = s.blob, _outline(s)
    s.modes[0].gain = 2.0
    s.modes[1].enabled = False
    flat = make.flat_target(keyed=False)
    s.target = flat
    s.axes = "XY"
    assert len(s.dolls) == 0  # one doll: the scene's own settings
    _second_doll(s, clip_file, make)
    # the scene's doll became the first of the list, named after its blob; the new one shows
    assert [d.name for d in s.dolls] == ["Doll", "Tail"]
    assert s.active_doll == s.shown_doll == 1
    assert s.blob.name == "Tail" and s.target is None and s.axes == "XZ"
    assert all(m.gain == 1.0 and m.enabled for m in s.modes)
    box = make.solid_target("Box")
    s.target = box
    # back to the first doll: everything as it was left
    s.active_doll = 0
    assert s.blob == first_blob and s.target == flat and s.axes == "XY"
    np.testing.assert_allclose(_outline(s), first_outline)
    assert s.modes[0].gain == 2.0 and not s.modes[1].enabled
    # and to the second again
    s.active_doll = 1
    assert s.blob.name == "Tail" and s.target == box
    # the blob of the doll not shown is in use: Remove Unused Blobs keeps it
    store = sub("operators.storage")
    assert store.blob_users(first_blob)
    assert bpy.ops.voodoo.remove_unused_blobs() in ({"FINISHED"}, {"CANCELLED"})
    assert first_blob.name in bpy.data.meshes
    dolls = sub("operators.dolls")
    names = [(n, d.blob.name) for n, d in dolls.doll_settings(s)]
    assert names == [("Doll", "Doll"), ("Tail", "Tail")]


def test_adding_renaming_and_removing_dolls_undo_in_one_step(prepared, clip_file, make):
    s = prepared.scene.voodoo
    bpy.ops.ed.undo_push(message="prepared")
    assert bpy.ops.voodoo.add_doll("EXEC_DEFAULT", True, name="Tail") == {"FINISHED"}
    s = bpy.context.scene.voodoo
    assert len(s.dolls) == 2
    assert bpy.ops.ed.undo() == {"FINISHED"}
    s = bpy.context.scene.voodoo
    assert len(s.dolls) == 0 and s.blob is not None and s.blob.name == "Doll"
    assert bpy.ops.ed.redo() == {"FINISHED"}
    s = bpy.context.scene.voodoo
    assert [d.name for d in s.dolls] == ["Doll", "Tail"]
    # a second doll of the same name gets a number
    assert bpy.ops.voodoo.add_doll(name="Tail") == {"FINISHED"}
    assert [d.name for d in s.dolls] == ["Doll", "Tail", "Tail 2"]
    s.dolls[2].name = "Paw"
    assert s.dolls[2].name == "Paw"
    # removing the one shown shows the next; the last doll cannot go
    s.active_doll = 1
    bpy.ops.ed.undo_push(message="three dolls")
    assert bpy.ops.voodoo.remove_doll("EXEC_DEFAULT", True) == {"FINISHED"}
    s = bpy.context.scene.voodoo
    assert [d.name for d in s.dolls] == ["Doll", "Paw"] and s.shown_doll == 1
    assert bpy.ops.ed.undo() == {"FINISHED"}
    assert [d.name for d in bpy.context.scene.voodoo.dolls] == ["Doll", "Tail", "Paw"]
    s = bpy.context.scene.voodoo
    assert bpy.ops.voodoo.remove_doll() == {"FINISHED"}
    assert bpy.ops.voodoo.remove_doll() == {"FINISHED"}
    assert len(s.dolls) == 1
    assert not bpy.ops.voodoo.remove_doll.poll()


def test_dolls_survive_save_and_reload(prepared, clip_file, make, tmp_path):
    s = prepared.scene.voodoo
    _second_doll(s, clip_file, make)
    s.active_doll = 0
    path = tmp_path / "dolls.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(path))
    s = bpy.context.scene.voodoo
    assert [d.name for d in s.dolls] == ["Doll", "Tail"] and s.shown_doll == 0
    assert s.blob.name == "Doll"
    s.active_doll = 1
    assert s.blob.name == "Tail" and len(s.modes) > 0


MULTI = Path(__file__).resolve().parents[2] / "samples" / "multi"


def _two_dolls_scene(make):
    """The two_dolls render, each sheet outlined and built as its own doll, two targets."""
    scene = bpy.context.scene
    clip = bpy.data.movieclips.load(str(MULTI / "two_dolls.mp4"))
    scene.active_clip = clip
    scene.frame_set(clip.frame_start)
    assert bpy.ops.voodoo.capture_frame() == {"FINISHED"}
    s = scene.voodoo
    targets = {}
    for i, name in enumerate(("left", "right")):
        if i:
            assert bpy.ops.voodoo.add_doll(name=name) == {"FINISHED"}
        points = json.loads((MULTI / f"two_dolls.{name}.json").read_text())["points"]
        make.add_mask(points, tuple(clip.size), name=f"{name} outline")
        assert bpy.ops.voodoo.contour_from_mask(mask=f"{name} outline") == {"FINISHED"}
        assert bpy.ops.voodoo.build_blob(name=name) == {"FINISHED"}
        targets[name] = s.target = make.flat_target(name=f"{name} puppet", keyed=False)
    return s, targets


def test_one_take_tracks_both_dolls_and_drives_two_characters(ctx, make, sub):
    s, targets = _two_dolls_scene(make)
    assert [d.name for d in s.dolls] == ["left", "right"]
    s.take_name = "Duet"
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    store = sub("operators.storage")
    for name, target in targets.items():
        blob = bpy.data.meshes[name]
        stored = store.stored_take(blob, "Duet")
        assert len(stored.take) == 144 and not stored.take.lost.any()
        action = target.animation_data.action
        assert action.name == f"Duet {name}"  # its own action, named after take and doll
        assert target.data.shape_keys.animation_data.action is action
    # the left sheet is partly covered by the right one mid-take: covered, not lost
    left = store.stored_take(bpy.data.meshes["left"], "Duet").take
    assert left.visible[85].mean() < 0.8 and left.visible[-1].all()
    # re-applying the doll shown rewrites its own action in place
    s.active_doll = 0
    assert bpy.ops.voodoo.apply_take(take="Duet") == {"FINISHED"}
    assert targets["left"].animation_data.action.name == "Duet left"
    assert len([a for a in bpy.data.actions if a.name.startswith("Duet")]) == 2


def test_a_take_of_two_dolls_is_journalled_and_recovered_for_both(ctx, make, sub):
    s, targets = _two_dolls_scene(make)
    s.take_name = "Cut"
    recorder = sub("operators.recorder")
    rec = recorder.Recorder(bpy.context, max_frames=30, live=True)
    for _ in range(6):
        assert rec.step()
    rec.close()  # as if Blender went away: nothing stored, the journals stay on disk
    found = recorder.interrupted_takes()
    assert sorted(m.name for _, m in found) == ["left", "right"]
    assert bpy.ops.voodoo.recover_takes() == {"FINISHED"}
    store = sub("operators.storage")
    for name in ("left", "right"):
        assert len(store.stored_take(bpy.data.meshes[name], "Cut").take) == 6
    assert recorder.interrupted_takes() == []


def test_two_dolls_that_clash_are_refused_before_anything_changes(ctx, make, sub):
    s, targets = _two_dolls_scene(make)
    s.target = targets["left"]  # the right doll (shown) takes the left one's target
    with pytest.raises(RuntimeError, match="same target 'left puppet'"):
        bpy.ops.voodoo.track_clip()
    s.target = targets["right"]
    s.dolls[0].name = "right"
    with pytest.raises(RuntimeError, match="Two dolls are named 'right'"):
        bpy.ops.voodoo.track_clip()
    s.dolls[0].name = "left"
    assert not any(t.animation_data and t.animation_data.action for t in targets.values())
    assert sub("operators.recorder").interrupted_takes() == []


def test_a_take_of_two_dolls_resumes_for_both(ctx, make, sub):
    s, targets = _two_dolls_scene(make)
    s.take_name = "Long"
    recorder = sub("operators.recorder")
    rec = recorder.Recorder(bpy.context, max_frames=40, live=False)
    while rec.step():
        pass
    assert rec.finish()["take"] == "Long"
    # no doll can be removed while a take records
    rec2 = recorder.Recorder(bpy.context, max_frames=5, live=False, resume="Long")
    with pytest.raises(RuntimeError, match="being recorded"):
        bpy.ops.voodoo.remove_doll()
    rec2.close()
    for path, _ in recorder.interrupted_takes():  # that recording is dropped
        path.unlink()
    assert bpy.ops.voodoo.track_clip(resume=True) == {"FINISHED"}
    store = sub("operators.storage")
    for name in ("left", "right"):
        take = store.stored_take(bpy.data.meshes[name], "Long").take
        assert len(take) == 144 and take.frame_indices.tolist() == list(range(144))


def test_outlines_that_overlap_are_refused_before_recording(ctx, make):
    s, targets = _two_dolls_scene(make)
    left = [tuple(p.co) for p in s.dolls[0].contour]
    s.contour.clear()
    for x, y in left:  # the right doll outlined over the left one
        s.contour.add().co = (x + 20, y)
    assert bpy.ops.voodoo.build_blob(name="right") == {"FINISHED"}
    with pytest.raises(RuntimeError, match="'left' and 'right' overlap"):
        bpy.ops.voodoo.track_clip()


def test_recording_two_dolls_streams_each_under_its_name(ctx, make, sub, osc_receiver):
    s, targets = _two_dolls_scene(make)
    rx = osc_receiver()
    s.osc_send, s.osc_target = True, f"127.0.0.1:{rx.port}"
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    frames = {}
    for dgram in rx.close():
        msgs = dict(rx.messages(dgram))
        (address,) = [a for a in msgs if a.endswith("/frame")]
        frames.setdefault(address.split("/")[2], []).append(msgs[address][0])
    store = sub("operators.storage")
    for name in ("left", "right"):
        take = store.stored_take(bpy.data.meshes[name], s.last_take).take
        assert frames[name] == take.frame_indices.tolist()
