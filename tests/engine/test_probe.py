"""The fold probe (devtools.probe): the truth's pose judged as the tracker judges its own,
without disturbing the track it judges."""

import numpy as np

from voodoo_addon.blob.build import build_blob
from voodoo_addon.devtools.clips import LatticeTruth, read_clip, track_ours
from voodoo_addon.devtools.folds import fold_clips
from voodoo_addon.devtools.probe import format_probe, probe
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
