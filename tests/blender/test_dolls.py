"""Several dolls in one scene: listed, each with its own outline, blob, modes and target.

The panels work on the doll selected in the list; choosing another doll keeps the first
one's settings and shows the other's. Adding, renaming and removing are undoable.
"""

import bpy
import numpy as np


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
