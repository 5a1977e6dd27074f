"""Takes of several dolls: tracked together from one source, kept in one file.

A take file of one doll is the command-line contract of :mod:`.take` (version 2) and stays
so. A file of several dolls (version 3) holds ``dolls`` (D,) -- their names, in order -- and,
for the i-th doll, every array of a one-doll file under the prefix ``doll{i}.``
(``doll0.vertices``, ``doll0.params``, ...). :func:`load_takes` reads both kinds: a one-doll
file gives one doll, named after the file.
"""

from __future__ import annotations

import io
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..archive import header, load_npz, require
from ..checks import whole
from ..errors import VoodooError, read_file, write_file
from ..media.sources import FrameSource
from ..tracking.troupe import Troupe, doll_names
from .take import (
    READABLE_VERSIONS,
    SEVERAL_VERSION,
    TAKE_KIND,
    Take,
    take_arrays,
    take_from_arrays,
    take_to_bytes,
)


def track_dolls(
    troupe: Troupe,
    source: FrameSource,
    progress: Callable[[int], None] | None = None,
    limit: int | None = None,
) -> dict[str, Take]:
    """Track every frame of a source for every doll of ``troupe``; each doll's take by name.

    Each frame is read (decoded) once and registered for every doll. ``progress`` and
    ``limit`` are as for :func:`~.take.track_source`.
    """
    if limit is not None:
        limit = whole(limit, "the number of frames to track", 1)
    results = {name: [] for name in troupe.names}
    indices, times = [], []
    for frame in source:
        for name, r in troupe.track(frame.pixels).items():
            results[name].append(r)
        indices.append(frame.index)
        times.append(frame.time)
        if progress is not None:
            progress(len(indices))
        if limit is not None and len(indices) >= limit:
            break
    if not indices:
        raise VoodooError("The source gave no frames to track.")
    return {
        name: Take.from_results(
            results[name],
            troupe.blobs[name].triangles,
            troupe.trackers[name].parameter_names,
            indices,
            times,
            source.fps,
        )
        for name in troupe.names
    }


def takes_to_bytes(takes: dict[str, Take]) -> bytes:
    """One doll: the one-doll file (:func:`~.take.take_to_bytes`); several: version 3."""
    names = doll_names(takes)
    if len(names) == 1:
        return take_to_bytes(next(iter(takes.values())))
    arrays = {}
    for i, take in enumerate(takes.values()):
        arrays.update({f"doll{i}.{k}": v for k, v in take_arrays(take).items()})
    buf = io.BytesIO()
    np.savez_compressed(
        buf,
        format_kind=np.array(TAKE_KIND),
        format_version=np.array(SEVERAL_VERSION),
        dolls=np.array(names, dtype=str),
        **arrays,
    )
    return buf.getvalue()


def takes_from_bytes(data: bytes, source: str = "the take data", name: str = "doll"):
    """Inverse of :func:`takes_to_bytes`: each doll's take by name, in the file's order.

    A one-doll file gives one doll called ``name``.

    Raises
    ------
    VoodooError
        When the bytes are not a take file, or a doll's arrays are damaged or its frames do
        not match the others'.
    """
    d = load_npz(data, source, "Voodoo take")
    is_take, version = header(d, TAKE_KIND)
    if is_take and version in READABLE_VERSIONS:
        return {name: take_from_arrays(d, version, source)}
    if not is_take or version != SEVERAL_VERSION:
        raise VoodooError(f"{source} is not a Voodoo take.")
    require("dolls" in d and d["dolls"].ndim == 1, source, "no list of dolls")
    names = doll_names(d["dolls"].tolist())
    takes = {}
    for i, doll in enumerate(names):
        prefix = f"doll{i}."
        arrays = {k[len(prefix) :]: v for k, v in d.items() if k.startswith(prefix)}
        takes[doll] = take_from_arrays(arrays, 2, f"{source} (doll {doll!r})")
    first = next(iter(takes.values()))
    for doll, take in takes.items():
        require(
            np.array_equal(take.frame_indices, first.frame_indices),
            source,
            f"doll {doll!r} was tracked on other frames",
        )
    return takes


def save_takes(path, takes: dict[str, Take]) -> None:
    """Write the takes of one or several dolls to an ``.npz`` file."""
    write_file(path, takes_to_bytes(takes), "take")


def load_takes(path) -> dict[str, Take]:
    """Read a take file of one or several dolls (a one-doll file's doll is named after it)."""
    stem = Path(path).name.split(".")[0] or "doll"
    return takes_from_bytes(read_file(path, "take"), source=str(path), name=stem)
