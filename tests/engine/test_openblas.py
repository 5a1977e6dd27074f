"""The OpenBLAS kernels the tests run on (``tests/conftest.py``): where the processor has the
AVX-512 of OpenBLAS's SkylakeX kernels, those, chosen before NumPy was first imported."""

import ctypes
import os
from pathlib import Path

import numpy as np
import pytest

#: What NumPy's OpenBLAS calls the function that names its kernels, by release.
CORENAME = ("scipy_openblas_get_corename64_", "openblas_get_corename64_", "openblas_get_corename")


def _openblas_kernels() -> str | None:
    """The kernels NumPy's own OpenBLAS runs, as it names them; None when it does not say."""
    for path in sorted((Path(np.__file__).parent.parent / "numpy.libs").glob("*openblas*")):
        lib = ctypes.CDLL(str(path))
        for name in CORENAME:
            fn = getattr(lib, name, None)
            if fn is not None:
                fn.restype = ctypes.c_char_p
                return fn().decode()
    return None


def test_openblas_runs_the_kernels_the_tests_asked_for():
    if os.environ.get("OPENBLAS_CORETYPE") != "SkylakeX":
        pytest.skip("no AVX-512 for OpenBLAS's SkylakeX kernels here: the machine's own run")
    kernels = _openblas_kernels()
    if kernels is None:
        pytest.skip("this NumPy's OpenBLAS does not name its kernels")
    assert kernels == "SkylakeX"
