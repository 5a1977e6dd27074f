"""The engine's one exception type, and file access that raises it."""

from pathlib import Path


class VoodooError(Exception):
    """An error the user can act on: bad input, a missing device, a lost track.

    The message is shown to the animator as it is (Blender's report, the command line's
    one-line error), so it says what went wrong *and* what to do about it.
    """


def write_file(path, data: bytes, what: str) -> None:
    """Write bytes; an OS error becomes a VoodooError naming ``what`` was being written."""
    try:
        Path(path).write_bytes(data)
    except OSError as exc:
        raise VoodooError(f"Could not write the {what} to {path} ({exc.strerror}).") from None


def read_file(path, what: str) -> bytes:
    """Read bytes; an OS error becomes a VoodooError naming ``what`` was being read."""
    try:
        return Path(path).read_bytes()
    except OSError as exc:
        raise VoodooError(f"Could not read the {what} file {path} ({exc.strerror}).") from None
