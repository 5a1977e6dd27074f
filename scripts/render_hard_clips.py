"""Render the hard test clips: a painted sheet bent, tilted, curled, crumpled, lit badly and shaken.

Run headless with the project's virtual environment (Blender as a Python module), one clip after
the other on one CPU core (the process pins itself to one core and renders with one thread)::

    .venv/bin/python scripts/render_hard_clips.py [--out samples/hard] [--only NAME ...]

``--draft`` renders the same scenes with Workbench in seconds (no motion blur, no Cycles
shading) to check the geometry and the ground truth; its clips are not the committed ones.

Every clip NAME writes into ``--out``:

``NAME.mp4``
    H.264 from Blender's FFmpeg, 640x360, with mild gaussian sensor noise added before encoding.
``NAME.json``
    ``{"points": [[x, y], ...]}``: a closed outline (a rounded rectangle, clockwise on screen) of
    a region of the sheet on frame 0, about ``OUTLINE_MARGIN`` px inside the sheet's edge, in
    OpenCV pixel coordinates (origin at the centre of the top-left pixel, y down).
``NAME_truth.npz``
    ``lattice`` (T, R, C, 2) float32: where a regular R x C grid of sheet points is in every
    frame, same pixel convention, projected from Blender's evaluated (deformed) mesh;
    ``visible`` (T, R, C) bool: the point is inside the image, on the side of the sheet turned
    towards the camera and not hidden by anything (a ray cast from the camera); ``fps``.
    On frame 0 the sheet lies flat and square to the camera, so there the lattice is an
    axis-aligned grid (see ``lattice_truth`` in ``voodoo_addon/devtools/bench.py``).

and ``README.md`` lists the clips. The clips (all but ``fast_8fps`` at 30 fps; perspective
camera; every sheet holds its rest pose for the first three frames):

``bend_out``
    One half of a matte foam patch bends towards the camera up to 80 degrees and back while the
    whole patch drifts: strong foreshortening and a fold line.
``tilt_twist``
    The patch tilts 55 degrees about a horizontal axis and back, then 55 degrees about a vertical
    axis and back, then twists 45 degrees end to end and back: perspective foreshortening.
``curl_away``
    The top edge curls away from the camera through 210 degrees, holds, and unrolls flat: the
    painted side turns its back to the camera and part of it is hidden (``visible`` false).
``glossy``
    A varnished (roughness 0.2) sheet bends and turns under a small strong lamp beside the
    camera: specular highlights and shading sweep across the paint.
``lighting_drift``
    Ten seconds of slow, gentle motion of a photo-like, low-contrast print while the exposure
    hunts (slow drift and steps of x1.5 and x0.7), the white balance drifts (+-15 % per
    channel) and the shadow of an unseen hand passes over the sheet twice.
``fast_8fps``
    8 fps: mostly 20-45 px of motion per frame, turns of up to 11 degrees per frame and bending,
    with Cycles motion blur (the truth is at the shutter's centre).
``crumple``
    A thin printed bag crumples: creases grow, the sheet is squeezed and folds over itself so
    that some of it is hidden for a while, then it relaxes almost flat.

The held-out clips of ``hardclips/heldout.py`` (``handheld_zoom``, ``occluded_exit``,
``glossy_fast_twist``), for checking that the tracker generalises, are made only when named with
``--only`` (not together with the others), into a folder of their own outside ``samples/``.

The clips of several dolls in one take (``hardclips/multi.py``) are likewise made only when named,
into ``samples/multi``::

    .venv/bin/python scripts/render_hard_clips.py --out samples/multi --only two_dolls

They write one outline and one truth per doll DOLL: ``NAME.DOLL.json`` and
``NAME_DOLL_truth.npz``, in the formats above, where ``visible`` is also false where another
doll hides the point:

``two_dolls``
    Two sheets with different paint (spots on the left, a printed label on the right) side by
    side and about 70 px apart on frame 0. Apart, the left one bends towards the camera and
    drifts while the right one squashes, tilts and turns; then the right one (0.12 nearer the
    camera) slides in front of the left one, covering about half of it for about a second,
    and they part and end apart, almost flat.

The clips of folds (``hardclips/folds.py``), whose sheets fold in half or over themselves or
turn past edge-on and back, are likewise made only when named, into ``samples/folds``::

    .venv/bin/python scripts/render_hard_clips.py --out samples/folds --only fold_squeeze \
        tail_turn sheet_foldover

``fold_squeeze``
    Two hands squeeze a printed label from the left and right: its right half folds back behind
    its left half in about half a second, holds, unfolds, and the hands leave.
``tail_turn``
    A furry, low-contrast stuffed-toy patch is turned in depth by one end: its body turns 40
    degrees and its tail end on to 95 degrees, past edge-on, and back.
``sheet_foldover``
    The top 35 % of a printed sheet folds 180 degrees over the rest, towards the camera, and back.

The held-out clips of folds (``hardclips/heldout_folds.py``) show the same kinds of motion with
other paint (``heldout_textures.py``) and other motion, to check that the tracker, tuned on the
clips of folds, generalises (never to tune it on). They too are made only when named, apart from
every other clip, into ``samples/heldout_folds``::

    .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds --only pouch_crush \
        plush_flip cloth_corner_fold

``pouch_crush``
    Two hands squeeze a printed snack pouch from the top and bottom: its top part folds back
    behind the rest along a roughly horizontal crease in half a second, holds, unfolds, and the
    hands leave.
``plush_flip``
    A furry, low-contrast grey and cream plush patch, held by its left end, turns away from the
    camera about a vertical axis near its right end: its right part turns 35 degrees and its
    left part on to 100 degrees, past edge-on, and back, while it drifts.
``cloth_corner_fold``
    The bottom right corner of a printed t-shirt cloth folds 180 degrees diagonally over the
    rest, towards the camera, and back.

A second batch of held-out clips of folds (``hardclips/heldout_folds2.py``, paint there too),
made after the tracker's last change, likewise never to tune it on and made only when named,
apart from every other clip, into ``samples/heldout_folds2``::

    .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds2 --only \
        box_side_squeeze plush_nod paper_half_fold

``box_side_squeeze``
    Two hands squeeze the printed face of a cereal carton from the left and right: its left
    part folds back behind the rest along a roughly vertical crease left of the centre in 0.4
    s while it is pushed along, holds, unfolds, and the hands leave.
``plush_nod``
    A furry, low-contrast honey and cocoa plush patch, held at its bottom edge by a hand, nods
    away from the camera about a horizontal axis: its top part on to 100 degrees, past edge-on,
    and back.
``paper_half_fold``
    The left part of a printed poster folds 180 degrees over the rest, towards the camera, in a
    soft loop, and back, while the sheet turns a few degrees in its plane.

A third batch of held-out clips of folds (``hardclips/heldout_folds3.py``, paint there too),
made for issue 22's check that the tracker generalises, likewise never to tune it on and made
only when named, apart from every other clip, into ``samples/heldout_folds3``::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds3 \
        --only bag_fold_hands toy_tail_lift shirt_fold_print

``bag_fold_hands``
    Two hands, in from the upper left and the lower right, squeeze a glossy foil snack bag
    lying off the middle: its upper left part folds back behind the rest along a diagonal
    crease in 0.45 s while it is pushed along, its logo staying in view; it holds, unfolds,
    and the hands leave along the diagonal.
``toy_tail_lift``
    A furry, low-contrast grey-blue plush patch with faint stripes, held by a hand at its lower
    right corner, turns away from the camera about an axis tilted 30 degrees from the vertical:
    the patch 50 degrees and its far part on to 105 degrees, past edge-on, and back, while it
    drifts.
``shirt_fold_print``
    The top part of a cloth with a big t-shirt print folds down 180 degrees over its print,
    towards the camera, about a crease tilted 9 degrees, slowly, and back, while the cloth
    slides sideways.

A fourth batch of held-out clips of folds (``hardclips/heldout_folds4.py``, paint there too),
made after the tracker's last change for issue 22's check that it generalises, likewise never
to tune it on and made only when named, apart from every other clip, into
``samples/heldout_folds4``::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds4 \
        --only kraft_bag_squeeze fleece_tail_raise comic_page_fold

``kraft_bag_squeeze``
    Two hands, in from below and from the right, squeeze a matte kraft paper coffee bag lying
    off the middle: its bottom part folds back behind the rest in half along a crease falling
    14 degrees to the right, slowly (0.8 s), while it is pushed up and left; it holds,
    unfolds, and the hands leave.
``fleece_tail_raise``
    A furry, low-contrast sage green plush patch with curly fur, held by a hand at its lower
    left corner, is lifted towards the camera about an axis 12 degrees off the horizontal: the
    patch 35 degrees and its lower half on to 115 degrees, past edge-on, fast, and back, while
    it drifts.
``comic_page_fold``
    The right part of an upright printed comic page folds over to the left by 180 degrees,
    towards the camera, about a crease leaning 7 degrees from the vertical, fast, and unfolds
    slowly while the page drifts and turns a little.

A fifth batch of held-out clips of folds (``hardclips/heldout_folds5.py``, paint there too),
made after the fourth for issue 22's check that the tracker generalises, likewise never to
tune it on and made only when named, apart from every other clip, into
``samples/heldout_folds5``::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds5 \
        --only felt_yaw_turn denim_corner_tuck bandana_diagonal_fold

``felt_yaw_turn``
    A folk-art felt coaster with appliqued flowers, held by a hand behind the middle of its
    left edge, is turned as a whole (no crease) in depth about an axis through the hand
    leaning 8 degrees from the vertical, its right edge away from the camera, to 75 degrees
    (strongly foreshortened, not past edge-on) in 0.7 s, and back while it drifts; the hand
    leaves.
``denim_corner_tuck``
    The lower right corner of a denim patch with iron-on patches folds back 180 degrees behind
    the rest about a diagonal crease, at a medium speed, while a hand in from the upper right
    lies over the upper right part; it holds, unfolds, and the hand leaves.
``bandana_diagonal_fold``
    The top left triangle of a square red paisley bandana folds over towards the camera by 180
    degrees about a crease along (a little off) its diagonal, fast, and unfolds slowly while
    the cloth turns 8 degrees and drifts.

A sixth batch of held-out clips of folds (``hardclips/heldout_folds6.py``, paint there too),
made after the fifth for issue 22's check that the tracker generalises, likewise never to
tune it on and made only when named, apart from every other clip, into
``samples/heldout_folds6``::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds6 \
        --only peas_bag_squeeze minky_tail_swing city_map_foldup

``peas_bag_squeeze``
    Two hands, in from above and from the left, squeeze a glossy bag of frozen peas lying
    above the middle: its upper part folds back behind the rest in half along a crease
    falling 25 degrees to the right, fast (0.34 s), while it is pushed down; it holds,
    unfolds slowly, and the hands leave.
``minky_tail_swing``
    A furry, low-contrast dusty pink minky plush patch with raised dots, held by a hand at its
    upper right corner, is lifted towards the camera about an axis falling 40 degrees to the
    right: the patch 25 degrees and its upper right part on to 110 degrees, past edge-on,
    slowly, and back fast, while it drifts up.
``city_map_foldup``
    The bottom part of a printed city street map folds up over the rest by 180 degrees,
    towards the camera, about a crease falling 5 degrees to the right, in two steps, and
    unfolds while the map comes nearer the camera, drifts and turns 6 degrees.

A seventh batch of held-out clips of folds (``hardclips/heldout_folds7.py``, paint there too),
made after the sixth for issue 22's check that the tracker generalises, likewise never to
tune it on and made only when named, apart from every other clip, into
``samples/heldout_folds7``::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds7 \
        --only gummy_bag_squeeze shag_tail_turn board_corner_flutter

``gummy_bag_squeeze``
    Two hands, in from the right and from the lower left, squeeze a glossy bag of gummy bears
    lying left of and above the middle, nearer the camera: its right part folds back behind
    the rest about a crease leaning 20 degrees from the vertical, at a medium pace (0.58 s),
    while it is pushed left and up; it holds, snaps back open fast (0.26 s), and the hands
    leave.
``shag_tail_turn``
    A furry, low-contrast caramel shaggy plush patch with long wavy locks, farther from the
    camera, held by a hand at its upper left corner, is turned away from the camera about an
    axis rising 50 degrees to the right: the patch 20 degrees and its upper left part on to
    120 degrees, past edge-on, fast, held long, and back slowly while it drifts left and down.
``board_corner_flutter``
    The top right corner of a printed snakes-and-ladders board, farther from the camera, folds
    over onto the rest by 180 degrees, towards the camera, about a crease falling 55 degrees
    to the right, half opens and folds over again, and unfolds while the board slides right
    and turns 7 degrees.

An eighth batch of held-out clips of folds (``hardclips/heldout_folds8.py``, paint there too),
made after the seventh for issue 22's check that the tracker generalises, likewise never to
tune it on and made only when named, apart from every other clip, into
``samples/heldout_folds8``::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds8 \
        --only calico_tail_turn spotted_plush_squeeze watercolour_card_fold

``calico_tail_turn``
    A furry stuffed-toy patch of calico faux fur, a faint short pile dyed in large soft-edged
    patches of cream, ginger and brown-black (its colours vary a lot overall, its fine texture
    is faint), left of and above the middle, held by a hand at its lower left corner, is
    turned away from the camera about an axis falling 65 degrees to the right: the patch 30
    degrees and its lower left half on to 110 degrees, past edge-on, at a moderate pace
    (0.8 s), held 0.45 s, and back while it drifts right and up.
``spotted_plush_squeeze``
    Two hands, in from the lower left and from above, squeeze a white plush patch with large
    soft-edged black spots lying right of and below the middle: its lower left part (49 %)
    folds back behind the rest about a crease rising 62 degrees to the left in 0.5 s while it
    is pushed right and up; it holds, opens again gently (0.7 s), and the hands leave.
``watercolour_card_fold``
    The left side (30 %) of a printed watercolour card (soft washes, weak fine detail) below
    the middle folds over onto the rest by 180 degrees, towards the camera, about a crease
    leaning 16 degrees from the vertical, in 0.75 s, holds and unfolds in 0.9 s while the card
    slides left and up and turns 3 degrees.

Everything is seeded: the same command makes the same scenes, truth and outlines (Cycles runs
seeded on one thread, so the renders should repeat too). The seven tuned clips, which a run
without ``--only`` renders, take about 50 minutes; the held-out, several-doll and fold clips are
rendered by naming them with ``--only``.

This file is the command line; the work is in ``hardclips/`` (scene, materials, sheet,
scenarios, truth, video, make: see its ``__init__``), built on ``blender_scene.py``,
``foam_paint.py`` and ``hard_textures.py``. Importing ``hardclips`` pins the process to one core
before bpy starts.
"""

import argparse
from pathlib import Path

from hardclips.make import GROUPS, make_clip, write_readme  # scripts/ on sys.path; pins one core
from hardclips.scenarios import CLIPS

EVERY = CLIPS + [clip for group in GROUPS for clip in group.clips]


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("samples/hard"), help="output folder")
    parser.add_argument(
        "--only",
        nargs="+",
        choices=[c.name for c in EVERY],
        help="make only these clips (the held-out, several-doll and fold ones only so)",
    )
    parser.add_argument(
        "--draft", action="store_true", help="render with Workbench, to check the geometry"
    )
    parser.add_argument(
        "--truth-only", action="store_true", help="write the ground truth, render nothing"
    )
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.only is None:
        clips = CLIPS  # never the held-out clips
    else:
        clips = [c for c in EVERY if c.name in args.only]
        for group in GROUPS:
            if any(c in group.clips for c in clips) and any(c not in group.clips for c in clips):
                raise SystemExit(f"make {group.name} apart from the others, in another folder")
    total = 0.0
    for clip in clips:
        total += make_clip(clip, args.out, args.draft, args.truth_only)
    if not (args.draft or args.truth_only):
        group = next((g.clips for g in GROUPS if clips[0] in g.clips), CLIPS)
        write_readme(args.out, group)
    print(f"rendering took {total:.0f} s in all")


if __name__ == "__main__":
    main()
