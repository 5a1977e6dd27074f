"""Blobs and takes inside the .blend.

A blob is a Mesh datablock (kept by a fake user) whose geometry is the blob's triangle mesh
(pixels / 100, image-down as -Y, for looking at) and whose ``["voodoo_blob"]`` property holds
the engine's pickle-free ``.npz`` bytes -- the exact blob, surviving save and reload. Takes
recorded with a blob are stored beside it, under ``["voodoo_takes"][name]``.
"""

import uuid

import bpy
import numpy as np

from ..voodoo_addon.blob.model import ActiveBlob, blob_from_bytes, blob_to_bytes
from ..voodoo_addon.errors import VoodooError
from ..voodoo_addon.takes.take import Take, take_from_bytes, take_to_bytes

BLOB_KEY = "voodoo_blob"
#: A fresh id per stored blob, so the parsed blob can be cached without reading its bytes.
BLOB_ID_KEY = "voodoo_blob_id"
TAKES_KEY = "voodoo_takes"
#: Pixels per Blender unit of the blob mesh shown in the file.
DISPLAY_SCALE = 100.0

_cache: dict = {}


def is_blob(mesh) -> bool:
    return mesh is not None and BLOB_KEY in mesh


def store_blob(name: str, blob: ActiveBlob) -> bpy.types.Mesh:
    """A new blob mesh datablock holding ``blob``."""
    mesh = bpy.data.meshes.new(name)
    v = np.zeros((blob.n_nodes, 3))
    v[:, 0] = blob.vertices[:, 0] / DISPLAY_SCALE
    v[:, 1] = -blob.vertices[:, 1] / DISPLAY_SCALE
    mesh.from_pydata(v.tolist(), [], blob.triangles.tolist())
    mesh.update()
    mesh[BLOB_KEY] = blob_to_bytes(blob)
    mesh[BLOB_ID_KEY] = uuid.uuid4().hex
    mesh.use_fake_user = True
    return mesh


def load_blob(mesh) -> ActiveBlob:
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


def store_take(mesh, name: str, take: Take) -> None:
    """Keep a take with its blob (replacing one of the same name)."""
    takes = mesh.get(TAKES_KEY)
    if takes is None:
        mesh[TAKES_KEY] = {}
        takes = mesh[TAKES_KEY]
    takes[name] = take_to_bytes(take)


def take_names(mesh) -> list:
    if mesh is None or TAKES_KEY not in mesh:
        return []
    return list(mesh[TAKES_KEY].keys())


def load_take(mesh, name: str) -> Take:
    """A take stored with a blob."""
    takes = mesh.get(TAKES_KEY) if mesh is not None else None
    if takes is None or name not in takes:
        raise VoodooError(f"There is no take named {name!r}; record one first.")
    return take_from_bytes(bytes(takes[name]), source=f"Take {name!r}")


def unique_take_name(mesh, base: str) -> str:
    names = set(take_names(mesh))
    if base not in names:
        return base
    i = 2
    while f"{base}.{i:03d}" in names:
        i += 1
    return f"{base}.{i:03d}"
