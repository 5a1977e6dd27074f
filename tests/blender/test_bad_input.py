"""Bad input gets a clear report and leaves the scene as it was."""

import shutil

import bpy
import numpy as np
import pytest


def _snapshot():
    """What must not change: datablocks, actions, shape keys, animation assignments."""
    objects = {}
    for o in bpy.data.objects:
        ad = o.animation_data
        keys = o.data.shape_keys if o.type == "MESH" else None
        objects[o.name] = (
            ad.action.name if ad and ad.action else None,
            len(ad.nla_tracks) if ad else 0,
            [kb.name for kb in keys.key_blocks] if keys else [],
            tuple(o.location),
        )
    return {
        "objects": objects,
        "actions": sorted(a.name for a in bpy.data.actions),
        "images": sorted(i.name for i in bpy.data.images),
        "meshes": sorted(m.name for m in bpy.data.meshes),
        "contour": [tuple(p.co) for p in bpy.context.scene.voodoo.contour],
        "takes": bpy.context.scene.voodoo.last_take,
    }


def test_capture_without_clip(ctx):
    before = _snapshot()
    with pytest.raises(RuntimeError, match="Open a movie clip"):
        bpy.ops.voodoo.capture_frame()
    assert _snapshot() == before


def test_camera_that_is_not_there(ctx):
    ctx.scene.voodoo.source = "CAMERA"
    ctx.scene.voodoo.camera_index = 63
    before = _snapshot()
    with pytest.raises(RuntimeError, match="No camera at index 63"):
        bpy.ops.voodoo.capture_frame()
    assert _snapshot() == before


def test_unreadable_clip(ctx, clip_file, tmp_path):
    path = tmp_path / "broken.avi"
    shutil.copy(clip_file["path"], path)
    clip = bpy.data.movieclips.load(str(path))
    ctx.scene.active_clip = clip
    path.write_bytes(b"this is not a video" * 100)
    before = _snapshot()
    with pytest.raises(RuntimeError, match="Cannot open .* as a video"):
        bpy.ops.voodoo.capture_frame()
    path.unlink()
    with pytest.raises(RuntimeError, match="missing"):
        bpy.ops.voodoo.capture_frame()
    assert _snapshot() == before


def test_no_mask(prepared):
    before = _snapshot()
    bpy.data.masks.remove(bpy.data.masks[0])
    with pytest.raises(RuntimeError, match="No mask"):
        bpy.ops.voodoo.contour_from_mask()
    assert _snapshot() == before


def test_self_intersecting_mask(prepared, make):
    before = _snapshot()
    bowtie = [(100, 80), (200, 160), (200, 80), (100, 160)]
    make.add_mask(bowtie, (320, 240), name="Bowtie")
    with pytest.raises(RuntimeError, match="crosses itself"):
        bpy.ops.voodoo.contour_from_mask(mask="Bowtie")
    assert _snapshot()["contour"] == before["contour"]


def test_build_without_outline(ctx, clip_file):
    clip = bpy.data.movieclips.load(str(clip_file["path"]))
    ctx.scene.active_clip = clip
    bpy.ops.voodoo.capture_frame()
    before = _snapshot()
    with pytest.raises(RuntimeError, match="Outline the object first"):
        bpy.ops.voodoo.build_blob()
    assert _snapshot() == before


@pytest.mark.parametrize("kind", ["camera", "empty", "no-vertices"])
def test_target_that_is_not_a_usable_mesh(prepared, kind):
    ctx = prepared
    if kind == "camera":
        obj = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    elif kind == "empty":
        obj = bpy.data.objects.new("Empty", None)
    else:
        obj = bpy.data.objects.new("Hollow", bpy.data.meshes.new("Hollow"))
    ctx.scene.collection.objects.link(obj)
    ctx.scene.voodoo["target"] = obj  # scripts can bypass the panel's mesh filter
    before = _snapshot()
    with pytest.raises(RuntimeError, match="not a mesh|no vertices"):
        bpy.ops.voodoo.track_clip()
    assert _snapshot() == before


def test_target_flat_in_the_chosen_plane(prepared, make):
    ctx = prepared
    obj = make.flat_target(keyed=False)  # lies in XZ
    ctx.scene.voodoo.target = obj
    ctx.scene.voodoo.axes = "XY"
    before = _snapshot()
    with pytest.raises(RuntimeError, match="flat in the XY plane"):
        bpy.ops.voodoo.track_clip()
    assert _snapshot() == before


def test_target_deleted_during_a_take(prepared, sub, make):
    """The take ends and is kept; the stand-in goes; nothing is animated."""
    ctx = prepared
    obj = make.flat_target()
    ctx.scene.voodoo.target = obj
    before = _snapshot()
    rec = sub("operators.recorder").Recorder(ctx, live=True)
    assert rec.step() and rec.step()
    bpy.data.objects.remove(bpy.data.objects["Flat"])
    assert rec.step() is False
    info = rec.finish()
    assert info["frames"] == 2 and not info["applied"]
    assert any("deleted during the take" in n for n in info["notes"])
    assert len(sub("operators.storage").stored_take(ctx.scene.voodoo.blob, info["take"]).take) == 2
    after = _snapshot()
    del before["objects"]["Flat"]
    assert after["objects"] == before["objects"]  # the stand-in is gone too
    assert after["actions"] == before["actions"]


def test_stand_in_deleted_during_a_take(prepared, sub, make):
    """Deleting the "(recording)" stand-in ends the live preview only: every frame is kept,
    the target comes back into view and is animated."""
    ctx = prepared
    obj = make.flat_target(keyed=False)
    ctx.scene.voodoo.target = obj
    rec = sub("operators.recorder").Recorder(ctx, max_frames=8, live=True)
    assert rec.step() and rec.step()
    bpy.data.objects.remove(bpy.data.objects["Flat (recording)"])
    while rec.step():
        pass
    info = rec.finish()
    assert info["frames"] == 8 and info["applied"]
    assert any("stand-in was deleted" in n for n in info["notes"])
    assert obj.visible_get()
    assert obj.animation_data.action.name == info["take"]


def test_clip_that_does_not_match_the_blob(prepared, tmp_path):
    """A clip of another size than the blob's capture frame is refused before tracking."""
    from voodoo_addon.devtools.scenarios import scenario_take
    from voodoo_addon.devtools.synthetic import write_frames

    frames, _, _ = scenario_take("bend", frames=4, size=(256, 192))
    path = tmp_path / "other.avi"
    write_frames(path, frames)
    ctx = prepared
    ctx.scene.active_clip = bpy.data.movieclips.load(str(path))
    before = _snapshot()
    with pytest.raises(RuntimeError, match="256x192 but the blob was built on a 320x240"):
        bpy.ops.voodoo.track_clip()
    assert _snapshot() == before


def test_apply_without_take(prepared, make):
    ctx = prepared
    ctx.scene.voodoo.target = make.flat_target()
    before = _snapshot()
    with pytest.raises(RuntimeError, match="Record a take first"):
        bpy.ops.voodoo.apply_take()
    assert _snapshot() == before


def test_lost_frames_are_not_keyed(ctx, make, exit_clip):
    """A take where the doll leaves the picture: those frames get no keys and are reported."""
    make.prepare(exit_clip)
    obj = make.flat_target(keyed=False)
    ctx.scene.voodoo.target = obj
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    from bpy_extras import anim_utils

    key = obj.data.shape_keys
    bag = anim_utils.action_get_channelbag_for_slot(
        key.animation_data.action, key.animation_data.action_slot
    )
    keyed = {int(round(k.co[0])) for k in bag.fcurves[0].keyframe_points}
    assert 0 < len(keyed) < 24
    for f in keyed:
        vals = [fc.evaluate(f) for fc in bag.fcurves]
        assert np.isfinite(vals).all()


def test_outline_off_the_frame(prepared, make):
    """A mask drawn mostly outside the picture: clipped to the frame or refused, never a
    blob with pixels that do not exist."""
    before = _snapshot()
    make.add_mask([(250, 150), (600, 150), (600, 500), (250, 500)], (320, 240), name="Off")
    try:
        bpy.ops.voodoo.contour_from_mask(mask="Off")
    except RuntimeError as exc:
        assert "frame" in str(exc) or "picture" in str(exc)
        assert _snapshot()["contour"] == before["contour"]
        return
    points = np.array([p.co for p in bpy.context.scene.voodoo.contour])
    assert (points >= 0).all() and (points[:, 0] <= 320).all() and (points[:, 1] <= 240).all()


@pytest.mark.parametrize("damage", ["truncated", "garbage"])
def test_damaged_blob_in_the_file(prepared, sub, make, damage):
    """A blob whose stored bytes were damaged says so; nothing is tracked or changed."""
    store = sub("operators.storage")
    blob = prepared.scene.voodoo.blob
    raw = bytes(blob[store.BLOB_KEY])
    blob[store.BLOB_KEY] = raw[: len(raw) // 2] if damage == "truncated" else b"\x00junk" * 50
    blob[store.BLOB_ID_KEY] = "damaged"  # what a file from elsewhere would carry
    prepared.scene.voodoo.target = make.flat_target()
    before = _snapshot()
    with pytest.raises(RuntimeError, match="Blob 'Doll'"):
        bpy.ops.voodoo.track_clip()
    assert _snapshot() == before
