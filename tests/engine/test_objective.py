"""devtools.objective: which pose a fold render's picture favours, by colours and gradients."""

from __future__ import annotations

import numpy as np

from voodoo_addon.devtools.folds import fold_suite
from voodoo_addon.devtools.objective import compare_poses, main


def _clip(name: str):
    return next(c for c in fold_suite() if c.name == name)


def test_the_capture_frame_matches_itself_and_a_followed_frame_nearly_so():
    """Frame 0 at its true pose is the reference itself (both correlations 1); on the next
    frames of a sheet the tracker follows within a pixel both poses read nearly 1."""
    rows = compare_poses(_clip("sheet_foldover"), 0, 3)
    assert [r["frame"] for r in rows] == [0, 1, 2, 3]
    assert rows[0]["colour_true"] > 0.999 and rows[0]["gradient_true"] > 0.999
    for r in rows:
        assert all(np.isfinite(v) for v in r.values())
        assert r["track_error_px"] < 1.0
        assert min(r["colour_true"], r["colour_track"]) > 0.95
        assert min(r["gradient_true"], r["gradient_track"]) > 0.8


def test_the_command_prints_a_row_per_frame(capsys):
    assert main(["sheet_foldover", "--first", "1", "--last", "2"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 4 and lines[2].startswith("| 1 |") and lines[3].startswith("| 2 |")
