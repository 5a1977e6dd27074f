"""Reporting of the demo: numbered steps with run times, operator failures as ``DemoError``."""

import os
import sys
import time
from contextlib import contextmanager
from pathlib import Path


class DemoError(Exception):
    """A step of the demo failed; the message says which and why."""


class Steps:
    """Numbered progress lines for the demo's steps, with their run times."""

    def __init__(self, total: int):
        self.total = total
        self.times: list[tuple[str, float]] = []

    @contextmanager
    def __call__(self, title: str):
        """Announce a step, run the body, then print and keep how long it took."""
        print(f"[{len(self.times) + 1}/{self.total}] {title} ...", flush=True)
        start = time.perf_counter()
        yield
        seconds = time.perf_counter() - start
        self.times.append((title, seconds))
        print(f"      done in {seconds:.1f} s", flush=True)

    def summary(self) -> str:
        """Run time per step and in total, one line each."""
        lines = [f"  {seconds:6.1f} s  {title}" for title, seconds in self.times]
        total = sum(seconds for _, seconds in self.times)
        return "\n".join([*lines, f"  {total:6.1f} s  total"])


def run_operator(operator, **properties) -> None:
    """Run a bpy operator; raise DemoError when it does not finish.

    Operators report their errors with ``self.report``: the bpy module prints them as
    ``Error: ...`` lines and, when called from Python, raises RuntimeError with the message.
    """
    name = operator.idname_py()
    try:
        result = operator(**properties)
    except RuntimeError as exc:
        raise DemoError(
            f"bpy.ops.{name} failed: {str(exc).strip().removeprefix('Error: ')}"
        ) from None
    if "FINISHED" not in result:
        raise DemoError(f"bpy.ops.{name} returned {sorted(result)}; see the Error line above.")


def file_size(path: Path) -> str:
    """A file's size for people (kB or MB)."""
    size = path.stat().st_size
    return f"{size / 1e6:.1f} MB" if size >= 1e6 else f"{size / 1e3:.0f} kB"


@contextmanager
def quiet_stdout():
    """Silence what C code prints on stdout (Blender's per-render status lines)."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "w") as devnull:
            os.dup2(devnull.fileno(), 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
