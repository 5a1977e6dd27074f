"""Everything the add-on keeps in the .blend; every key is spelled here and nowhere else.

Format version 2 (``FORMAT_VERSION``):

- A blob is a Mesh datablock (kept by a fake user) whose geometry is the blob's triangle mesh
  (see ``pixels.pixels_to_display``, for looking at). ``["voodoo_blob"]`` holds the engine's
  pickle-free ``.npz`` bytes (the exact blob, surviving save and reload), ``["voodoo_blob_id"]``
  a fresh id per stored blob, ``["voodoo_format"]`` this format's version.
- Takes recorded with a blob live beside it: ``["voodoo_takes"][name]`` is a group with
  ``take`` (the engine's take bytes), ``frames`` (the scene frame of every row) and
  ``rest_frame`` (the scene frame the blob was captured on; the target's rest pose is read
  there). Version 1 kept the bytes directly under the name and the frames under
  ``["voodoo_take_frames"][name]``; it is still read.
- A target driven by a take carries ``["voodoo"]`` (see :class:`TargetLink`) and a
  ``["voodoo_quality"]`` property whose F-curve is the take's tracking quality, and a
  ``["voodoo_in_view"]`` property whose F-curve is the share of the doll in view.
- The action written for a take carries ``["voodoo_take"]`` and ``["voodoo_blob"]``.
- Takes being recorded are journalled to ``voodoo_recovery/`` beside the .blend (or in the
  system's temporary folder for an unsaved file) until they are stored, so a crash loses
  at most a few seconds of them.
"""

import tempfile
import uuid
import zlib
from dataclasses import dataclass
from pathlib import Path

import bpy
import numpy as np

from ..voodoo_addon.blob.model import ActiveBlob, blob_from_bytes, blob_to_bytes
from ..voodoo_addon.errors import VoodooError
from ..voodoo_addon.takes.journal import journals_in, read_journal, read_journal_header
from ..voodoo_addon.takes.take import Take, take_from_bytes, take_to_bytes
from .pixels import pixels_to_display

FORMAT_VERSION = 2
FORMAT_KEY = "voodoo_format"
BLOB_KEY = "voodoo_blob"
BLOB_ID_KEY = "voodoo_blob_id"
TAKES_KEY = "voodoo_takes"
#: Version 1 only: scene frames of each take, by take name.
V1_FRAMES_KEY = "voodoo_take_frames"
LINK_KEY = "voodoo"
QUALITY_PROP = "voodoo_quality"
IN_VIEW_PROP = "voodoo_in_view"
ACTION_TAKE_KEY = "voodoo_take"
ACTION_BLOB_KEY = "voodoo_blob"
#: On a target's shape keys (the Key): the gain each mode's shape was written with.
SHAPE_GAIN_KEY = "voodoo_gain"
RECOVERY_DIR = "voodoo_recovery"
#: Camera footage and camera captures are saved here, beside the .blend.
FOOTAGE_DIR = "voodoo_footage"
_cache: dict = {}
#: The takes the overlay shows, parsed once: (blob mesh's session uid, take name) ->
#: (checksum of the stored bytes, StoredTake); see :func:`shown_take`.
_shown: dict = {}


# ---------------------------------------------------------------------------- blobs


def is_blob(mesh) -> bool:
    try:
        return mesh is not None and BLOB_KEY in mesh
    except ReferenceError:
        return False


def blob_meshes() -> list:
    """Every blob in the file."""
    return [m for m in bpy.data.meshes if BLOB_KEY in m]


def blob_id(mesh) -> str:
    return str(mesh.get(BLOB_ID_KEY, ""))


def store_blob(name: str, blob: ActiveBlob) -> bpy.types.Mesh:
    """A new blob mesh datablock holding ``blob``."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(pixels_to_display(blob.vertices).tolist(), [], blob.triangles.tolist())
    mesh.update()
    mesh[BLOB_KEY] = blob_to_bytes(blob)
    mesh[BLOB_ID_KEY] = uuid.uuid4().hex
    mesh[FORMAT_KEY] = FORMAT_VERSION
    mesh.use_fake_user = True
    return mesh


def stored_blob(mesh) -> ActiveBlob:
    """The blob stored on a mesh.

    Parsed once per mesh and stored blob: the overlay asks for it on every redraw.
    """
    if not is_blob(mesh):
        raise VoodooError("No blob is built yet: capture a frame, outline it, then Build Blob.")
    key = (mesh.session_uid, mesh.get(BLOB_ID_KEY))
    blob = _cache.get(key) if key[1] is not None else None
    if blob is None:
        blob = blob_from_bytes(bytes(mesh[BLOB_KEY]), source=f"Blob {mesh.name!r}")
        _cache.clear()
        _cache[key] = blob
    return blob


def blob_users(mesh) -> list:
    """What keeps a blob in use: scenes that have it as their blob, objects its takes drive."""
    from .dolls import blobs_in_use

    users = [f"scene {s.name!r}" for s in bpy.data.scenes if mesh in blobs_in_use(s)]
    users += [f"object {o.name!r}" for o in bpy.data.objects if linked_to(o, mesh)]
    return users


def blob_bytes(mesh) -> int:
    """Bytes a blob and its takes add to the .blend."""
    size = len(mesh[BLOB_KEY]) if is_blob(mesh) else 0
    for name in take_names(mesh):
        record = mesh[TAKES_KEY][name]
        data = record if isinstance(record, (bytes, str)) else record.get("take", b"")
        size += len(data)
    return size


def remove_blob(mesh) -> None:
    bpy.data.meshes.remove(mesh)


# ---------------------------------------------------------------------------- takes


@dataclass(frozen=True)
class StoredTake:
    """A take kept with its blob, with the scene frames it was recorded on."""

    name: str
    take: Take
    frames: np.ndarray
    rest_frame: int | None


def store_take(mesh, name: str, take: Take, frames, rest_frame: int | None) -> None:
    """Keep a take with its blob (replacing one of the same name)."""
    frames = [int(f) for f in frames]
    if len(frames) != len(take):
        raise VoodooError(f"Take {name!r}: {len(frames)} scene frames for {len(take)} rows.")
    takes = mesh.get(TAKES_KEY)
    if takes is None:
        mesh[TAKES_KEY] = {}
        takes = mesh[TAKES_KEY]
    record = {"take": take_to_bytes(take), "frames": frames}
    if rest_frame is not None:
        record["rest_frame"] = int(rest_frame)
    takes[name] = record
    old = mesh.get(V1_FRAMES_KEY)
    if old is not None and name in old:
        del old[name]
    mesh[FORMAT_KEY] = FORMAT_VERSION


def take_names(mesh) -> list:
    if not is_blob(mesh) or TAKES_KEY not in mesh:
        return []
    return list(mesh[TAKES_KEY].keys())


def stored_take(mesh, name: str) -> StoredTake:
    """A take stored with a blob, in either format version."""
    return _parsed(name, *_take_record(mesh, name))


def _parsed(name: str, data: bytes, frames, rest) -> StoredTake:
    """The take ``name`` from its stored record (see :func:`_take_record`)."""
    take = take_from_bytes(data, source=f"Take {name!r}")
    if frames is None or len(frames) != len(take):
        raise VoodooError(f"Take {name!r} has no frame numbers; record it again.")
    return StoredTake(name, take, np.asarray(frames, dtype=np.int64), rest)


def _take_record(mesh, name: str):
    """(the take's bytes, its scene frames or None, its rest frame or None), either version."""
    takes = mesh.get(TAKES_KEY) if is_blob(mesh) else None
    if takes is None or name not in takes:
        raise VoodooError(f"There is no take named {name!r}; record one first.")
    record = takes[name]
    if isinstance(record, (bytes, str)):  # version 1
        data, frames, rest = record, mesh.get(V1_FRAMES_KEY, {}).get(name), None
    else:
        data, frames, rest = record.get("take"), record.get("frames"), record.get("rest_frame")
    if data is None:
        raise VoodooError(f"Take {name!r} is damaged (its data is missing); record it again.")
    data = data.encode("latin-1") if isinstance(data, str) else bytes(data)
    return data, frames, rest


def shown_take(mesh, name: str) -> StoredTake | None:
    """:func:`stored_take`, or None where there is none (or it cannot be read).

    Parsed again only when the stored bytes changed: the overlay asks for it on every
    redraw.
    """
    try:
        record = _take_record(mesh, name)
    except VoodooError:
        return None
    key, check = (mesh.session_uid, name), zlib.crc32(record[0])
    kept = _shown.get(key)
    if kept is not None and kept[0] == check:
        return kept[1]
    try:
        stored = _parsed(name, *record)
    except VoodooError:
        return None
    if len(_shown) > 16:
        _shown.clear()
    _shown[key] = (check, stored)
    return stored


def unique_take_name(mesh, base: str) -> str:
    """``base``, or ``base.002`` ... so that no take and no action already has the name.

    The take's action is named after the take, so the two always match.
    """
    used = set(take_names(mesh)) | set(bpy.data.actions.keys())
    if base not in used:
        return base
    i = 2
    while f"{base}.{i:03d}" in used:
        i += 1
    return f"{base}.{i:03d}"


# ---------------------------------------------------------------------------- targets


@dataclass(frozen=True)
class TargetLink:
    """How a target is driven: by which take of which blob, laid on it how."""

    blob: str
    take: str
    action: str
    axes: str
    mapping: list
    rest_matrix: list
    #: Whether translation, rotation and scale are keyed from the take (else held at rest).
    use: list = (True, True, True)

    def write(self, obj) -> None:
        obj[LINK_KEY] = {
            "blob": self.blob,
            "take": self.take,
            "action": self.action,
            "axes": self.axes,
            "mapping": list(self.mapping),
            "rest_matrix": list(self.rest_matrix),
            "use": [bool(u) for u in self.use],
        }


def read_link(obj) -> TargetLink | None:
    """The target's link, or None when no take drives it (or the link is damaged)."""
    try:
        raw = obj.get(LINK_KEY) if obj is not None else None
    except ReferenceError:
        return None
    if raw is None:
        return None
    try:
        return TargetLink(
            blob=str(raw["blob"]),
            take=str(raw["take"]),
            action=str(raw["action"]),
            axes=str(raw["axes"]),
            mapping=[float(v) for v in raw["mapping"]],
            rest_matrix=[float(v) for v in raw["rest_matrix"]],
            use=[bool(u) for u in raw.get("use", (True, True, True))],
        )
    except (KeyError, TypeError, ValueError):
        return None


def linked_to(obj, blob_mesh) -> bool:
    link = read_link(obj)
    return link is not None and obj.type == "MESH" and link.blob == blob_mesh.name


def tag_action(action, blob_mesh, take_name: str) -> None:
    action[ACTION_TAKE_KEY] = take_name
    action[ACTION_BLOB_KEY] = blob_mesh.name


def is_take_action(action, blob_mesh, take_name: str) -> bool:
    return (
        action is not None
        and action.get(ACTION_TAKE_KEY) == take_name
        and action.get(ACTION_BLOB_KEY) == blob_mesh.name
    )


# ---------------------------------------------------------------------------- side files


def _beside_blend(folder: str) -> Path | None:
    return Path(bpy.path.abspath("//")) / folder if bpy.data.filepath else None


def footage_dir() -> Path:
    """Where camera footage is written: beside the .blend, or Blender's session folder."""
    return _beside_blend(FOOTAGE_DIR) or Path(bpy.app.tempdir) / FOOTAGE_DIR


def recovery_dir() -> Path:
    """Where takes being recorded are journalled: beside the .blend, else a folder that
    outlives Blender's session (its own temporary folder is removed on exit).
    """
    return _beside_blend(RECOVERY_DIR) or Path(tempfile.gettempdir()) / RECOVERY_DIR


_journal_cache: dict = {}


def recoverable_journals() -> list:
    """(path, blob mesh) of the journals interrupted recordings of this file's blobs left.

    Cheap enough for a panel: a folder is read again only when it changed.
    """
    blobs = {blob_id(m): m for m in blob_meshes()}
    found = []
    for folder in {recovery_dir(), Path(tempfile.gettempdir()) / RECOVERY_DIR}:
        try:
            stamp = folder.stat().st_mtime_ns
        except OSError:
            continue
        cached = _journal_cache.get(folder)
        if cached is None or cached[0] != stamp:
            entries = []
            for path in journals_in(folder):
                try:
                    entries.append((path, read_journal_header(path).get("meta", {})))
                except VoodooError:
                    continue
            _journal_cache[folder] = cached = (stamp, entries)
        found += [(p, blobs[m.get("blob_id")]) for p, m in cached[1] if m.get("blob_id") in blobs]
    return found


def recover_take(path, blob_mesh) -> str:
    """Store the take of a journal with its blob; returns the take's name.

    A journal of a resumed take grows the take it continued; any other gets the name it
    was recorded under (made unique if that name is taken meanwhile). The journal is
    deleted once the take is stored.
    """
    journal = read_journal(path)
    meta = journal.header.get("meta", {})
    take, frames = journal.take, journal.frames
    extends = meta.get("extends")
    if extends and extends in take_names(blob_mesh):
        before = stored_take(blob_mesh, extends)
        if before.frames[-1] < frames[0]:
            take = before.take.extended(take)
            frames = np.concatenate([before.frames, frames])
            name = extends
        else:
            name = unique_take_name(blob_mesh, extends)
    else:
        name = meta.get("take") or "Take"
        if name in take_names(blob_mesh):
            name = unique_take_name(blob_mesh, name)
    store_take(blob_mesh, name, take, frames, meta.get("rest_frame"))
    path.unlink(missing_ok=True)
    return name
