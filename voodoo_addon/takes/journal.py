"""A take written to disk as it is recorded, so that a crash loses at most a few seconds.

A journal is one append-only file: a magic line, a length-prefixed JSON header (the take's
triangles, parameter names, fps and whatever the caller wants to find again, e.g. which blob
and take it belongs to), then one fixed-size record of float64 per tracked frame. Each record
is handed to the operating system as soon as it is written (a crashed or killed program loses
nothing) and synced to the disk every ``sync_every`` seconds (a crashed machine loses at most
that much); reading stops at the last whole record, so a file cut short still reads.
"""

from __future__ import annotations

import json
import os
import struct
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import VoodooError
from .take import Take

MAGIC = b"VOODOO-JOURNAL 1\n"
SUFFIX = ".vjournal"
#: Fixed fields at the start of each record, before nodes, params and visibility.
_FIELDS = ("index", "time", "frame", "confidence", "lost", "iterations")


@dataclass(frozen=True)
class Journal:
    """What a journal file holds: the take so far, the scene frame of each row, the header."""

    take: Take
    frames: np.ndarray
    header: dict


def _record_size(header: dict) -> int:
    return len(_FIELDS) + 2 * header["n_nodes"] + len(header["param_names"]) + header["n_triangles"]


class JournalWriter:
    """Appends tracked frames to a journal file.

    Parameters
    ----------
    path : path-like
        The journal file (created, replacing any file there).
    triangles : (t, 3) int
    n_nodes : int
    param_names : sequence of str
    fps : float
    meta : dict
        JSON-serialisable facts stored in the header (blob id, take name, ...).
    sync_every : float
        Seconds between syncs to the disk (0: after every frame).
    """

    def __init__(self, path, triangles, n_nodes, param_names, fps, meta=None, sync_every=2.0):
        self.path = Path(path)
        self.header = {
            "triangles": np.asarray(triangles, dtype=np.int64).tolist(),
            "n_triangles": len(triangles),
            "n_nodes": int(n_nodes),
            "param_names": [str(n) for n in param_names],
            "fps": float(fps),
            "meta": dict(meta or {}),
        }
        self.sync_every = float(sync_every)
        self.rows = 0
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._file = open(self.path, "wb")  # noqa: SIM115 - open for the recording's life
        except OSError as exc:
            raise VoodooError(f"Cannot write the recording journal {self.path}: {exc}") from None
        text = json.dumps(self.header).encode()
        self._file.write(MAGIC + struct.pack("<Q", len(text)) + text)
        self._file.flush()
        self._last_sync = time.monotonic()

    def add(self, result, index: int, seconds: float, frame: int) -> None:
        """Append one tracked frame (a TrackResult) shown at scene ``frame``."""
        h = self.header
        visible = (
            np.zeros(h["n_triangles"]) if result.visible is None else np.asarray(result.visible)
        )
        head = [index, seconds, frame, result.confidence, float(result.lost), result.iterations]
        record = np.concatenate(
            [
                np.asarray(head, dtype=np.float64),
                np.asarray(result.nodes, dtype=np.float64).ravel(),
                np.asarray(result.params, dtype=np.float64),
                visible.astype(np.float64),
            ]
        )
        self._file.write(record.tobytes())
        self._file.flush()
        self.rows += 1
        now = time.monotonic()
        if now - self._last_sync >= self.sync_every:
            self.sync()
            self._last_sync = now

    def sync(self) -> None:
        """Write everything so far through to the disk."""
        if not self._file.closed:
            self._file.flush()
            os.fsync(self._file.fileno())

    def close(self) -> None:
        if not self._file.closed:
            self.sync()
            self._file.close()

    def discard(self) -> None:
        """Close and delete the journal (its take is safely stored elsewhere)."""
        self.close()
        self.path.unlink(missing_ok=True)


def _header(data: bytes, path) -> tuple[dict, int]:
    """The header of a journal's bytes and where its records start."""
    if not data.startswith(MAGIC) or len(data) < len(MAGIC) + 8:
        raise VoodooError(f"{path} is not a recording journal.")
    (n,) = struct.unpack_from("<Q", data, len(MAGIC))
    start = len(MAGIC) + 8
    try:
        header = json.loads(data[start : start + n])
        _record_size(header)
        header["fps"] = float(header["fps"])
    except (ValueError, KeyError, TypeError) as exc:
        raise VoodooError(f"The journal {path} has a damaged header ({exc}).") from None
    return header, start + n


def read_journal_header(path) -> dict:
    """Only the header of a journal (cheap: what a recovery list shows)."""
    try:
        with open(path, "rb") as f:
            head = f.read(len(MAGIC) + 8)
            if not head.startswith(MAGIC) or len(head) < len(MAGIC) + 8:
                raise VoodooError(f"{path} is not a recording journal.")
            (n,) = struct.unpack_from("<Q", head, len(MAGIC))
            data = head + f.read(n)
    except OSError as exc:
        raise VoodooError(f"Cannot read the journal {path}: {exc}") from None
    return _header(data, path)[0]


def read_journal(path) -> Journal:
    """The take recorded in a journal, up to its last whole record.

    Raises
    ------
    VoodooError
        When the file is not a journal, or holds no whole frame.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise VoodooError(f"Cannot read the journal {path}: {exc}") from None
    header, start = _header(data, path)
    size = _record_size(header)
    try:
        triangles = np.asarray(header["triangles"], dtype=np.int32).reshape(-1, 3)
    except (ValueError, TypeError) as exc:
        raise VoodooError(f"The journal {path} has a damaged header ({exc}).") from None
    body = data[start:]
    rows = len(body) // (8 * size)
    if rows == 0:
        raise VoodooError(f"The journal {path} holds no tracked frame.")
    rec = np.frombuffer(body[: rows * 8 * size], dtype=np.float64).reshape(rows, size)
    rec = rec[np.isfinite(rec).all(axis=1)]  # a damaged record is skipped, not the rest
    if not len(rec):
        raise VoodooError(f"The journal {path} holds no readable frame.")
    frames = rec[:, 2]
    rec = rec[np.append(frames[1:] != frames[:-1], True)]  # a later row of a frame replaces it
    m, p = header["n_nodes"], len(header["param_names"])
    k = len(_FIELDS)
    take = Take(
        vertices=rec[:, k : k + 2 * m].reshape(-1, m, 2).copy(),
        triangles=triangles,
        params=rec[:, k + 2 * m : k + 2 * m + p].copy(),
        confidence=rec[:, 3].copy(),
        lost=rec[:, 4] > 0.5,
        param_names=np.array(header["param_names"], dtype=str),
        frame_indices=rec[:, 0].astype(np.int64),
        times=rec[:, 1].copy(),
        fps=float(header["fps"]),
        iterations=rec[:, 5].astype(np.int64),
        visible=rec[:, k + 2 * m + p :] > 0.5,
    )
    return Journal(take=take, frames=rec[:, 2].astype(np.int64), header=header)


def journals_in(folder) -> list:
    """Journal files in a folder, oldest first (an absent folder has none)."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    return sorted(folder.glob(f"*{SUFFIX}"), key=lambda p: p.stat().st_mtime)
