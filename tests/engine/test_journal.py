"""The recording journal: what was tracked survives a crash, a cut-short file and a re-read."""

import os
import subprocess
import sys
import textwrap
from types import SimpleNamespace

import numpy as np
import pytest

from voodoo_addon.errors import VoodooError
from voodoo_addon.takes.journal import JournalWriter, journals_in, read_journal, read_journal_header
from voodoo_addon.takes.take import Take

TRIANGLES = np.array([[0, 1, 2], [1, 3, 2]])
NAMES = ["tx", "ty", "rot", "scale", "bend-x", "gain", "bias"]


def _result(rng, lost=False):
    return SimpleNamespace(
        nodes=rng.normal(size=(4, 2)) * 50 + 100,
        params=rng.normal(size=len(NAMES)),
        confidence=float(rng.uniform()),
        lost=lost,
        iterations=int(rng.integers(1, 9)),
        visible=rng.uniform(size=len(TRIANGLES)) > 0.3,
    )


def _write(path, results, frames, **kw):
    writer = JournalWriter(path, TRIANGLES, 4, NAMES, 24.0, meta={"take": "Take"}, **kw)
    for i, (r, f) in enumerate(zip(results, frames, strict=True)):
        writer.add(r, i, i / 24.0, f)
    return writer


def test_round_trip_matches_the_take_from_results(tmp_path):
    rng = np.random.default_rng(0)
    results = [_result(rng, lost=i == 3) for i in range(10)]
    _write(tmp_path / "a.vjournal", results, range(1, 11)).close()
    got = read_journal(tmp_path / "a.vjournal")
    want = Take.from_results(results, TRIANGLES, NAMES, range(10), np.arange(10) / 24.0, 24.0)
    for field in ("vertices", "params", "confidence", "lost", "frame_indices", "times"):
        np.testing.assert_array_equal(getattr(got.take, field), getattr(want, field))
    np.testing.assert_array_equal(got.take.visible, want.visible)
    np.testing.assert_array_equal(got.frames, np.arange(1, 11))
    assert got.header["meta"] == {"take": "Take"}
    assert read_journal_header(tmp_path / "a.vjournal")["param_names"] == NAMES


def test_a_file_cut_mid_record_keeps_every_whole_frame(tmp_path):
    rng = np.random.default_rng(1)
    path = tmp_path / "cut.vjournal"
    _write(path, [_result(rng) for _ in range(6)], range(6)).close()
    data = path.read_bytes()
    path.write_bytes(data[:-13])
    assert len(read_journal(path).take) == 5


def test_a_later_row_of_the_same_scene_frame_replaces_the_earlier(tmp_path):
    rng = np.random.default_rng(2)
    results = [_result(rng) for _ in range(4)]
    _write(tmp_path / "d.vjournal", results, [1, 2, 2, 3]).close()
    got = read_journal(tmp_path / "d.vjournal")
    np.testing.assert_array_equal(got.frames, [1, 2, 3])
    np.testing.assert_array_equal(got.take.params[1], results[2].params)


def test_a_killed_process_loses_no_recorded_frame(tmp_path):
    """The writer hands each record to the OS at once: os._exit right after the last add."""
    script = textwrap.dedent(
        f"""
        import os, sys
        from types import SimpleNamespace
        import numpy as np
        sys.path.insert(0, {os.getcwd()!r})
        from voodoo_addon.takes.journal import JournalWriter
        w = JournalWriter(sys.argv[1], [[0, 1, 2], [1, 3, 2]], 4, {NAMES!r}, 24.0, sync_every=60)
        for i in range(37):
            r = SimpleNamespace(nodes=np.full((4, 2), float(i)), params=np.zeros({len(NAMES)}),
                                confidence=0.9, lost=False, iterations=3, visible=None)
            w.add(r, i, i / 24.0, i + 1)
        os._exit(0)
        """
    )
    path = tmp_path / "crash.vjournal"
    subprocess.run([sys.executable, "-c", script, str(path)], check=True, timeout=60)
    got = read_journal(path)
    assert len(got.take) == 37
    assert got.take.vertices[-1, 0, 0] == 36.0


@pytest.mark.parametrize(
    "content, message",
    [
        (b"", "not a recording journal"),
        (b"hello world, this is not a journal at all", "not a recording journal"),
        (b"VOODOO-JOURNAL 1\n" + (5).to_bytes(8, "little") + b"{bad}", "damaged header"),
    ],
)
def test_what_is_not_a_journal_says_so(tmp_path, content, message):
    path = tmp_path / "bad.vjournal"
    path.write_bytes(content)
    with pytest.raises(VoodooError, match=message):
        read_journal(path)


def test_a_journal_without_frames_says_so(tmp_path):
    path = tmp_path / "empty.vjournal"
    _write(path, [], []).close()
    with pytest.raises(VoodooError, match="no tracked frame"):
        read_journal(path)


def test_a_damaged_record_is_skipped_not_the_rest(tmp_path):
    rng = np.random.default_rng(3)
    path = tmp_path / "nan.vjournal"
    _write(path, [_result(rng) for _ in range(5)], range(5)).close()
    data = bytearray(path.read_bytes())
    size = (6 + 8 + len(NAMES) + 2) * 8
    start = len(data) - 5 * size
    data[start + 2 * size + 16 : start + 2 * size + 24] = np.float64(np.nan).tobytes()
    path.write_bytes(bytes(data))
    got = read_journal(path)
    assert len(got.take) == 4 and np.isfinite(got.take.vertices).all()


def test_journals_in_a_folder(tmp_path):
    assert journals_in(tmp_path / "absent") == []
    rng = np.random.default_rng(4)
    _write(tmp_path / "one.vjournal", [_result(rng)], [1]).close()
    (tmp_path / "other.txt").write_text("x")
    assert [p.name for p in journals_in(tmp_path)] == ["one.vjournal"]


def test_discard_removes_the_file(tmp_path):
    rng = np.random.default_rng(5)
    writer = _write(tmp_path / "gone.vjournal", [_result(rng)], [1])
    writer.discard()
    assert not (tmp_path / "gone.vjournal").exists()


def test_an_unwritable_folder_says_so(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(VoodooError, match="journal"):
        JournalWriter(blocker / "sub" / "a.vjournal", TRIANGLES, 4, NAMES, 24.0)
