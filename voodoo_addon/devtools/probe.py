"""Whose fault a fold clip's error is: the objective's, or the search's.

On a fold render the renderer knows where the doll is. For each frame asked about, the
tracker's pose and the pose nearest the renderer's truth that the modes can take without
folding (:func:`.folds.nearest_unfolded_params`: the tracker never takes a folded shape,
and a part out of view left free by the seen nodes often folds) are both judged on the
frame the way the tracker judges its own fits
(:meth:`~voodoo_addon.tracking.fitter.CoarseToFineFitter.hold`: the quality and the robust
residual, against the look the tracker compared that frame with,
:attr:`~voodoo_addon.tracking.Tracker.appearance`), and one more fit is started at the
truth's pose. How to read a row:

- the truth has the higher confidence *and* the lower residual, and the fit started there
  stays there: the objective is right, and the tracker's search did not reach it (a start,
  or a pose it could not leave);
- the tracker's pose has the lower residual: the objective itself prefers the wrong place,
  and no search would help.

Both poses are modal (no local offsets); the truth's takes the tracker's lighting. Run as
``python -m voodoo_addon.devtools.probe CLIP [--camera C --seed N] [--frames A B]``; it
tracks every frame up to the last one asked about. Without a clip, every fold render is
probed on every frame and summed up per clip (:func:`summarise`).
"""

from __future__ import annotations

import numpy as np

from ..tracking import Tracker
from .camera import CameraFaults, add_camera_arguments, chosen_camera
from .clips import Clip
from .folds import nearest_unfolded_params, open_fold_clip


def probe(clip: Clip, frames=None, camera: CameraFaults | None = None) -> list[dict]:
    """One row per frame in ``frames`` (default: all) of ``clip`` (a fold render).

    Row entries: ``frame``; ``seen`` (share of the truth's nodes in view); ``error`` (the
    track's seen nodes, pixels) and ``modal_error`` (its modal mesh alone); ``truth_error``
    (the nearest modal pose's); ``confidence`` / ``residual`` of the tracker's modal pose
    and ``truth_confidence`` / ``truth_residual`` of the truth's, judged alike;
    ``from_truth_error`` / ``from_truth_confidence`` of a fit started at the truth's pose.
    Errors are means over the seen nodes; a row of a lost frame has no judgement (NaN).
    """
    pictures, blob, truth = open_fold_clip(clip, camera)
    tracker = Tracker(blob)
    poses = nearest_unfolded_params(blob, truth, tracker.layout)
    asked = set(range(len(pictures)) if frames is None else frames)
    zero = np.zeros_like(blob.vertices)
    fitter = tracker.fitter
    rows = []
    for i, frame in enumerate(pictures):
        if i > max(asked, default=-1):
            break
        look = tracker.appearance
        res = tracker.track(frame)
        if i not in asked:
            continue
        nodes, seen = truth(i, blob.vertices)

        def off(mesh, nodes=nodes, seen=seen):
            return float(np.linalg.norm(mesh[seen] - nodes[seen], axis=1).mean())

        at = poses[i].copy()
        stop = tracker.layout.modes.stop
        at[stop:] = res.params[stop:]  # the tracker's lighting
        row = {
            "frame": i,
            "seen": float(seen.mean()),
            "error": off(res.nodes),
            "modal_error": off(fitter.nodes(res.params, zero)),
            "truth_error": off(fitter.nodes(at, zero)),
        }
        judged = dict.fromkeys(
            (
                "confidence",
                "residual",
                "truth_confidence",
                "truth_residual",
                "from_truth_error",
                "from_truth_confidence",
            ),
            np.nan,
        )
        if not res.lost:
            fitter.forget()
            mine, theirs = fitter.hold(frame, res.params, look), fitter.hold(frame, at, look)
            again = fitter.fit(frame, [at], False, None, at, look)
            judged.update(
                confidence=mine.confidence,
                residual=mine.residual,
                truth_confidence=theirs.confidence,
                truth_residual=theirs.residual,
                from_truth_error=off(fitter.nodes(again.params, zero)),
                from_truth_confidence=again.confidence,
            )
        rows.append(row | {k: float(v) for k, v in judged.items()})
    return rows


#: A frame whose tracked modal mesh is this far off the truth (pixels, mean over the seen
#: nodes) is counted by :func:`summarise`.
OFF = 2.0


def summarise(rows) -> dict:
    """What the probe found on the frames (not lost) whose modal mesh is :data:`OFF` off.

    ``off``: those frames; ``objective``: of them, those where the tracker's pose has a
    residual no higher than the truth's (the objective prefers the wrong place, or the
    modes cannot hold the truth: compare ``truth_error``); ``search``: those where the
    truth's is lower; ``stays``: of the latter, those where a fit from the truth stays
    within a pixel of it; ``confidence``: those where the truth scores the higher
    confidence.
    """
    off = [r for r in rows if np.isfinite(r["residual"]) and r["modal_error"] > OFF]
    search = [r for r in off if r["residual"] > r["truth_residual"]]
    return {
        "off": len(off),
        "objective": len(off) - len(search),
        "search": len(search),
        "stays": sum(r["from_truth_error"] < r["truth_error"] + 1.0 for r in search),
        "confidence": sum(r["truth_confidence"] > r["confidence"] for r in off),
    }


def format_summary(named) -> str:
    """:func:`summarise` of each clip's rows (``{clip: rows}``) as a Markdown table."""
    lines = [
        f"| clip | frames off > {OFF:g} px | the track's residual lower | the truth's lower"
        " | of those, a fit from the truth stays | the truth's confidence higher |",
        "|" + "---|" * 6,
    ]
    for name, rows in named.items():
        s = summarise(rows)
        lines.append(
            f"| {name} | {s['off']} | {s['objective']} | {s['search']} | {s['stays']} |"
            f" {s['confidence']} |"
        )
    return "\n".join(lines)


def format_probe(rows) -> str:
    """The rows as a Markdown table."""
    head = (
        "| frame | seen | error px | modal error px | truth's error px | confidence: track /"
        " truth | residual: track / truth | fit from the truth: error px / confidence |"
    )
    lines = [head, "|" + "---|" * 8]
    for r in rows:
        lines.append(
            f"| {r['frame']} | {r['seen']:.2f} | {r['error']:.2f} | {r['modal_error']:.2f} | "
            f"{r['truth_error']:.2f} | {r['confidence']:.3f} / {r['truth_confidence']:.3f} | "
            f"{r['residual']:.4f} / {r['truth_residual']:.4f} | "
            f"{r['from_truth_error']:.2f} / {r['from_truth_confidence']:.3f} |"
        )
    return "\n".join(lines)


def main(argv=None) -> int:
    import argparse

    from .folds import fold_suite

    clips = {c.name: c for c in fold_suite()}
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("clip", nargs="?", choices=sorted(clips), help="default: all, summed up")
    p.add_argument("--frames", nargs=2, type=int, metavar=("FIRST", "LAST"))
    add_camera_arguments(p)
    args = p.parse_args(argv)
    camera = chosen_camera(p, args)
    frames = None if args.frames is None else range(args.frames[0], args.frames[1] + 1)
    if args.clip is None:
        print(format_summary({name: probe(c, frames, camera) for name, c in clips.items()}))
    else:
        print(format_probe(probe(clips[args.clip], frames, camera)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
