"""Folds and turns: a doll partly hidden by itself, judged on the part still in view.

Part ``folds`` of the benchmark. Every render under ``samples/folds`` (a sheet squeezed until
it folds in half, turned edge-on by one end, folded over onto itself; see
``samples/folds/README.md``), and every held-out one under ``samples/heldout_folds`` to
``samples/heldout_folds8`` (the same kinds of motion in other paint and motion, rendered
after the tracker's last change and never tuned on), is tracked by ours, KLT and DIS on the
same decoded frames and judged on what the issue asks of a fold:

- **folded frames**: frames where any triangle of the mesh is turned over;
- **lost while a third is in view**: lost frames while at least :data:`THIRD` of the true
  lattice is seen;
- **node error** of the nodes the renderer sees (mean over frames, and the 90th percentile);
- **recovery**: after the frame where the sheet was least seen, the first frame where the
  hidden part is back -- *in view*, :data:`RETURNED` of the lattice seen again (it may still
  be nearly edge-on), and *open*, the seen lattice covering :data:`RETURNED` of its frame-0
  area on the picture again -- and how many frames after each the error of the seen nodes
  first falls below :data:`SUBPIXEL`;
- **modes at best** (the ``modes`` row): the renderer's seen nodes fitted by the similarity
  and the modes together (:func:`nearest_modal`), judged like a track: the nearest the
  tracker's modal mesh can come to the truth, so its frames to sub-pixel are the fewest any
  fit by these modes could take;
- **out of view marked** (ours): the share of the triangles the renderer does not see (most
  of their nodes unseen) that the result reports out of view, over the frames not lost where
  at least :data:`MARKED_FROM` of the triangles are unseen; beside it the share of the seen
  triangles it reports out of view, over every frame not lost;
- **mode jump** (ours): the largest change of the mode amplitudes from one tracked frame to
  the next (pixels RMS over the doll), against the median change and against the largest
  change of the renderer's own mesh projected onto the modes (:func:`true_modes`): what a
  character driven by the modes would show as a jump the doll did not make.

With ``--camera webcam`` or ``--camera dim`` every clip is first given a camera's faults
(:mod:`.camera`: defocus, exposure drift, sensor noise, JPEG), and the blob is built on the
degraded first frame.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
from scipy.optimize import least_squares

from ..blob.build import build_blob
from ..media.images import to_float_rgb
from ..tracking.folding import MAX_AREA, MIN_AREA, FoldGuard
from ..tracking.params import ParamLayout, node_positions, similarity_from_matrix
from ..tracking.proposals import PointFit
from ..tracking.quality import score_track
from .baselines import track_dis, track_klt
from .camera import CameraFaults, add_camera_arguments, chosen_camera, degrade
from .clips import (
    SAMPLES,
    Clip,
    LatticeTruth,
    read_clip,
    track_ours,
    track_ours_both_ways,
    truth_errors,
)

FOLDS = SAMPLES / "folds"
#: Renders of the same kinds of motion in other paint and motion, made after the tracker's
#: last change to check that it generalises: never tuned on.
HELDOUT_FOLDS = SAMPLES / "heldout_folds"
#: A second batch of held-out renders, made after the first batch had been run once.
HELDOUT_FOLDS2 = SAMPLES / "heldout_folds2"
#: A third batch, made after the tracker's last change, when the second had been run.
HELDOUT_FOLDS3 = SAMPLES / "heldout_folds3"
#: A fourth batch, made when the tracker had not changed since the third had been run.
HELDOUT_FOLDS4 = SAMPLES / "heldout_folds4"
#: A fifth, likewise: a whole doll turned in depth, a corner tucked back under a hand, a
#: diagonal fold over.
HELDOUT_FOLDS5 = SAMPLES / "heldout_folds5"
#: A sixth, likewise: a bag folded back in half fast under two hands, a plush lifted by a
#: corner about a falling axis, a sheet's bottom part folded up in two steps.
HELDOUT_FOLDS6 = SAMPLES / "heldout_folds6"
#: A seventh, likewise: a bag's right part folded back under two hands and snapped open, a
#: plush turned away by a corner about a rising axis, a board's corner folded over twice; each
#: at another distance from the camera.
HELDOUT_FOLDS7 = SAMPLES / "heldout_folds7"
#: An eighth, made after fur dyed in patches came to have its faint fine detail strengthened:
#: a calico plush turned away by a corner, a spotted plush folded back under two hands, a
#: watercolour card (a print with weak fine detail) folded over.
HELDOUT_FOLDS8 = SAMPLES / "heldout_folds8"
HELDOUT_ROOTS = (
    HELDOUT_FOLDS,
    HELDOUT_FOLDS2,
    HELDOUT_FOLDS3,
    HELDOUT_FOLDS4,
    HELDOUT_FOLDS5,
    HELDOUT_FOLDS6,
    HELDOUT_FOLDS7,
    HELDOUT_FOLDS8,
)
#: The doll counts as in view while at least this share of its true lattice is seen.
THIRD = 1.0 / 3.0
#: The hidden part is back once this share of the lattice is seen again.
RETURNED = 0.9
#: Sub-pixel: the mean error of the seen nodes below this many pixels.
SUBPIXEL = 1.0
#: The out-of-view marking is judged on frames where at least this share of the triangles
#: is unseen.
MARKED_FROM = 0.1
#: What the benchmark runs on every clip: the three trackers, then the nearest shape the
#: modes can take (the ``modes`` row, :func:`nearest_modal`).
#: ``both``: ours tracked forward, then back from the end, merged (a recorded take's
#: ``--both-ways``, see :mod:`voodoo_addon.takes.both_ways`).
TRACKERS = ("ours", "both", "klt", "dis", "modes")


def fold_clips(root: Path = FOLDS) -> list[Clip]:
    """The renders of folds under ``root`` (video, outline, truth)."""
    clips = []
    for video in sorted(root.glob("*.mp4")):
        outline = video.with_suffix(".json")
        truth = video.with_name(f"{video.stem}_truth.npz")
        if outline.exists() and truth.exists():
            clips.append(Clip(video.stem, video, outline, truth))
    return clips


def fold_suite() -> list[Clip]:
    """The fold clips the tracker was tuned on, then the held-out ones (every batch)."""
    return [clip for root in (FOLDS, *HELDOUT_ROOTS) for clip in fold_clips(root)]


def held_out(clip: Clip) -> bool:
    folder = clip.video.parent.resolve()
    return any(folder == root.resolve() for root in HELDOUT_ROOTS)


def open_area(truth: LatticeTruth) -> np.ndarray:
    """Per frame, the seen part's picture area over the lattice's area on frame 0 (T,).

    The seen part: the lattice cells whose four corners are seen.
    """
    lat, vis = truth.lattice, truth.visible >= 0.5
    a, b = lat[:, :-1, :-1], lat[:, :-1, 1:]
    c, d = lat[:, 1:, 1:], lat[:, 1:, :-1]

    def cross(p, q):
        return p[..., 0] * q[..., 1] - q[..., 0] * p[..., 1]

    area = 0.5 * np.abs(cross(a, b) + cross(b, c) + cross(c, d) + cross(d, a))
    cells = vis[:, :-1, :-1] & vis[:, :-1, 1:] & vis[:, 1:, 1:] & vis[:, 1:, :-1]
    return (area * cells).sum(axis=(1, 2)) / area[0].sum()


def recovery(err: np.ndarray, seen: np.ndarray, back_at: np.ndarray | None = None):
    """(return frame, frames from it to sub-pixel) of one track; None where there is none.

    The return is the first frame after the least-seen one where ``back_at`` (default
    ``seen``) is at least :data:`RETURNED` again; the second figure is None when the error
    never falls below :data:`SUBPIXEL` after it.
    """
    back_at = seen if back_at is None else back_at
    low = int(np.argmin(seen))
    back = np.flatnonzero(back_at[low:] >= RETURNED)
    if seen[low] >= RETURNED or not len(back):
        return None, None
    start = low + int(back[0])
    good = np.flatnonzero(err[start:] < SUBPIXEL)
    return start, (int(good[0]) if len(good) else None)


def judge(frames, blob, truth: LatticeTruth, verts, lost) -> dict:
    """One track of one clip, judged (see the module's list)."""
    score = score_track(frames, verts, blob.triangles, lost)
    err, seen = truth_errors(truth, blob.vertices, verts)
    lost = np.asarray(lost[: len(seen)], bool)
    back, to_subpixel = recovery(err, seen)
    opened, open_to_subpixel = recovery(err, seen, open_area(truth)[: len(seen)])
    return {
        **score.summary(),
        "error_px": round(float(np.nanmean(err)), 3),
        "error_p90_px": round(float(np.nanpercentile(err, 90)), 3),
        "lost_in_third": int(np.count_nonzero(lost & (seen >= THIRD))),
        "least_seen": round(float(seen.min()), 2),
        "returned_at": back,
        "recovery_frames": to_subpixel,
        "opened_at": opened,
        "open_recovery_frames": open_to_subpixel,
        "frame_error": np.round(err, 3).tolist(),
        "seen": np.round(seen, 3).tolist(),
    }


def marked(blob, truth: LatticeTruth, visible: np.ndarray, lost) -> tuple[float, float]:
    """(share of the unseen triangles reported out of view, share of the seen ones).

    ``visible`` (T, t): the triangles a track reports in view; see the module's list.
    """
    hit = unseen = wrong = seen = 0
    for i in range(min(len(truth), len(visible))):
        if lost[i]:
            continue
        _, nodes_seen = truth(i, blob.vertices)
        truly = nodes_seen[blob.triangles].sum(axis=1) >= 2
        out = ~np.asarray(visible[i], bool)
        wrong += np.count_nonzero(out & truly)
        seen += np.count_nonzero(truly)
        if np.count_nonzero(~truly) >= MARKED_FROM * len(truly):
            hit += np.count_nonzero(out & ~truly)
            unseen += np.count_nonzero(~truly)
    return (hit / unseen if unseen else np.nan), (wrong / seen if seen else np.nan)


def mode_jumps(amps: np.ndarray, lost: np.ndarray) -> tuple[float, float]:
    """(largest, median) RMS change of the mode amplitudes between tracked frames."""
    keep = ~np.asarray(lost, bool)
    steps = np.sqrt((np.diff(amps[keep], axis=0) ** 2).mean(axis=1))
    if not len(steps):
        return 0.0, 0.0
    return float(steps.max()), float(np.median(steps))


def true_modes(blob, truth: LatticeTruth, layout) -> np.ndarray:
    """The mode amplitudes (T, k) of the renderer's mesh.

    Every node's true position (seen or not), the similarity taken out (least squares),
    projected onto the modes.
    """
    fit = PointFit(blob, layout, blob.vertices)
    every = np.arange(blob.n_nodes)
    rest = blob.vertices.astype(np.float32)
    out = []
    for i in range(len(truth)):
        nodes = truth(i, blob.vertices)[0]
        mat, _ = cv2.estimateAffinePartial2D(rest, nodes.astype(np.float32), method=cv2.LMEDS)
        sim = similarity_from_matrix(mat, blob.centre)
        a = fit.fit(every, nodes, np.asarray(sim, np.float64)[:4], layout.identity(), 1e-4)
        out.append(a[layout.modes])
    return np.array(out)


def nearest_modal(blob, truth: LatticeTruth, layout) -> np.ndarray:
    """Per frame, the mesh (T, m, 2) of the modal shape nearest the renderer's seen nodes.

    The shapes of :func:`nearest_modal_params`.
    """
    return np.array(
        [
            node_positions(a, layout, blob.vertices, blob.modes, blob.centre)
            for a in nearest_modal_params(blob, truth, layout)
        ]
    )


def nearest_modal_params(blob, truth: LatticeTruth, layout) -> np.ndarray:
    """Per frame, the parameters (T, P) of the modal shape nearest the renderer's seen nodes.

    The similarity and the modes are fitted together by least squares on the seen nodes
    (a similarity taken out first and held would leave what it got wrong to the modes,
    which cannot turn or scale the doll). Frames where fewer than three nodes are seen
    keep the previous frame's shape. The lighting entries stay at none.
    """
    rest = blob.vertices.astype(np.float32)
    stop = layout.modes.stop
    fit = PointFit(blob, layout, blob.vertices)  # every node; each frame uses the seen ones
    a = layout.identity()
    out = []
    for i in range(len(truth)):
        nodes, seen = truth(i, blob.vertices)
        idx = np.flatnonzero(seen)
        if len(idx) >= 3:
            mat, _ = cv2.estimateAffinePartial2D(rest[idx], nodes[idx].astype(np.float32))
            if mat is not None:
                sim = np.asarray(similarity_from_matrix(mat, blob.centre, a[2]), np.float64)
                start = fit.fit(idx, nodes[idx], sim[:4], a, 1e-6)

                def misfit(p, idx=idx, target=nodes[idx], base=start):
                    full = base.copy()
                    full[:stop] = p
                    return (fit.positions(full)[idx] - target).ravel()

                a = start.copy()
                a[:stop] = least_squares(misfit, start[:stop], method="lm").x
        out.append(a.copy())
    return np.array(out)


#: The never-folding shape's barrier keeps each triangle's area this many times above the
#: fold guard's least (see :func:`nearest_unfolded_params`), so that it ends within bounds.
UNFOLDED_MARGIN = 1.4
#: How hard the barrier pushes, in pixels of node misfit per unit of area ratio.
UNFOLDED_BARRIER = 300.0


def nearest_unfolded_params(blob, truth: LatticeTruth, layout) -> np.ndarray:
    """Per frame, the parameters (T, P) of :func:`nearest_modal_params` that fold nothing.

    The nearest modal shape is fitted to the seen nodes alone, so where part of the doll is
    out of view the modes may put that part anywhere: over a turned-away half it folds
    dozens of triangles (``plush_flip`` frames 31-49, areas down to -16 times their rest
    area). The tracker never takes such a shape (``tracking.folding``), and the fitter pulls
    one back towards rest before starting from it, far from the truth (18-28 px there).
    Where the nearest shape leaves a triangle outside the fold guard's bounds, the modes
    are fitted to the seen nodes again with those bounds as a barrier
    (:data:`UNFOLDED_MARGIN`, :data:`UNFOLDED_BARRIER`), from the nearest shape pulled back
    within them and from the last frame's shape, whichever ends nearer; a result still
    outside them is pulled back too. The similarity and lighting stay the nearest shape's.
    """
    guard = FoldGuard(blob.vertices, blob.triangles, blob.modes[:, : layout.n_modes])
    fit = PointFit(blob, layout, blob.vertices)
    modes, stop = layout.modes, layout.modes.stop
    low, high = UNFOLDED_MARGIN * MIN_AREA, MAX_AREA / UNFOLDED_MARGIN  # the guard's bounds
    out, last = [], None
    for i, near in enumerate(nearest_modal_params(blob, truth, layout)):
        a = near.copy()
        if not guard.valid(a[modes]):
            nodes, seen = truth(i, blob.vertices)
            idx = np.flatnonzero(seen)

            def misfit(p, idx=idx, target=nodes[idx], base=near):
                full = base.copy()
                full[:stop] = p
                r = guard.ratios(full[modes])
                bounds = np.concatenate([np.maximum(0.0, low - r), np.maximum(0.0, r - high)])
                return np.concatenate(
                    [(fit.positions(full)[idx] - target).ravel(), UNFOLDED_BARRIER * bounds]
                )

            best = None
            for start in [guard.clamp(near[modes])] + ([] if last is None else [last[modes]]):
                x0 = near[:stop].copy()
                x0[modes] = start
                got = least_squares(misfit, x0, method="trf")
                best = got if best is None or got.cost < best.cost else best
            a[:stop] = best.x
            a[modes] = guard.clamp(a[modes])
        out.append(a)
        last = a
    return np.array(out)


def open_fold_clip(clip: Clip, camera: CameraFaults | None = None):
    """(frames, blob, truth) of a fold render: the blob built on its first frame.

    ``camera``: the faults to put on the frames first (None: the clean render).
    """
    frames, outline, _ = read_clip(clip)
    if camera is not None:
        frames = degrade(frames, camera)
    return frames, build_blob(to_float_rgb(frames[0]), outline), LatticeTruth(clip.truth)


def run_fold_clip(
    clip: Clip, trackers=("ours", "klt", "dis"), options=None, camera: CameraFaults | None = None
) -> list[dict]:
    """Every tracker on one clip; a row per tracker (with per-frame series).

    ``camera``: the faults to put on the frames first (None: the clean render).
    """
    frames, blob, truth = open_fold_clip(clip, camera)
    layout = ParamLayout(tuple(str(n) for n in blob.labels))
    rows = []
    forward = None
    for name in trackers:
        extra = {}
        if name in ("ours", "both"):
            if forward is None:
                forward = track_ours(frames, blob, options, params=True, visible=True)
            both = name == "both"
            passes = {}
            got = track_ours_both_ways(frames, blob, forward, options, passes) if both else forward
            verts, lost, secs, conf, params, visible = got
            amps = params[:, layout.modes]
            extra["confidence"] = np.round(conf, 3).tolist()
            hidden_marked, seen_marked = marked(blob, truth, visible, lost)
            extra["hidden_marked"] = round(float(hidden_marked), 3)
            extra["seen_marked"] = round(float(seen_marked), 3)
            jump, typical = mode_jumps(amps, lost)
            extra["mode_jump_px"] = round(jump, 2)
            extra["mode_step_median_px"] = round(typical, 3)
            if both:  # the crossfade's own jumps: beyond the larger of the two passes'
                back = passes["backward"]
                extra["backward_mode_jump_px"] = round(
                    mode_jumps(back.params[:, layout.modes], back.lost)[0], 2
                )
            truth_jump = mode_jumps(true_modes(blob, truth, layout), np.zeros(len(truth), bool))
            extra["true_mode_jump_px"] = round(truth_jump[0], 2)
        elif name == "modes":
            verts = nearest_modal(blob, truth, layout)
            lost, secs = np.zeros(len(verts), bool), None
        elif name == "klt":
            verts, lost, secs = track_klt(frames, blob.vertices)
        else:
            verts, lost, secs = track_dis(frames, blob.vertices)
        row = {
            "clip": clip.name,
            "held_out": held_out(clip),
            "tracker": name,
            "frames": len(frames),
        }
        row.update(judge(frames, blob, truth, verts, lost), **extra)
        row["median_ms"] = None if secs is None else round(1000.0 * float(np.median(secs)), 2)
        row["p95_ms"] = None if secs is None else round(1000.0 * float(np.percentile(secs, 95)), 2)
        rows.append(row)
    return rows


def run_folds() -> list[dict]:
    """Every fold clip, tuned and held out; rows without the per-frame series."""
    rows = []
    for clip in fold_suite():
        got = run_fold_clip(clip, TRACKERS)
        rows += [{k: v for k, v in r.items() if not isinstance(v, list)} for r in got]
    return rows


def format_folds(rows: list[dict]) -> str:
    """The Markdown table: a row per clip and tracker (held-out clips marked)."""
    lines = [
        "| clip | tracker | error px (p90), seen nodes | folded frames | lost while 1/3 seen "
        "| least seen | back in view at | frames to < 1 px | back open at | frames to < 1 px "
        "| out of view marked: unseen / seen "
        "| largest mode jump px (median step; the renderer's largest) | consistency mean | p10 "
        "| median / p95 ms |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        back, rec = _recovery(r["returned_at"], r["recovery_frames"])
        opened, open_rec = _recovery(r["opened_at"], r["open_recovery_frames"])
        name = f"{r['clip']} (held out)" if r["held_out"] else r["clip"]
        tracker = {"modes": "*modes at best*", "both": "ours, both ways"}.get(
            r["tracker"], r["tracker"]
        )
        ms = "—" if r["median_ms"] is None else f"{r['median_ms']:.1f} / {r['p95_ms']:.1f}"
        jump = mark = "—"
        if "hidden_marked" in r:
            mark = f"{_num(r['hidden_marked'], '.0%')} / {_num(r['seen_marked'], '.0%')}"
        if "mode_jump_px" in r:
            jump = (
                f"{r['mode_jump_px']:.2f} ({r['mode_step_median_px']:.2f}; "
                f"{r['true_mode_jump_px']:.2f})"
            )
        lines.append(
            f"| {name} | {tracker} | {r['error_px']:.2f} ({r['error_p90_px']:.2f}) | "
            f"{100 * r['folded_fraction']:.0f}% | {r['lost_in_third']} | {r['least_seen']:.2f} | "
            f"{back} | {rec} | {opened} | {open_rec} | {mark} | {jump} | "
            f"{_num(r['consistency_mean'])} | {_num(r['consistency_p10'])} | "
            f"{ms} |"
        )
    return "\n".join(lines)


def _recovery(at, frames) -> tuple[str, str]:
    if at is None:
        return "—", "—"
    return str(at), ("never" if frames is None else str(frames))


def _num(value, form: str = ".3f") -> str:
    """Three decimals (or ``form``), or a dash where there is nothing to judge (NaN)."""
    return "—" if value is None or not np.isfinite(value) else format(value, form)


def main(argv=None) -> int:
    import argparse
    import json

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--root", type=Path, help="one folder of clips (default: tuned and held out)")
    p.add_argument("--only", nargs="*", help="clip names")
    p.add_argument("--trackers", nargs="*", default=list(TRACKERS), choices=TRACKERS)
    p.add_argument("--json", help="write all rows (with per-frame series) here")
    add_camera_arguments(p)
    args = p.parse_args(argv)
    camera = chosen_camera(p, args)
    rows = []
    for clip in fold_clips(args.root) if args.root else fold_suite():
        if args.only and clip.name not in args.only:
            continue
        rows += run_fold_clip(clip, args.trackers, camera=camera)
    if args.json:
        Path(args.json).write_text(json.dumps(rows))
    print(format_folds(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
