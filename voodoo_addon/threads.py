"""One BLAS thread while building a blob and tracking (see :func:`single_blas_thread`)."""

from __future__ import annotations

import os
import sys

_threads = None


def cores() -> int:
    """The CPU cores this process may run on (its affinity where the system has one)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # macOS and Windows have no affinity call
        return os.cpu_count() or 1


def single_blas_thread():
    """A context in which NumPy's BLAS runs on one thread.

    A frame's linear algebra is a few hundred small matrix-vector products. A multithreaded
    BLAS wakes its threads for each and leaves them spinning in ``sched_yield`` between
    calls: on two cores the tracker then spent as much time in the kernel as in its own
    work, and slowed everything else down. One thread does the same work faster.
    """
    global _threads
    if _threads is None:
        import scipy.linalg  # noqa: F401 - loads SciPy's own BLAS, so that it is limited too

        # threadpoolctl is a one-file module: the bytecode Python would write beside it in
        # the extension's site-packages is not in its wheel's record, so Blender would leave
        # it behind on uninstall. Import it without writing any.
        keep, sys.dont_write_bytecode = sys.dont_write_bytecode, True
        try:
            from threadpoolctl import ThreadpoolController
        finally:
            sys.dont_write_bytecode = keep
        _threads = ThreadpoolController()
    return _threads.limit(limits=1, user_api="blas")
