"""The part of a doll out of view: kept out while it is hidden, found again when it is back.

A fold, a turn in depth or a hand hides part of a doll for a while. :class:`HiddenPart` is
what the tracker remembers of it from frame to frame, and the seven more fits it asks for
(:meth:`Tracker._hidden_part <voodoo_addon.tracking.tracker.Tracker>`):

- *still hidden*: a frame whose comparison was not close enough to tell covered from
  misaligned is fitted once more with the part left out -- the part out of view in the last
  frame, or else this frame's poorly fitting triangles when they lie beyond a line across
  the doll (:meth:`HiddenPart.covered`) -- and that fit is taken when it explains the part
  in view better (:func:`still_hidden`);
- *shown*: a faint doll is compared with its detail strengthened, and a part of it merely
  misaligned by a few pixels -- a folded half coming back -- then no longer correlates and
  is left out as covered, and a part left out is not pulled back into place. Once a large
  part has been out of view (:attr:`HiddenPart.away`), a fit that explains what it kept
  well but leaves out a large part that still correlates somewhat is made once more,
  coarse to fine from its own pose, with nothing left out, and taken when it explains the
  whole doll better and the part in view nearly as well (:func:`left_out`,
  :func:`shows_more`);
- *opening*: once a large part has been out of view, a fit that explains what it kept
  well but leaves a small part out that still correlates somewhat is made once more, from
  the last frame's pose, with the part it leaves out held at the doll's rest shape instead
  of the shape it was last seen in, and taken when it explains the whole doll and the part
  in view better (:func:`left_out`, :func:`opens_better`): a part misaligned by a pixel or
  two is left out as covered, and a part left out is held where it was, so the fit stays
  off the doll with it;
- *following on*: in the first frames after a large part was out of view
  (:attr:`HiddenPart.returning`), a fit that leaves a small part out that still correlates
  somewhat is made again from its own pose with that part held there, instead of where
  the last frame had it, up to :data:`FOLLOW_TIMES` times, each taken as the *opening*
  fit is (:func:`follows_on`, :func:`opens_better`): a part just back is still on its way
  in, and held at the last frame's shape it holds the whole fit a pixel off behind it;
- *settled back*: once the part is back, a fit under :data:`SETTLE_BELOW` whose pose at the
  rest shape glances nearly as well (:data:`SETTLE_GLANCE`) is tried from the rest shape,
  and taken when it is :data:`SETTLE_GAIN` surer (in the first :data:`FOLLOW_AFTER` frames
  after the part came back, as much surer as a search made again must be): a doll let go after a
  turn settles back at its rest shape, while the modal fit can stay stuck a few pixels off
  with the local stage's offsets making up the rest;
- *back*: after a frame with a large part out of view, the fit from the doll's rest shape
  (:func:`at_rest`) is taken when it brings that part back into view
  (:func:`returned`): a folded part comes back near its rest shape far more often than in
  the shape it was last seen in. It is refined at full resolution only when its coarse
  levels already explain the doll nearly as well as the fit at hand (:data:`RETURN_SLACK`),
  and made only while at least :data:`RETURN_GAIN` of the part out of view lies on the
  picture (:meth:`HiddenPart.on_picture`): a doll leaving the frame brings nothing back;
- *the way back*: a doll that turns or folds a part away mostly brings it back through
  the shapes it went away through. :class:`WayOut` keeps the poses of the frames before a
  large part went out of view; while it is out, a poor fit is compared with the few of
  them whose nodes in view lie nearest its own (:meth:`WayOut.nearest`), and the one that
  explains the frame best is taken when it explains it better than the fit and than the
  last frame's pose held still; where it does not, or glances up to :data:`RETURN_SLACK`
  below the fit, it is fitted (a trial) and taken when that brings the part back as the
  fit from the rest shape must (:func:`returned`).

It also says which triangles a frame's result reports in view (:meth:`HiddenPart.seen`):
those the fit kept, less the poorly fitting ones in a large region out of view. When the
doll is lost it keeps which part was out of view (:meth:`HiddenPart.lose`), so that the
pose held while it is lost is judged on the part that was in view.
"""

from __future__ import annotations

import numpy as np

from ..blob.mesh import triangle_edges
from . import kernels
from .creases import DIRECTIONS

#: After a frame where less than this share of the textured doll was in view (folded
#: under, turned away, covered), that part is remembered and the rest shape is tried.
RETURN_BELOW = 0.75
#: The fit from the rest shape is taken when it fits better and brings this much more of
#: the textured doll into view: the hidden part is back.
RETURN_GAIN = 0.1
#: That fit is made at full resolution only when its coarse levels end at a pose that
#: explains the doll nearly as well as the fit at hand: glanced at (the quality meter's own
#: pixels, ``CoarseToFineFitter.glance``) at most this much below its confidence. While the
#: part stays away the rest shape explains the doll worse, frame after frame: over the 21
#: fold renders and the 11 clips of the clip suite, 292 of the 708 such fits stop after the
#: coarse levels (the finest is over half a fit's time), while the six that brought a part
#: back had glanced at most 0.036 below; no track changes there, nor on the 54 faint draws.
RETURN_SLACK = 0.05
#: The *shown* fit is made when the fit explains the part it kept at least this well
#: (``Quality.in_view``) and leaves at least :data:`SHOWN_LEFT_OUT` of the textured doll out
#: as covered (see :func:`left_out`).
SHOWN_IN_VIEW = 0.8
SHOWN_LEFT_OUT = 0.1
#: ...and the part it leaves out still correlates with the template at least this much
#: (``Quality.left_out_correlation``, on the colours as they are): a part merely misaligned
#: does, somewhat; a part under something else mostly does not.
SHOWN_CORRELATION = 0.15
#: The *opening* fit is made when the fit leaves at least this share of the textured doll
#: out (the other bars as for the *shown* fit), and taken when it explains the whole doll
#: at least :data:`OPEN_GAIN` better and the part in view no worse (:func:`opens_better`).
OPEN_LEFT_OUT = 0.05
OPEN_GAIN = 0.01
#: *Following on*: in the first this many frames after the last one with a large part out
#: of view (:attr:`HiddenPart.returning`)...
FOLLOW_AFTER = 5
#: ...a fit that leaves at least this share of the textured doll out as covered, still
#: correlating at :data:`SHOWN_CORRELATION` or more (:func:`follows_on`), is made again from
#: its own pose with that part held there, at most :data:`FOLLOW_TIMES` times, each taken as
#: the *opening* fit is (:func:`opens_better`).
FOLLOW_LEFT_OUT = 0.03
FOLLOW_TIMES = 3
#: *Settled back*: once a large part has been out of view and is back, a fit under this...
SETTLE_BELOW = 0.8
#: ...whose pose at the rest shape glances at most this much below it is tried from there
#: (``Tracker._settled``).
SETTLE_GLANCE = 0.12
#: ...and taken when it is this much surer than the fit -- once the part has been back for
#: more than :data:`FOLLOW_AFTER` frames; before, while it may still be opening, as much
#: surer as a search made again must be (``tracker.AGAIN_GAIN``). Through a dim or noisy
#: camera the confidence of a doll at rest tops out near 0.78: ``toy_tail_lift`` through the
#: dim camera (seed 0) fitted 0.64-0.72 and stayed 2.3-3.3 px off on frames 78-86 where its
#: rest shape fitted 0.75-0.78, short of a 0.15 gain; with this bar it is 0.8-1.4 px off.
SETTLE_GAIN = 0.05
#: The way back (:class:`WayOut`): the poses of this many frames before a large part went
#: out of view are kept; they are tried from this many frames after it went...
WAY_OUT_FRAMES = 24
WAY_BACK_AFTER = 5
#: ...on the poses whose nodes in view lie nearest the fit's, this many of them...
WAY_BACK_NEAREST = 4
#: ...until the doll is back: this share of it in view, explained this well.
WAY_BACK_SHARE = 0.95
WAY_BACK_IN_VIEW = 0.8
#: Poorly fitting triangles are taken for a part folded away or covered when they make up
#: at least this share of the triangles beyond some line across the doll -- the line that
#: leaves all but :data:`ONE_SIDE_STRAY` of them beyond it.
ONE_SIDE = 0.65
ONE_SIDE_STRAY = 0.15
#: The *still hidden* fit is taken when it explains the part in view better and the whole
#: doll at most this much less well (see :func:`still_hidden`).
HELD_SLACK = 0.02
#: A result reports a kept triangle that fits poorly out of view when it lies in a region of
#: poorly fitting or left-out triangles, joined by their edges, of at least this share of the
#: doll's triangles (see :meth:`HiddenPart.seen`).
OUT_OF_VIEW_REGION = 0.1


class HiddenPart:
    """The large part of one doll out of view in the last frame, if any.

    Parameters
    ----------
    vertices : (m, 2) float64
        The blob's rest nodes.
    triangles : (t, 3) int
    share : (t,) float64, optional
        Each triangle's share of the textured doll (``QualityMeter.triangle_share``); by
        default all triangles alike.
    """

    def __init__(self, vertices: np.ndarray, triangles: np.ndarray, share=None):
        self.centroids = vertices[triangles].mean(axis=1)
        self._corners = np.asarray(triangles)
        t = len(triangles)
        self._share = np.full(t, 1.0 / max(t, 1)) if share is None else np.asarray(share)
        self._neighbours = _edge_neighbours(triangles)
        #: (t,) bool: the triangles out of view in the last frame the doll was found in,
        #: when they were a large part of it; None otherwise.
        self.triangles = None
        #: A large part has been out of view in some frame since the track began or the
        #: doll was last lost: a part left out now may be one coming back, and the *shown*
        #: fit is worth making (see :func:`left_out`). Before that, it is not: made while a
        #: faint half only began to fold, it sent the track elsewhere
        #: (``samples/heldout_folds/plush_flip`` through a dim camera: 30-42 px off over
        #: frames 52-68; 5.61 px on average against 8.87).
        self.away = False
        self._back_for = FOLLOW_AFTER + 1  # found frames since a large part was out of view

    def forget(self) -> None:
        self.triangles = None
        self.away = False
        self._back_for = FOLLOW_AFTER + 1

    @property
    def back(self) -> bool:
        """A large part has been out of view since the doll was last lost, and is back."""
        return self.away and self.triangles is None

    @property
    def returning(self) -> bool:
        """A large part was out of view, and is back since at most :data:`FOLLOW_AFTER` frames."""
        return self.back and self._back_for <= FOLLOW_AFTER

    def lose(self) -> None:
        """The doll was lost: that a part has been away is forgotten, not which part was.

        While the doll is lost, the pose it was last found in is judged on each frame with
        the part that was then out of view left out (``Tracker._track``), so a doll lost
        while half turned away is found again by the half in view.
        ``samples/heldout_folds6/minky_tail_swing`` redrawn with half a grey level of noise
        (``--camera redraw --seed 0``) was lost for 12 frames with its tail turned away and
        held 4.1-4.6 px off; judged on the rest it is found again on the next frame and
        followed 2.7-3.3 px off.
        """
        self.away = False

    def remember(self, share: float, visible) -> None:
        """After a tracked frame: ``share`` of the textured doll in view, ``visible`` (t,)."""
        if share < RETURN_BELOW and visible is not None:
            self.triangles = ~np.asarray(visible, bool)
            self.away = True
            self._back_for = 0
        else:
            self.triangles = None
            self._back_for += 1

    def on_picture(self, nodes: np.ndarray, size) -> float:
        """The share of the textured doll out of view in the last frame now on the picture.

        ``nodes`` (m, 2): the mesh in frame pixels; ``size``: the frame's (w, h). 0 when no
        large part was out of view. A part off the picture -- a doll leaving the frame --
        no fit can bring back into view (a triangle counts where its centroid lands).
        """
        if self.triangles is None:
            return 0.0
        c = nodes[self._corners].mean(axis=1)
        w, h = size
        on = (c[:, 0] >= 0) & (c[:, 0] < w) & (c[:, 1] >= 0) & (c[:, 1] < h)
        return float(self._share[self.triangles & on].sum())

    def covered(self, quality) -> np.ndarray | None:
        """The triangles to leave out in the *still hidden* fit of a frame (None: none).

        The part out of view in the last frame; else the frame's poorly fitting triangles
        (``Quality.poor``), when they are a large part of the doll and lie on one side.
        """
        if self.triangles is not None:
            return self.triangles
        if quality is None or quality.poor_share < 1.0 - RETURN_BELOW:
            return None
        return quality.poor if self.one_side(quality.poor) else None

    def seen(self, kept, poor) -> np.ndarray:
        """The triangles a frame's result reports in view (t,) bool.

        ``kept`` (t,) bool: the triangles the fit kept (not off the picture, covered or
        turned away); ``poor`` (t,) bool or None: the textured ones among them that do not
        correlate with the template (``Quality.poor``). A kept triangle that fits poorly is
        reported out of view when it joins, edge to edge, a region of poorly fitting or
        left-out triangles of at least :data:`OUT_OF_VIEW_REGION` of the doll: what a fold,
        a turn or a hand hides is a region, and the fit keeps the rim of it -- nearly
        edge-on, or covered by something the occlusion test took for the doll (a furry patch
        turned away, ``samples/heldout_folds2/plush_nod``: 7% of the part the renderer did not
        see was reported out of view, 58% with the rim). A crumple the fit cannot follow
        scatters poorly fitting triangles instead; one of them alone is still reported in
        view. Only the report: the tracker's own decisions use what the fit kept.
        """
        if kept is None:
            return None
        kept = np.asarray(kept, bool)
        if poor is None or not (poor & kept).any():
            return kept
        size = np.empty(len(kept), np.int64)
        kernels.region_sizes(self._neighbours, ~kept | poor, size)
        region = size >= OUT_OF_VIEW_REGION * len(kept)
        return kept & ~(poor & region)

    def one_side(self, poor: np.ndarray) -> bool:
        """The triangles ``poor`` (t,) bool lie beyond a line across the doll.

        A fold, a turn or a hand from one side hides a part like that; a crumple the fit
        cannot follow scatters poorly fitting triangles over the doll.
        """
        for angle in DIRECTIONS:
            along = self.centroids @ np.array([np.cos(angle), np.sin(angle)])
            beyond = along >= np.quantile(along[poor], ONE_SIDE_STRAY)
            if np.count_nonzero(poor & beyond) >= ONE_SIDE * np.count_nonzero(beyond):
                return True
        return False


class WayOut:
    """The poses a doll went through just before a large part of it went out of view.

    A tail turned away and back, a flap folded over and open again, comes back through
    the shapes it went away through, in the opposite order. The fits cannot find those
    shapes from where the part was last held (near its rest shape, open, while the part
    comes back nearly edge-on: ``samples/folds/tail_turn`` came back 35 px off where the
    nearest shape the modes can take is 2.5 px off, and took 15 frames to come under a
    pixel); the poses kept on the way out are starts near them.

    Parameters
    ----------
    nodes : callable
        ``a -> (m, 2)``: the modal mesh of the parameters ``a`` in frame pixels.
    """

    def __init__(self, nodes):
        self._nodes = nodes
        self.forget()

    def forget(self) -> None:
        self._recent = []
        #: The poses of the way out, oldest first, or None while no large part is out.
        self.path = None
        self._path_nodes = None
        self._age = 0

    @property
    def open(self) -> bool:
        """A large part went out of view at least :data:`WAY_BACK_AFTER` frames ago.

        In the first frames the fit still follows the part going away; a pose from just
        before that is the last frame's held still, not a way back.
        """
        return self.path is not None and self._age >= WAY_BACK_AFTER

    def record(self, a: np.ndarray, share: float, in_view: float) -> None:
        """After a frame the doll was found in: its pose, share in view and in-view quality."""
        if self.path is None:
            if share < RETURN_BELOW:
                if len(self._recent) >= 2:
                    self.path = self._recent
                    self._path_nodes = np.array([self._nodes(p) for p in self.path])
                    self._age = 0
                self._recent = []
            else:
                self._recent.append(a.copy())
                del self._recent[:-WAY_OUT_FRAMES]
        elif share >= WAY_BACK_SHARE and in_view >= WAY_BACK_IN_VIEW:
            self.forget()
            self._recent = [a.copy()]
        else:
            self._age += 1

    def nearest(self, nodes: np.ndarray, seen: np.ndarray) -> np.ndarray:
        """Indices into :attr:`path` of the poses nearest a fit, nearest first.

        ``nodes`` (m, 2): the fit's modal mesh; ``seen`` (k,) int: its nodes in view. The
        part in view is where the fit is sure, so it says how far along the way the doll
        is: on tail_turn's way back the nearest were the frames of its way out in the
        opposite order.
        """
        gap = self._path_nodes[:, seen] - nodes[seen]
        rms = np.sqrt((gap**2).sum(axis=2).mean(axis=1))
        return np.argsort(rms, kind="stable")[:WAY_BACK_NEAREST]


def _edge_neighbours(triangles: np.ndarray) -> np.ndarray:
    """(t, 3) int64: the triangle across each edge of each triangle, -1 where none."""
    t = len(triangles)
    edges = triangle_edges(triangles)
    owner = np.tile(np.arange(t), 3)
    slot = np.repeat(np.arange(3), t)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    e = edges[order]
    pair = np.flatnonzero((e[1:] == e[:-1]).all(axis=1))
    a, b = order[pair], order[pair + 1]
    out = np.full((t, 3), -1, np.int64)
    out[owner[a], slot[a]] = owner[b]
    out[owner[b], slot[b]] = owner[a]
    return out


def still_hidden(fit, held) -> bool:
    """The fit that left the hidden part out (``held``) is taken over ``fit``.

    It must explain the part in view better, and the whole doll nearly as well: within
    :data:`HELD_SLACK`. The whole-doll value judges the part it left out too, against
    whatever is in front of it now (a hand, the background, the doll's own back), so a fit
    that squeezes the whole doll into the part in view can score a hair higher there while
    it explains the part in view worse: on the squeezed label of ``samples/folds``, 0.377
    against 0.369 on the whole doll, 0.38 against 0.46 on the part in view; the squeezed
    fit drifted 5-8 px off the seen half for 35 frames.
    """
    return held.confidence >= fit.confidence - HELD_SLACK and held.in_view > fit.in_view


def left_out(fit, share: float = SHOWN_LEFT_OUT) -> bool:
    """``fit`` explains what it kept well, but leaves ``share`` of the doll or more out.

    Then, with the detail strengthened, the part left out may only be misaligned: the
    *shown* fit is worth making. On ``samples/heldout_folds/plush_flip`` the half that
    flips back came in 4 px off and stayed there, left out as covered, with the rest fitting
    at 0.92, for the 25 frames to the end. Only after a fit that explains the kept part
    well (:data:`SHOWN_IN_VIEW`): while a tail turns away, the whole-doll value favours a
    fit that drags the turned part onto the fur around it (tried after any fit, the track
    of ``samples/folds/tail_turn`` was 5.5 px off where it is 3.5, frames 40-46). Only
    when the part left out still correlates somewhat (:data:`SHOWN_CORRELATION`): on
    plush_flip's frames where the shown fit was taken, its returning half correlated at
    0.22-0.53; the folded-under half of ``samples/heldout_folds6/city_map_foldup`` at
    -0.14 to 0.10 on 17 of the 21 frames the fit was made, descents that left its track
    as it was (its median frame 7.5-8.1 -> 10.3-11.3 ms).
    """
    q = fit.quality
    if q is None or q.in_view < SHOWN_IN_VIEW or q.seen - q.share < share:
        return False
    return q.left_out_correlation >= SHOWN_CORRELATION


def follows_on(fit) -> bool:
    """The *following on* fit is worth making after ``fit`` (a part has just come back).

    ``fit`` leaves at least :data:`FOLLOW_LEFT_OUT` of the textured doll out as covered, and
    that part still correlates with the template at :data:`SHOWN_CORRELATION` or more: a part
    a pixel or two off does, somewhat; a part under a hand mostly does not (the real bag
    clip, squeezed by two hands, would otherwise make 25 of these fits rather than 12).
    """
    q = fit.quality
    if q is None or q.seen - q.share < FOLLOW_LEFT_OUT:
        return False
    return q.left_out_correlation >= SHOWN_CORRELATION


def opens_better(fit, opened) -> bool:
    """The *opening* fit (``opened``) is taken over ``fit``.

    It must explain the whole doll at least :data:`OPEN_GAIN` better and the part in view
    no worse. Where nothing had come back -- a glint left out on the glossy card of the
    clip suite -- the two fits differ by a few thousandths, either way; where a part held
    as it was last seen had come back, the fits taken on the fold renders explained the
    doll 0.018-0.24 better (``samples/folds/fold_squeeze``, opened flat again: the fit
    stayed 1.1-1.7 px off for seven frames with 6% of the doll left out, while the
    renderer's shape fitted better than it did; fitted from that shape it walked 1.4 px
    away, held by the part left out).
    """
    return opened.confidence >= fit.confidence + OPEN_GAIN and opened.in_view >= fit.in_view


def shows_more(fit, again) -> bool:
    """The *shown* fit's pose, or a pose of the way back, is taken over ``fit``.

    ``again``: that pose judged as any fit is, what is covered there left out again. It
    must explain the whole doll better, and the part it keeps at most :data:`HELD_SLACK`
    less well. A textured occluder -- another doll sliding over this one, a hand -- raises
    the whole-doll figure of a pose that pulls the doll onto it, and the part in view then
    fits worse. Taken as it was fitted, with nothing left out, the pose would report the
    part under the occluder in view too (two cards crossing, ``tests/engine/test_troupe.py``:
    the covered card's nodes reported in view were 0.58 px off on average, 3 px at its edge).
    """
    return again.confidence > fit.confidence and again.in_view >= fit.in_view - HELD_SLACK


def at_rest(a: np.ndarray, layout, frozen=frozenset()) -> np.ndarray:
    """``a`` with the free modes at rest (the pose, lighting and frozen modes kept)."""
    out = a.copy()
    modes = [k for k in range(layout.size)[layout.modes] if k not in frozen]
    out[modes] = 0.0
    return out


def returned(fit, back, hidden=None) -> bool:
    """The fit from the rest shape (``back``) shows the hidden part back in view.

    It explains the doll better than ``fit`` and brings at least :data:`RETURN_GAIN` more
    of it into view; and of the triangles it brings back (``hidden`` (t,) bool: the part
    out of view), fewer than half fit poorly. A card over half the doll, flat grey where
    the doll is faint, passes the occlusion test on many triangles; those are back in
    view only in name: they do not correlate with the template at all.
    """
    if back.quality is None or fit.quality is None:
        return back.quality is not None
    gain = back.quality.share - fit.quality.share
    if not (back.confidence > fit.confidence and gain >= RETURN_GAIN):
        return False
    if hidden is None or back.visible is None or back.quality.poor is None:
        return True
    back_again = hidden & back.visible
    poor = np.count_nonzero(back_again & back.quality.poor)
    return poor < 0.5 * np.count_nonzero(back_again)
