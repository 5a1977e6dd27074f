"""The engine's files (blobs, takes) are pickle-free ``.npz`` archives; reading them warily.

A file may be truncated, overwritten, renamed from something else or damaged on disk. Whatever
is wrong with it, reading it gives a :class:`VoodooError` that names the file and what is
wrong -- never a traceback, and never a NaN that surfaces frames later.
"""

from __future__ import annotations

import io
import zipfile

import numpy as np

from .errors import VoodooError

#: Archives that unpack to more than this are refused (a damaged or hostile size field).
MAX_UNPACKED_BYTES = 1 << 30

#: dtype kinds by the names the specs use, and how messages call them.
KINDS = {"float": "f", "int": "iu", "bool": "b", "str": "U"}
_SAY = {"float": "numbers", "int": "whole numbers", "bool": "yes/no values", "str": "text"}


def load_npz(data: bytes, source: str, what: str) -> dict[str, np.ndarray]:
    """Every array of an ``.npz`` archive held in ``data``.

    Parameters
    ----------
    data : bytes
    source : str
        The file's name (or "the blob data"), for messages.
    what : str
        What the file should be ("Voodoo blob", "Voodoo take").

    Raises
    ------
    VoodooError
        When the bytes are not a readable archive of arrays.
    """
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as z:
            unpacked = sum(info.file_size for info in z.infolist())
        if unpacked > MAX_UNPACKED_BYTES:
            raise ValueError(f"it would unpack to {unpacked / 2**30:.1f} GiB")
        loaded = np.load(io.BytesIO(data), allow_pickle=False)
        if not isinstance(loaded, np.lib.npyio.NpzFile):
            raise ValueError("a single array, not an archive")
        with loaded as npz:
            return {k: npz[k] for k in npz.files}
    except Exception as exc:  # noqa: BLE001 - any failure to parse foreign bytes means this
        why = str(exc) or type(exc).__name__
        raise VoodooError(f"{source} is not a {what} file ({why}).") from None


def check_arrays(arrays: dict, spec: dict, source: str) -> dict[str, int]:
    """Check that arrays are present, of their kind and shape, and finite.

    Parameters
    ----------
    arrays : dict of str to ndarray
    spec : dict of str to (kind, shape)
        ``kind`` is a key of :data:`KINDS`; ``shape`` holds ints and names of sizes that must
        agree wherever they appear (``("T", "m", 2)``).
    source : str

    Returns
    -------
    dict of str to int
        The sizes the names took.

    Raises
    ------
    VoodooError
        "incomplete" when arrays are missing, "corrupt" when one does not fit.
    """
    missing = [k for k in spec if k not in arrays]
    if missing:
        raise VoodooError(f"{source} is incomplete (missing {', '.join(missing)}).")
    sizes: dict[str, int] = {}
    for name, (kind, shape) in spec.items():
        a = arrays[name]
        if a.dtype.kind not in KINDS[kind]:
            corrupt(source, f"{name} holds {a.dtype} values, not {_SAY[kind]}")
        if a.ndim != len(shape):
            corrupt(source, f"{name} has {a.ndim} axes, not {len(shape)}")
        for axis, (want, got) in enumerate(zip(shape, a.shape, strict=True)):
            if isinstance(want, str):
                want = sizes.setdefault(want, got)
            if want != got:
                corrupt(source, f"{name} has {got} entries along axis {axis}, not {want}")
        if kind == "float" and not np.isfinite(a).all():
            corrupt(source, f"{name} has NaN or infinite values")
    return sizes


def corrupt(source: str, why: str):
    """Raise the VoodooError for a file whose contents do not fit together."""
    raise VoodooError(f"{source} is corrupt ({why}).")


def require(ok, source: str, why: str) -> None:
    """:func:`corrupt` unless ``ok``."""
    if not ok:
        corrupt(source, why)


def header(arrays: dict, kind: str) -> tuple[bool, int]:
    """Whether the archive says it is a ``kind``, and its format version (-1 if unreadable)."""
    a = arrays.get("format_kind")
    is_kind = a is not None and a.dtype.kind == "U" and a.ndim == 0 and str(a) == kind
    v = arrays.get("format_version")
    version = int(v) if v is not None and v.dtype.kind in "iu" and v.ndim == 0 else -1
    return is_kind, version
