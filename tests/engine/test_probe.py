"""The fold probe (devtools.probe): the truth's pose judged as the tracker judges its own,
without disturbing the track it judges."""

import numpy as np

from voodoo_addon.blob.build import build_blob
from voodoo_addon.devtools.clips import LatticeTruth, read_clip, track_ours
from voodoo_addon.devtools.folds import fold_clips
from voodoo_addon.devtools.probe import format_probe, format_summary, probe, summarise
from voodoo_addon.media.images import to_float_rgb

FRAMES = range(6, 10)


def test_the_probe_judges_the_truth_beside_an_undisturbed_track():
    """Before the sheet folds, the pose nearest the renderer's is within half a pixel, fits
    at least as well as the tracker's own and a fit started there stays there; the track's
    errors are those of the tracker run alone on the same frames."""
    clip = next(c for c in fold_clips() if c.name == "sheet_foldover")
    rows = probe(clip, FRAMES)
    assert [r["frame"] for r in rows] == list(FRAMES)

    frames, outline, _ = read_clip(clip)
    blob = build_blob(to_float_rgb(frames[0]), outline)
    verts = track_ours(frames[: FRAMES[-1] + 1], blob)[0]
    truth = LatticeTruth(clip.truth)
    for r in rows:
        nodes, seen = truth(r["frame"], blob.vertices)
        alone = np.linalg.norm(verts[r["frame"]][seen] - nodes[seen], axis=1).mean()
        assert r["error"] == alone
        assert r["seen"] > 0.9
        assert r["truth_error"] < 0.5
        assert r["from_truth_error"] < 0.5
        assert r["truth_confidence"] >= r["confidence"] - 0.02
        assert 0.0 < r["truth_residual"] < np.inf
    table = format_probe(rows)
    assert table.count("\n") == len(rows) + 1


def test_the_summary_counts_frames_off_by_whose_residual_is_lower():
    """Lost frames and frames on target are not counted; a frame off is the objective's
    when the track's residual is no higher than the truth's, else the search's."""

    def row(modal, mine, theirs, again=0.5, conf=(0.5, 0.6)):
        return {
            "modal_error": modal,
            "truth_error": 0.3,
            "residual": mine,
            "truth_residual": theirs,
            "from_truth_error": again,
            "confidence": conf[0],
            "truth_confidence": conf[1],
        }

    rows = [
        row(0.5, 0.01, 0.02),  # on target
        row(5.0, np.nan, 0.02),  # lost
        row(5.0, 0.01, 0.02, conf=(0.6, 0.5)),  # the objective prefers the track
        row(5.0, 0.03, 0.02),  # the truth's residual lower, and a fit from it stays
        row(5.0, 0.03, 0.02, again=4.0),  # ... but the fit from it runs off
    ]
    assert summarise(rows) == {"off": 3, "objective": 1, "search": 2, "stays": 1, "confidence": 2}
    assert format_summary({"a clip": rows}).splitlines()[-1] == "| a clip | 3 | 1 | 2 | 1 | 2 |"
