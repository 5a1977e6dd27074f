"""Clips with several dolls (painted sheets) in one take, for tracking them all at once.

``MULTI`` lists them. ``render_hard_clips.py`` makes them only when asked by name, into a
folder of their own (``samples/multi``), apart from the single-sheet clips::

    .venv/bin/python scripts/render_hard_clips.py --out samples/multi --only two_dolls

A builder here returns ``{doll name: Sheet}`` instead of one ``Sheet``; every doll gets its own
outline (``NAME.DOLL.json``) and truth (``NAME_DOLL_truth.npz``), and the other dolls count as
occluders in its ``visible``.

``two_dolls``
    Two sheets with different paint (``hard_textures.spots`` on the left, ``label`` on the
    right) lie flat side by side on frame 0, about 70 px apart, the right one 0.12 nearer the
    camera. Apart, the left one bends towards the camera and drifts while the right one
    squashes, tilts and turns; then the right one slides in front of the left one, covering
    about half of it for about a second (the left one bent slightly away, so that they never
    touch), and they part again and end apart, almost flat.
"""

import hard_textures as paint  # scripts/ is on sys.path when a script runs

from hardclips.materials import studio_lights
from hardclips.scene import Clip
from hardclips.sheet import BEND_X_TOWARDS_CAMERA, add_sheet, bend, deform_origin, deg, finish_sheet

DOLL_SIZE = (2.1, 1.5)  # world units: about 218 x 156 px at the rest depth
DOLL_SEGMENTS = (84, 60)
DOLL_STRIDE = 6  # a 11 x 15 lattice, about 15 px apart
DOLL_X = 1.4  # the dolls' centres on frame 0: -1.4 and +1.4, 0.7 (about 73 px) apart
FRONT_Z = 0.12  # the right doll's height above the left one: it passes in front


def add_doll(name, texture, rng, location):
    sheet = add_sheet(texture, DOLL_SIZE, DOLL_SEGMENTS, DOLL_STRIDE, rng=rng)
    sheet.obj.name = name
    sheet.obj.location = location
    return sheet


def build_two_dolls(rng, clip):
    studio_lights()
    left = add_doll("LeftDoll", paint.spots, rng, (-DOLL_X, 0.0, 0.0))
    right = add_doll("RightDoll", paint.label, rng, (DOLL_X, 0.0, FRONT_Z))
    # The left doll bends along its length about its centre: towards the camera while the two
    # are apart, slightly away from it (its ends away from the right doll) while they cross.
    origin = deform_origin(left, (0.0, 0.0, 0.0), BEND_X_TOWARDS_CAMERA)
    bend(left, "Bend", origin)
    clip.keyframe(
        left.obj,
        {
            ('modifiers["Bend"].angle', 0): deg(
                [(0.0, 0), (0.1, 0), (0.9, 45), (1.6, -10), (2.3, -12), (3.0, -8), (3.9, 0)]
            ),
            ("location", 0): [
                (0.0, -DOLL_X),
                (0.1, -DOLL_X),
                (1.0, -1.6),
                (2.0, -1.0),
                (2.9, -0.95),
                (3.9, -1.45),
            ],
            ("location", 1): [(0.0, 0), (0.1, 0), (1.0, 0.25), (2.0, 0.05), (3.0, -0.08), (4.1, 0)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.1, 0), (1.2, -6), (2.8, 3), (4.2, 0)]),
        },
    )
    # The right doll squashes (narrower and a little taller), tilts and turns while apart; it
    # is flat (no tilt) from 1.4 s, before it reaches the left doll, until after they part.
    clip.keyframe(
        right.obj,
        {
            ("scale", 0): [(0.0, 1), (0.1, 1), (0.8, 0.72), (1.5, 0.92), (2.5, 0.86), (3.5, 1)],
            ("scale", 1): [(0.0, 1), (0.1, 1), (0.8, 1.08), (1.5, 1.0), (2.5, 1.04), (3.5, 1)],
            ("rotation_euler", 0): deg([(0.0, 0), (0.1, 0), (0.7, 12), (1.4, 0)]),
            ("rotation_euler", 2): deg(
                [(0.0, 0), (0.1, 0), (0.9, 12), (1.7, -6), (2.7, 4), (3.9, 0)]
            ),
            ("location", 0): [
                (0.0, DOLL_X),
                (0.1, DOLL_X),
                (1.0, 1.55),
                (2.1, 0.0),
                (2.5, -0.12),
                (2.9, 0.0),
                (3.9, 1.45),
            ],
            ("location", 1): [
                (0.0, 0),
                (0.1, 0),
                (0.9, -0.2),
                (2.0, 0.08),
                (3.1, 0.0),
                (4.1, 0.05),
            ],
        },
    )
    return {"left": finish_sheet(left), "right": finish_sheet(right)}


MULTI = [
    Clip(
        "two_dolls",
        144,
        30,
        "two dolls with different paint: the left bends and drifts, the right squashes, tilts "
        "and turns; then the right one passes in front of the left, covering about half of it "
        "for about 1 s, and they part and end apart, almost flat",
        build_two_dolls,
    ),
]
