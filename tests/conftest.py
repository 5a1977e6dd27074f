"""Fixtures shared by the test folders.

``extension_zips`` builds the extension from this checkout once per test session (the same as
``make extension``) for the packaging test and the install test. It needs Blender's extension
builder, which ships in the bpy wheel: without bpy it skips.
"""

import importlib.util
import os
import platform
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: What OpenBLAS's SkylakeX kernels use (``/proc/cpuinfo`` flags).
SKYLAKEX_FLAGS = frozenset({"avx512f", "avx512cd", "avx512bw", "avx512dq", "avx512vl"})


def _cpu_flags() -> set[str]:
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return set()
    line = next((ln for ln in text.splitlines() if ln.startswith("flags")), "")
    return set(line.partition(":")[2].split())


def pin_openblas_kernels() -> str | None:
    """Ask OpenBLAS for its SkylakeX kernels on a processor with their AVX-512; the name set.

    OpenBLAS picks its kernels by the processor, and the environment may pick others: one
    machine, an AMD Zen 5, came with ``OPENBLAS_CORETYPE=Haswell`` set, and without it takes
    the Cooperlake kernels (SkylakeX's with bfloat16 added). A fold render's track follows
    the last bits of a float, so the tests' frame-by-frame figures hold for one family of
    kernels: with the Haswell ones six of them failed there (a trial two frames later,
    counterfactuals that recovered anyway); with the Cooperlake ones one clean fold render
    of the 27 changed in its 90th percentile; with the SkylakeX ones every figure of the 27
    came out as on an Intel Xeon. So on a processor that has what those kernels use, the
    tests ask for them, whatever the environment asked for. Must run
    before NumPy is first imported.
    """
    if platform.machine() not in ("x86_64", "AMD64") or not SKYLAKEX_FLAGS <= _cpu_flags():
        return None
    os.environ["OPENBLAS_CORETYPE"] = "SkylakeX"
    return "SkylakeX"


pin_openblas_kernels()


@pytest.fixture(scope="session")
def extension_zips() -> dict[str, Path]:
    """Build the extension zips; Blender platform name (``linux-x64``) -> its zip."""
    if importlib.util.find_spec("bpy") is None:
        pytest.skip("Blender's extension builder comes with bpy, which is not installed")
    script = ROOT / "scripts" / "build_extension.py"
    done = subprocess.run([sys.executable, script], capture_output=True, text=True, timeout=1200)
    assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-4000:]
    manifest = tomllib.loads((ROOT / "blender_manifest.toml").read_text())
    stem = f"{manifest['id']}-{manifest['version']}"
    return {p: ROOT / "dist" / f"{stem}-{p.replace('-', '_')}.zip" for p in manifest["platforms"]}


def osc_messages(dgram: bytes) -> list:
    """(address, params) of every OSC message in a datagram (a bundle or one message)."""
    from pythonosc.osc_bundle import OscBundle
    from pythonosc.osc_message import OscMessage

    if OscBundle.dgram_is_bundle(dgram):
        return [m for item in OscBundle(dgram) for m in osc_messages(item.dgram)]
    m = OscMessage(dgram)
    return [(m.address, list(m.params))]


class OscReceiver:
    """A UDP socket on 127.0.0.1 (only there) collecting datagrams on a thread.

    It stops by itself after ``seconds``; :meth:`close` waits for what is in flight.
    ``messages`` parses a datagram.
    """

    messages = staticmethod(osc_messages)

    def __init__(self, seconds: float = 60.0):
        import socket
        import threading
        import time

        self._time = time
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", 0))
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 22)
        self.sock.settimeout(0.1)
        self.port = self.sock.getsockname()[1]
        self.datagrams: list = []
        self._stop = threading.Event()
        self._until = time.monotonic() + seconds
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        while not self._stop.is_set() and self._time.monotonic() < self._until:
            try:
                self.datagrams.append(self.sock.recv(65536))
            except TimeoutError:
                continue

    def close(self) -> list:
        """Stop (after what is in flight on loopback lands); the datagrams received."""
        self._time.sleep(0.3)
        self._stop.set()
        self._thread.join()
        self.sock.close()
        return self.datagrams


@pytest.fixture
def osc_receiver():
    """Make :class:`OscReceiver` s (closed at the end of the test)."""
    made = []

    def make(seconds: float = 60.0) -> OscReceiver:
        made.append(OscReceiver(seconds))
        return made[-1]

    yield make
    for rx in made:
        if rx._thread.is_alive():
            rx.close()
