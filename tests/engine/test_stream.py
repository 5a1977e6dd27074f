"""Streaming over OSC: the address space, bad targets, and a sender that never holds up.

Every datagram goes to loopback (127.0.0.1), to a receiver these tests bind themselves.
"""

import errno
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from voodoo_addon.errors import VoodooError
from voodoo_addon.stream import OscSender, osc_name, parse_target
from voodoo_addon.takes.rig import unit
from voodoo_addon.takes.take import load_take

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "sample_take.mp4"
OUTLINE = ROOT / "samples" / "sample_take.json"


@pytest.mark.parametrize(
    "text, want",
    [
        ("127.0.0.1:9000", ("127.0.0.1", 9000)),
        ("localhost:1", ("localhost", 1)),
        ("[::1]:57120", ("::1", 57120)),
    ],
)
def test_targets_parse(text, want):
    assert parse_target(text) == want


@pytest.mark.parametrize("text", ["", "9000", ":9000", "host:", "host:0", "host:70000", "a b:9"])
def test_bad_targets_are_refused_by_name(text):
    with pytest.raises(VoodooError, match="HOST:PORT"):
        parse_target(text)


def test_a_name_that_does_not_resolve_is_refused_before_any_frame():
    with pytest.raises(VoodooError, match="not known"):
        OscSender("no-such-host.invalid:9000")


def test_names_become_address_parts():
    assert osc_name("bend-x 2") == "bend-x_2"
    assert osc_name("a/b#c*d,e?f[g]h{i}") == "a_b_c_d_e_f_g_h_i_"


@pytest.mark.parametrize("bundle", [True, False])
def test_a_frame_arrives_with_the_documented_addresses(bundle, osc_receiver):
    rx = osc_receiver(5.0)
    with OscSender(f"127.0.0.1:{rx.port}", bundle=bundle) as tx:
        ok = tx.send(
            "my doll",
            7,
            0.25,
            [1.5, -2.0, 0.1, 0.05],
            {"bend-x": 0.5, "twist 2": -1.0},
            0.9,
            False,
            0.625,
        )
    rx.close()
    assert ok and tx.sent == 1 and not tx.warnings
    assert len(rx.datagrams) == (1 if bundle else 6)
    got = [m for d in rx.datagrams for m in rx.messages(d)]
    assert [a for a, _ in got] == [
        "/voodoo/my_doll/frame",
        "/voodoo/my_doll/pose",
        "/voodoo/my_doll/mode/bend-x",
        "/voodoo/my_doll/mode/twist_2",
        "/voodoo/my_doll/quality",
        "/voodoo/my_doll/view",
    ]
    params = dict(got)
    assert params["/voodoo/my_doll/frame"] == [7, 0.25]
    np.testing.assert_allclose(params["/voodoo/my_doll/pose"], [1.5, -2.0, 0.1, 0.05], rtol=1e-6)
    assert params["/voodoo/my_doll/quality"][1] == 0
    np.testing.assert_allclose(params["/voodoo/my_doll/view"], [0.625])


def test_sending_errors_are_counted_and_said_once_never_raised(monkeypatch):
    tx = OscSender("127.0.0.1:9")

    class Unreachable:
        def sendto(self, data, address):
            raise OSError(errno.ENETUNREACH, "Network is unreachable")

        def close(self):
            pass

    monkeypatch.setattr(tx, "_socket", Unreachable())
    for i in range(5):
        assert tx.send("d", i, 0.0, [0, 0, 0, 0], {}, 1.0, False) is False
    assert tx.dropped == 5 and tx.sent == 0
    assert len(tx.warnings) == 1 and "unreachable" in tx.warnings[0]


def test_a_receiver_that_never_reads_does_not_hold_up_the_sender():
    """The port is taken by a socket that reads nothing: its buffer fills, the sender drops
    and counts, and every send returns at once."""
    deaf = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    deaf.bind(("127.0.0.1", 0))
    deaf.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    port = deaf.getsockname()[1]
    modes = {f"mode {k}": 0.1 * k for k in range(20)}
    slowest = 0.0
    with OscSender(f"127.0.0.1:{port}") as tx:
        for i in range(3000):  # bounded
            t0 = time.perf_counter()
            tx.send("d", i, i / 30, [0, 0, 0, 0], modes, 1.0, False)
            slowest = max(slowest, time.perf_counter() - t0)
    deaf.close()
    assert tx.sent + tx.dropped == 3000
    assert slowest < 0.05


def load_blob_of_sample():
    """The blob `voodoo live` builds on the sample take (the same frame and outline)."""
    from voodoo_addon.blob.build import build_blob
    from voodoo_addon.blob.outline import load_contour_json
    from voodoo_addon.media.sources import read_image

    return build_blob(read_image(SAMPLE), load_contour_json(OUTLINE))


def run_live(*args, **kwargs):
    cmd = [sys.executable, "-m", "voodoo_addon", "live", str(SAMPLE), "--contour", str(OUTLINE)]
    return subprocess.Popen(
        cmd + [str(a) for a in args],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        **kwargs,
    )


def test_voodoo_live_streams_every_frame_in_order_as_in_the_take_file(tmp_path, osc_receiver):
    rx = osc_receiver(240.0)
    out = tmp_path / "take.npz"
    proc = run_live("--osc", f"127.0.0.1:{rx.port}", "--fast", "--quiet", "--out", out)
    stdout, stderr = proc.communicate(timeout=240)
    rx.close()
    assert proc.returncode == 0, stderr
    assert "fps, latency" in stdout
    take = load_take(out)
    per_unit = unit(load_blob_of_sample())
    frames = [rx.messages(d) for d in rx.datagrams]
    assert len(frames) == len(take) > 20
    names = list(take.param_names)
    modes = [n for n in names[4:] if not n.startswith(("brightness", "contrast"))]
    for row, msgs in enumerate(frames):
        got = dict(msgs)
        assert got["/voodoo/sample_take/frame"][0] == take.frame_indices[row] == row
        np.testing.assert_allclose(
            got["/voodoo/sample_take/pose"], take.params[row, :4].astype(np.float32), rtol=1e-6
        )
        for name in modes:
            value = got[f"/voodoo/sample_take/mode/{osc_name(name)}"][0]
            want = np.float32(take.params[row, names.index(name)] / per_unit)
            assert value == pytest.approx(want, rel=1e-5, abs=1e-7)
        conf, lost = got["/voodoo/sample_take/quality"]
        assert conf == pytest.approx(np.float32(take.confidence[row]), rel=1e-6)
        assert lost == int(take.lost[row])


def _default_sigint():
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


def test_voodoo_live_stops_cleanly_on_ctrl_c_and_keeps_the_take(tmp_path):
    out = tmp_path / "take.npz"
    # Started with Ctrl-C at its default and unblocked, as from a terminal, whatever the test
    # process's libraries did to it: a child inherits an ignored or blocked SIGINT. (In two
    # full CI runs the command never saw the Ctrl-C; run alone it always did. The cause is
    # not pinned down.)
    proc = run_live("--out", out, preexec_fn=_default_sigint)  # the clip's pace: about 5 s
    # Ctrl-C once the take is under way (its first once-a-second status line), not after a
    # fixed time: a busy machine may still be starting the command then.
    lines = []
    for line in proc.stderr:
        lines.append(line)
        if line.startswith("live: ") and "fps" in line:
            break
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    stderr = "".join(lines) + stderr
    assert proc.returncode == 0, stderr
    assert "(stopped)" in stdout and "Traceback" not in stderr, (stdout, stderr)
    assert 0 < len(load_take(out))


@pytest.mark.parametrize("target", ["nowhere", "no-such-host.invalid:9000"])
def test_voodoo_live_with_a_bad_target_says_so_and_tracks_on(tmp_path, target):
    out = tmp_path / "take.npz"
    proc = run_live("--osc", target, "--fast", "--quiet", "--frames", 10, "--out", out)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 0, stderr
    assert stderr.count("warning:") == 1 and "Tracking without streaming" in stderr
    assert len(load_take(out)) == 10


def test_the_example_puppet_moves_with_a_streamed_clip(tmp_path):
    """examples/osc_puppet.py, headless: it draws every frame `voodoo live` streams to it."""
    probe = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()
    video = tmp_path / "puppet.mp4"
    puppet = subprocess.Popen(
        [sys.executable, str(ROOT / "examples" / "osc_puppet.py"), "--port", str(port)]
        + ["--out", str(video), "--frames", "30", "--idle", "120"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert "listening on 127.0.0.1" in puppet.stdout.readline()
    live = run_live("--osc", f"127.0.0.1:{port}", "--fast", "--quiet", "--frames", 30)
    assert live.wait(timeout=120) == 0
    stdout, stderr = puppet.communicate(timeout=120)
    assert puppet.returncode == 0, stderr
    assert "30 frames drawn" in stdout and "bend-x" in stdout
    import cv2

    cap = cv2.VideoCapture(str(video))
    pictures = []
    while (got := cap.read())[0]:
        pictures.append(got[1].astype(np.int16))
    cap.release()
    assert len(pictures) == 30
    moved = [np.abs(b - a).mean() for a, b in zip(pictures[2:], pictures[3:], strict=False)]
    assert max(moved) > 0.5  # the figure moves with the doll
