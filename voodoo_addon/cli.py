"""Command line: ``python -m voodoo_addon {blob,track,live,check,segment,bench,synth} ...``.

Bad input exits with status 2 and one line on stderr; see docs/design.md, *Command line*.
"""

from __future__ import annotations

import argparse
import json
import sys
from contextlib import ExitStack, nullcontext
from pathlib import Path

import numpy as np

from .checks import whole
from .errors import VoodooError


def _blob_options(args):
    from .blob.build import BlobOptions

    return BlobOptions(
        n_modes=args.modes,
        min_angle=args.min_angle,
        max_area=args.max_area,
        poly_degree=args.poly_degree,
    )


def _add_blob_args(p):
    p.add_argument("--modes", type=int, default=20, help="elastic modes (default 20)")
    p.add_argument("--min-angle", type=float, default=25.0, help="smallest triangle angle, degrees")
    p.add_argument("--max-area", type=float, default=None, help="largest triangle, square pixels")
    p.add_argument(
        "--poly-degree",
        type=int,
        default=3,
        help="polynomial tiers of the mode basis (0: plain FE vibration modes)",
    )


def cmd_blob(args) -> int:
    from .blob.build import build_blob
    from .blob.model import save_blob
    from .blob.outline import load_contour_json
    from .blob.preview import modes_picture
    from .media.images import check_picture_path, write_image
    from .media.sources import read_image

    if args.preview:
        check_picture_path(args.preview)  # before any work, and before the blob is written
    frame = read_image(args.frame)
    blob = build_blob(frame, load_contour_json(args.contour), _blob_options(args))
    save_blob(args.out, blob)
    for w in blob.warnings:
        print(f"warning: {w}", file=sys.stderr)
    if args.preview:
        write_image(args.preview, modes_picture(frame, blob))
    print(
        f"blob: {blob.n_nodes} nodes, {len(blob.triangles)} triangles, {blob.n_pixels} pixels, "
        f"{blob.n_modes} modes ({', '.join(blob.labels)}) -> {args.out}"
    )
    return 0


def _troupe(args, src, name: str | None = None, on_first=None):
    """The dolls of ``--contour`` and ``--blob`` (both repeatable), as a Troupe.

    Blobs are built on the source's first frame; a file is then rewound. ``name`` renames a
    single doll. ``on_first`` is called with that frame (a camera's footage keeps it: the
    camera's next frame is the first one tracked).
    """
    from .blob.build import build_blob
    from .blob.model import load_blob
    from .blob.outline import check_apart, contour_name, load_contour_json
    from .tracking.troupe import Troupe, doll_names

    contours, blob_files = args.contour or [], args.blob or []
    if not contours and not blob_files:
        raise VoodooError(f"{args.command} needs an outline (--contour) or a blob (--blob).")
    names = [contour_name(c) for c in contours] + [Path(b).name.split(".")[0] for b in blob_files]
    if name is not None:
        if len(names) > 1:
            raise VoodooError("--name names one doll; with several, name each in its outline.")
        names = [name]
    names = doll_names(names)
    blobs = []
    if contours:
        outlines = {n: load_contour_json(c) for n, c in zip(names, contours, strict=False)}
        check_apart(outlines)
        frame = src.read()
        if frame is None:
            raise VoodooError(f"{getattr(args, 'video', None) or args.source} gave no frame.")
        if on_first is not None:
            on_first(frame)
        blobs += [build_blob(frame.image, o, _blob_options(args)) for o in outlines.values()]
        if not src.live:
            src.seek(0)
    blobs += [load_blob(b) for b in blob_files]
    frozen = dict.fromkeys(names, getattr(args, "freeze", None) or ())
    return Troupe(dict(zip(names, blobs, strict=True)), frozen=frozen)


def cmd_track(args) -> int:
    from .media.prefetch import Prefetcher
    from .media.sources import open_source
    from .takes.dolls import save_takes, track_dolls
    from .takes.take import ProgressBar, missing_frames

    if args.frames is not None:
        whole(args.frames, "the number of frames (--frames)", 1)
    with open_source(args.video) as src:
        troupe = _troupe(args, src)
        long_clip = src.count is None or src.count > 30
        bar = ProgressBar(src.count) if long_clip and not args.quiet else None
        if args.both_ways and src.live:
            raise VoodooError(
                "--both-ways needs a file: a camera's frames cannot be read again backwards."
            )
        # Frames are decoded on a second thread (a second core) while this one tracks.
        with Prefetcher(src, limit=args.frames) as ahead:
            takes = track_dolls(troupe, ahead, progress=bar, limit=args.frames)
        short = missing_frames(src, next(iter(takes.values())), args.frames, name=str(args.video))
        if args.both_ways:
            show = long_clip and not args.quiet
            takes = _both_ways(troupe, takes, lambda: nullcontext(src), show, "forward")
    save_takes(args.out, takes)
    if short:
        print(f"warning: {short}", file=sys.stderr)
    for name, take in takes.items():
        n_lost = int(take.lost.sum())
        who = f" {name}:" if len(takes) > 1 else ""
        msg = f"track:{who} {len(take)} frames, mean confidence {take.confidence.mean():.2f}"
        if n_lost:
            msg += f", blob lost in {n_lost} frame(s)"
        print(msg + f" -> {args.out}")
    return 0


def cmd_live(args) -> int:
    from .live import LiveStats, run_live
    from .media.footage import Footage
    from .media.sources import open_source
    from .stream import OscSender, osc_name
    from .takes.dolls import save_takes

    if args.frames is not None:
        whole(args.frames, "the number of frames (--frames)", 1)
    if args.both_ways and not args.out:
        raise VoodooError("--both-ways needs --out: the take tracked both ways is written there.")
    sender = None
    if args.osc:
        try:
            sender = OscSender(args.osc, bundle=not args.messages)
        except VoodooError as exc:  # tracking goes on without the stream
            print(f"warning: {exc} Tracking without streaming.", file=sys.stderr)
    with open_source(args.source) as src, ExitStack() as stack:
        if args.both_ways and src.live and not args.footage:
            raise VoodooError(
                "--both-ways with a camera needs --footage FILE.avi: a camera's frames cannot "
                "be read again otherwise."
            )
        footage = None
        if args.footage:
            footage = stack.enter_context(Footage(args.footage, src.fps, src.size))
        # A camera's frame the blob is built on is in the footage too: footage frame N is
        # the source's frame N, as the take's frame indices count them.
        first = footage.write if footage is not None and src.live else None
        troupe = _troupe(args, src, args.name, first)
        where = ""
        if sender:
            dolls = ", ".join(f"/voodoo/{osc_name(n)}" for n in troupe.names)
            where = f" -> OSC {sender.target} as {dolls}"
        print(f"live: tracking {args.source}{where}; Ctrl-C stops", file=sys.stderr)
        stats = LiveStats()

        def status(st):
            if not args.quiet:
                print(f"live: {st.line()}", file=sys.stderr)

        interrupted = False
        try:
            write = footage.write if footage is not None else None
            run_live(src, troupe, sender, not args.fast, args.frames, stats, status, write)
        except KeyboardInterrupt:
            interrupted = True
        fps, live_source = src.fps, src.live
    if sender is not None:
        for warning in sender.warnings:
            print(f"warning: {warning}", file=sys.stderr)
        sender.close()
    if not stats.results:
        raise VoodooError("No frame was tracked.")
    msg = f"live: {stats.line()}" + (" (stopped)" if interrupted else "")
    if args.out:
        takes = stats.takes(troupe, fps)
        if args.both_ways:
            again = args.footage if live_source else args.source
            takes = _both_ways(troupe, takes, lambda: open_source(again), not args.quiet, "live")
        save_takes(args.out, takes)
        msg += f" -> {args.out}"
    print(msg)
    return 0


def _both_ways(troupe, takes: dict, reread, show: bool, kept: str) -> dict:
    """``--both-ways``: the takes merged with a backward pass (:mod:`.takes.both_ways`).

    ``reread()`` opens what is read backwards (the file tracked, or a camera's footage), as
    a context manager; ``show`` a progress bar. A failure, or Ctrl-C, keeps the takes as
    they were tracked (``kept``: "forward", "live"), with a warning.
    """
    from .takes.both_ways import backward_frames, track_both_ways
    from .takes.take import ProgressBar

    bar = ProgressBar(backward_frames(takes), "backwards") if show else None
    try:
        with reread() as src:
            return track_both_ways(troupe, src, takes, bar)
    except VoodooError as exc:
        print(f"warning: {exc} The take is kept as tracked {kept}.", file=sys.stderr)
    except KeyboardInterrupt:
        print(f"warning: stopped backwards; the take is kept as tracked {kept}.", file=sys.stderr)
    return takes


def cmd_check(args) -> int:
    from .media.sources import open_source
    from .takes.dolls import load_takes
    from .tracking.quality import check_take

    takes = load_takes(args.take)
    several = len(takes) > 1
    report = {}
    with open_source(args.video) as src:
        for name, take in takes.items():
            src.seek(0)
            report[name] = (take, check_take(src, take))
    if args.json:
        out = {name: score.report(take) for name, (take, score) in report.items()}
        print(json.dumps({"dolls": out} if several else next(iter(out.values()))))
        return 0
    for name, (take, score) in report.items():
        who = f" {name}:" if several else ""
        if args.per_frame:
            if several:
                print(f"{name}:")
            print("frame  consistency  seen  folded  lost  confidence")
            for row, i in enumerate(take.frame_indices):
                c = score.per_frame[row]
                print(
                    f"{int(i):5d}  {'   -  ' if not np.isfinite(c) else f'{c:7.3f}'}     "
                    f"{score.seen[row]:4.2f}  {'yes' if score.folded[row] else ' no'}     "
                    f"{'yes' if score.lost[row] else ' no'}   {take.confidence[row]:.3f}"
                )
        print(
            f"check:{who} {len(take)} frames; texture consistency mean {score.mean:.3f}, "
            f"10th percentile {score.p10:.3f}; folded frames {int(score.folded.sum())} "
            f"({100 * score.folded_fraction:.0f}%); lost frames {int(score.lost.sum())} "
            f"({100 * score.lost_fraction:.0f}%)"
        )
    return 0


def cmd_segment(args) -> int:
    from .blob.outline import save_contour_json
    from .blob.preview import draw_outline
    from .blob.segment import segment_contour
    from .media.images import check_picture_path, to_uint8_bgr, write_image
    from .media.sources import read_image

    if args.preview:
        check_picture_path(args.preview)
    frame = read_image(args.frame)
    contour = segment_contour(frame, point=args.point, box=args.box)
    save_contour_json(args.out, contour)
    if args.preview:
        canvas = to_uint8_bgr(frame)
        draw_outline(canvas, contour)
        write_image(args.preview, canvas)
    print(f"segment: outline of {len(contour)} points -> {args.out}")
    return 0


def cmd_bench(args) -> int:
    try:
        from .devtools import report as bench
    except ImportError:
        raise VoodooError(
            "The benchmark is a development tool: run it from a checkout of the repository."
        ) from None
    parts = bench.PARTS if not args.only else tuple(args.only)
    unknown = sorted(set(parts) - set(bench.PARTS))
    if unknown:
        raise VoodooError(f"Unknown part {unknown[0]!r}; pick from {', '.join(bench.PARTS)}.")
    if args.quick:
        parts = ("speed",)
    try:
        report = bench.run(parts, quick=args.quick)
    except RuntimeError as exc:
        raise VoodooError(f"The benchmark failed: {exc}") from None
    if args.json:
        print(json.dumps(report))
    else:
        bench.print_report(report)
    if args.write:
        written = bench.write(args.write, report)
        print(f"bench: {', '.join(written)} written into {args.write}", file=sys.stderr)
    return 0


def cmd_synth(args) -> int:
    from .blob.outline import save_contour_json

    try:
        from .devtools.scenarios import write_scenario
    except ImportError:
        raise VoodooError(
            "Synthetic takes are a development tool: run them from a checkout of the repository."
        ) from None

    contour = write_scenario(args.scenario, args.out, frames=args.frames, size=tuple(args.size))
    if args.contour:
        save_contour_json(args.contour, contour)
    print(f"synth: {args.scenario} take of {args.frames} frames -> {args.out}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m voodoo_addon", description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)

    b = sub.add_parser("blob", help="build an active blob from a frame and an outline")
    b.add_argument("frame", help="picture (or video: its first frame)")
    b.add_argument("--contour", required=True, help='JSON {"points": [[x, y], ...]}')
    b.add_argument("--out", required=True, help="blob file to write (.npz)")
    b.add_argument("--preview", help="PNG of the mesh and the modes")
    _add_blob_args(b)
    b.set_defaults(func=cmd_blob)

    t = sub.add_parser("track", help="track one or several dolls through a video")
    t.add_argument("video", help="video file, picture folder, or camera:N")
    t.add_argument(
        "--contour",
        action="append",
        help="outline on the first frame (JSON); repeat it for several dolls",
    )
    t.add_argument(
        "--blob", action="append", help="use this blob file instead of building one; repeatable"
    )
    t.add_argument("--out", required=True, help="take file to write (.npz), every doll in it")
    t.add_argument("--freeze", nargs="*", help="parameters held fixed, e.g. rotate scale")
    t.add_argument("--frames", type=int, help="stop after this many frames (needed for cameras)")
    t.add_argument("--quiet", action="store_true", help="no progress bar")
    t.add_argument(
        "--both-ways",
        action="store_true",
        help="track the take again backwards from its end and keep, frame by frame, the surer "
        "pass (files only; twice the time): parts that fold or turn away and come back are "
        "found sooner",
    )
    _add_blob_args(t)
    t.set_defaults(func=cmd_track)

    v = sub.add_parser("live", help="track a camera or a clip live and stream the motion over OSC")
    v.add_argument("source", help="camera:N, a camera index, a video file or a picture folder")
    v.add_argument(
        "--contour", action="append", help="outline on the first frame (JSON); repeatable"
    )
    v.add_argument(
        "--blob", action="append", help="use this blob file instead of building one; repeatable"
    )
    v.add_argument("--osc", metavar="HOST:PORT", help="send every frame there (OSC over UDP)")
    v.add_argument("--messages", action="store_true", help="plain messages, no bundles")
    v.add_argument("--name", help="one doll's name in the addresses (default: its file's)")
    v.add_argument("--fast", action="store_true", help="a file as fast as possible")
    v.add_argument("--frames", type=int, help="stop after this many frames")
    v.add_argument("--out", help="also write the take file (.npz)")
    v.add_argument(
        "--footage", metavar="FILE.avi", help="also write every frame read to this video file"
    )
    v.add_argument(
        "--both-ways",
        action="store_true",
        help="when tracking ends, track the take again backwards (from the file, or a camera's "
        "--footage) and write to --out, frame by frame, the surer pass",
    )
    v.add_argument("--quiet", action="store_true", help="no status line every second")
    _add_blob_args(v)
    v.set_defaults(func=cmd_live)

    c = sub.add_parser(
        "check", help="judge a take without ground truth: texture consistency, folds, losses"
    )
    c.add_argument("video", help="the video the take was tracked on")
    c.add_argument("take", help="take file (.npz) written by track")
    c.add_argument("--per-frame", action="store_true", help="a line per frame")
    c.add_argument("--json", action="store_true", help="print one JSON line")
    c.set_defaults(func=cmd_check)

    s = sub.add_parser("segment", help="find an object's outline automatically")
    s.add_argument("frame")
    g = s.add_mutually_exclusive_group(required=True)
    g.add_argument("--point", type=float, nargs=2, metavar=("X", "Y"), help="a point on the object")
    g.add_argument(
        "--box", type=float, nargs=4, metavar=("X0", "Y0", "X1", "Y1"), help="a box around it"
    )
    s.add_argument("--out", required=True, help="outline JSON to write")
    s.add_argument("--preview", help="PNG with the outline drawn")
    s.set_defaults(func=cmd_segment)

    e = sub.add_parser(
        "bench", help="speed, accuracy, the clip comparison with KLT and DIS (development)"
    )
    e.add_argument("--json", action="store_true", help="print one JSON line")
    e.add_argument("--quick", action="store_true", help="short synthetic sequences only")
    e.add_argument(
        "--only", nargs="+", help="parts: speed live dolls folds osc clips calibration hd"
    )
    e.add_argument("--write", metavar="FILE", help="put the tables into FILE (BENCHMARKS.md)")
    e.set_defaults(func=cmd_bench)

    y = sub.add_parser("synth", help="write a synthetic take with known motion")
    y.add_argument("scenario")
    y.add_argument("--out", required=True, help="video file (.mp4/.avi) or folder")
    y.add_argument("--contour", help="write the blob outline here (JSON)")
    y.add_argument("--frames", type=int, default=48)
    y.add_argument("--size", type=int, nargs=2, default=(320, 240), metavar=("W", "H"))
    y.set_defaults(func=cmd_synth)
    return p


def main(argv=None) -> int:
    from .media.sources import quiet_opencv

    args = build_parser().parse_args(argv)
    quiet_opencv()
    if args.command in ("track", "live") and not (args.contour or args.blob):
        print(f"error: {args.command} needs --contour (or --blob)", file=sys.stderr)
        return 2
    from .threads import single_blas_thread

    try:
        with single_blas_thread():  # small linear algebra: threads only spin (see there)
            return args.func(args)
    except VoodooError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except MemoryError:
        print("error: out of memory; use a smaller picture, outline or take.", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
