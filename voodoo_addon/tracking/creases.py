"""Creases: a doll folding along a line inside it, followed on both sides of the line.

A soft doll folded in half, or one half turned in depth about a line through it, shows the
far side of the line foreshortened towards it, more each frame, until it is a sliver; then
it opens again. No smooth field of the blob's modes bends that sharply, and the local stage
(:mod:`.refine`) follows a few pixels a frame, not a side sliding ten pixels towards a line.
So when the fit leaves much unexplained, :class:`CreaseSearch` tries creases: for a line
through the doll, the node offsets that press (or open) its far side along the line's normal

    U' = U + d * max(0, n . (S - p)) * n,   S = X - c + Phi a + U

(``S`` the doll's current shape in its rest frame, ``p`` a point of the line, ``n`` its unit
normal, ``d`` < 0 presses, ``d`` > 0 opens). Candidate lines run in eight directions through
three points across the doll, each with a few amounts; they are judged on a thin sample of
the pixels, the best then refined by the local stage on all of them. Once a crease was
taken, the next frames try only its own line (and lines beside it), so that a fold in
progress is followed frame by frame. The offsets move the tracked mesh only, as the local
stage's do: the similarity and the named modes are the modal fit's.

The same press shows a part out of view where it is likely to be (:meth:`CreaseSearch.pressed`):
turned away or folded under, it lies foreshortened towards its edge with the part in view.
"""

from __future__ import annotations

import numpy as np

from .evaluation import residuals

#: Directions of the candidate lines' normals (radians), and where the lines cross the
#: doll: offsets from its centre along the normal, in RMS radii.
DIRECTIONS = np.arange(8) * (np.pi / 4)
CROSSINGS = (-0.3, 0.0, 0.3)
#: Amounts ``d`` tried on every line in a full search, and around the last crease.
AMOUNTS = (-0.5, -0.25, 0.25)
NEAR_AMOUNTS = (-0.3, -0.15, -0.07, 0.07, 0.15, 0.3)
#: Lines beside the last crease: its crossing moved by this much (RMS radii).
NEAR_SHIFT = 0.1
#: Pixels the candidates are judged on (an even subsample of the finest level).
PROBE_PIXELS = 1500
#: Candidates refined by the local stage.
REFINED = 1
#: Amounts the part out of view is pressed towards its edge by (see
#: :meth:`CreaseSearch.pressed`).
PRESSES = (-0.95, -0.7, -0.5, -0.3)


class CreaseSearch:
    """Crease offsets for the local stage (see the module).

    Parameters
    ----------
    refiner : LocalRefiner
        The local stage (its level, fold guard, node positions and quality).
    blob : ActiveBlob
    """

    def __init__(self, refiner, blob):
        self.refiner = refiner
        level = refiner.level
        self.level = level
        self.probe, self.rows = level.every(max(1, len(level) // PROBE_PIXELS))
        self.step = refiner.step_.on(self.probe)
        self.radius = float(blob.length)
        self.line = None  # (point, normal) of the last crease taken, rest frame
        self._triangles = np.asarray(blob.triangles)
        self._rest = blob.vertices - blob.centre

    def forget(self) -> None:
        self.line = None

    def lines(self, shape: np.ndarray):
        """Candidate lines (point, unit normal) across a shape (m, 2) in the rest frame."""
        if self.line is not None:
            p, n = self.line
            return [(p + s * self.radius * n, n) for s in (0.0, -NEAR_SHIFT, NEAR_SHIFT)]
        centre = shape.mean(axis=0)
        out = []
        for angle in DIRECTIONS:
            n = np.array([np.cos(angle), np.sin(angle)])
            out += [(centre + t * self.radius * n, n) for t in CROSSINGS]
        return out

    def search(self, a, pictures, offsets, template=None, covered=None, needed=None):
        """The best crease offsets on a fit's frame, refined; None when none helps.

        ``a`` the modal fit, ``pictures`` its (FramePyramid, origin), ``offsets`` (m, 2)
        the local stage's so far (rest frame). Returns (offsets, Quality, Evaluation,
        line) of the best refined candidate. ``needed``: the confidence below which the
        caller will not take a crease; a refinement still far from it after two steps
        stops there, as the local stage's does (``LocalRefiner.run``).
        """
        images, origin = pictures
        ref = self.refiner
        step = self.step
        org, box = step.bind(images[step.index], origin)
        shape = ref.bare(a) + offsets
        amounts = NEAR_AMOUNTS if self.line is not None else AMOUNTS
        sub = None if template is None else np.ascontiguousarray(template[self.rows])
        tried, nodes = [], []
        for p, n in self.lines(shape):
            side = np.maximum((shape - p) @ n, 0.0)[:, None] * n  # (m, 2)
            if not side.any():
                continue
            for d in amounts:
                u = offsets + d * side
                tau = ref.guard.shape_step(shape, d * side)
                if tau < 1.0:
                    u = offsets + tau * d * side
                tried.append((u, (p, n)))
                nodes.append(ref._nodes(a, u) * self.level.scale)
        if not tried:
            return None
        found = residuals(
            self.probe, a, nodes, org, box, step.backend, step.norm, step.layout,
            cover=step.cover, template=sub,
        )  # fmt: skip
        scored = [(r, u, line) for r, (u, line) in zip(found, tried, strict=True) if r < np.inf]
        if not scored:
            return None
        scored.sort(key=lambda item: item[0])
        best = None
        for _, u, line in scored[:REFINED]:
            out = ref.run(a, 0.0, pictures, u, template, covered, needed)
            if out is not None and (best is None or out[1].value > best[1].value):
                best = (*out, line)
        return best

    def pressed(self, a, pictures, offsets, away):
        """The part out of view pressed towards its edge: (offsets, value) or None.

        ``away`` (t,) bool: the triangles out of view in the last frame. A part turning
        away about a line, or folding under, shows foreshortened towards that line; held
        in the shape it was last seen in it hangs over whatever lies beyond. Two shapes of
        that part are pressed along the normal of the line through its edge with the part
        in view: as it is now, and at rest, carried by the part in view (an affine map of
        the rest nodes of the part in view onto where they are). Each candidate is glanced
        at (the quality meter's pixels, the whole doll).
        """
        tri = self._triangles
        ref = self.refiner
        m = len(offsets)
        out = np.zeros(m, bool)
        out[tri[away].ravel()] = True
        kept = np.zeros(m, bool)
        kept[tri[~away].ravel()] = True
        edge = out & kept
        beyond = out & ~kept
        if np.count_nonzero(edge) < 2 or not beyond.any() or np.count_nonzero(kept) < 3:
            return None
        images, origin = pictures
        step = ref.step_
        org, box = step.bind(images[step.index], origin)
        plain = images.judged(step.index)
        turned = step.hidden(a)
        shape = ref.bare(a) + offsets
        rest = np.hstack([self._rest, np.ones((m, 1))])
        lift = np.linalg.lstsq(rest[kept], shape[kept], rcond=None)[0]
        attached = shape.copy()
        attached[beyond] = rest[beyond] @ lift
        best = None
        for base in (shape, attached):
            p = base[edge].mean(axis=0)
            along = np.linalg.svd(base[edge] - p)[2][0]
            n = np.array([-along[1], along[0]])
            if ((base[beyond] - p) @ n).mean() < 0:
                n = -n
            side = (np.maximum((base - p) @ n, 0.0) * beyond)[:, None] * n
            for d in PRESSES:
                move = (base - shape) + d * side
                u = offsets + ref.guard.shape_step(shape, move) * move
                v = ref.value(a, org, box, ref._nodes(a, u) * self.level.scale, turned, plain)
                if best is None or v > best[1]:
                    best = (u, v)
        return best
