"""Fixtures shared by the test folders.

``extension_zips`` builds the extension from this checkout once per test session (the same as
``make extension``) for the packaging test and the install test. It needs Blender's extension
builder, which ships in the bpy wheel: without bpy it skips.
"""

import importlib.util
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


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
