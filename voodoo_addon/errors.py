"""The engine's one exception type."""


class VoodooError(Exception):
    """An error the user can act on: bad input, a missing device, a lost track.

    The message is shown to the animator as it is (Blender's report, the command line's
    one-line error), so it says what went wrong *and* what to do about it.
    """
