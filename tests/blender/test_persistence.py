"""Blobs and takes live in the .blend: save, reopen, and keep tracking."""

import bpy
import numpy as np


def test_blob_and_take_survive_save_and_reload(prepared, sub, make, tmp_path):
    ctx = prepared
    s = ctx.scene.voodoo
    store = sub("operators.store")
    obj = make.flat_target(keyed=False)
    s.target = obj
    assert bpy.ops.voodoo.track_clip(max_frames=10) == {"FINISHED"}
    blob = store.load_blob(s.blob)
    take = store.load_take(s.blob, s.last_take)
    labels = [m.name for m in s.modes]
    path = tmp_path / "doll.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))

    bpy.ops.wm.read_homefile(use_empty=True)
    assert bpy.context.scene.voodoo.blob is None
    bpy.ops.wm.open_mainfile(filepath=str(path))
    s = bpy.context.scene.voodoo
    store._cache.clear()  # really parse what was saved
    again = store.load_blob(s.blob)
    for name in ("vertices", "triangles", "modes", "texture", "pixel_weights", "labels", "mass"):
        np.testing.assert_array_equal(getattr(again, name), getattr(blob, name))
    took = store.load_take(s.blob, s.last_take)
    np.testing.assert_array_equal(took.params, take.params)
    np.testing.assert_array_equal(took.vertices, take.vertices)
    assert [m.name for m in s.modes] == labels
    obj = bpy.data.objects["Flat"]
    assert obj.animation_data.action.name.startswith(s.last_take)
    assert len(obj.data.shape_keys.key_blocks) == 1 + len(labels)
    assert s.capture_image is not None and s.capture_image.packed_file is not None

    # tracking continues where the take ended, from its last pose
    first = s.last_take
    assert bpy.ops.voodoo.track_clip(resume=True) == {"FINISHED"}
    cont = store.load_take(s.blob, s.last_take)
    assert s.last_take != first
    assert cont.frame_indices[0] == take.frame_indices[-1] + 1
    assert cont.frame_indices[-1] == 19 and not cont.lost.any()
    # ... landing where an uninterrupted take is
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    full = store.load_take(s.blob, s.last_take)
    row = {int(f): i for i, f in enumerate(full.frame_indices)}
    for i, f in enumerate(cont.frame_indices):
        err = np.linalg.norm(cont.vertices[i] - full.vertices[row[int(f)]], axis=1).mean()
        assert err < 0.1
