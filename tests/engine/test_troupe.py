"""Several dolls in one take: tracked together, the one in front covers the one behind.

The clip: two textured cards on a plain background; the left card slides over the right one
(drawn in front of it), covering half of it, and slides back. Ground truth is the drawing.
"""

import json
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.blob.outline import check_apart, contour_name
from voodoo_addon.devtools.synthetic import write_frames
from voodoo_addon.errors import VoodooError
from voodoo_addon.media.sources import ArraySource
from voodoo_addon.takes.both_ways import track_both_ways
from voodoo_addon.takes.dolls import (
    load_takes,
    save_takes,
    takes_from_bytes,
    takes_to_bytes,
    track_dolls,
)
from voodoo_addon.takes.take import load_take, save_take
from voodoo_addon.tracking.troupe import Troupe, doll_names

ROOT = Path(__file__).resolve().parents[2]
SIZE = (360, 240)
CARD = 80
LEFT0, RIGHT0, TOP = 40, 200, 80
FRAMES = 76


def _card(seed):
    rng = np.random.default_rng(seed)
    tex = cv2.GaussianBlur(rng.random((CARD, CARD, 3)).astype(np.float32), (0, 0), 2.5)
    tex = (tex - tex.min()) / (tex.max() - tex.min())
    return (40 + 180 * tex).astype(np.uint8)


def _left_x(i):
    """The left card's x: slides right 3 px a frame for 40 px of overlap, then back."""
    return LEFT0 + 3.0 * min(i, 40, max(0, 80 - i))


def _frames(left_x=None, frames=None):
    left_x = left_x or _left_x
    a, b = _card(1), _card(2)
    out = []
    for i in range(frames or FRAMES):
        f = np.full((SIZE[1], SIZE[0], 3), 128, np.uint8)
        f[TOP : TOP + CARD, RIGHT0 : RIGHT0 + CARD] = b
        m = np.float32([[1, 0, left_x(i)], [0, 1, TOP]])
        warped = cv2.warpAffine(a, m, SIZE, flags=cv2.INTER_LINEAR)
        inside = cv2.warpAffine(np.ones((CARD, CARD), np.uint8), m, SIZE) > 0
        f[inside] = warped[inside]
        out.append(f)
    return out


def _outline(x0):
    m = 8
    return np.array(
        [[x0 + m, TOP + m], [x0 + CARD - m, TOP + m], [x0 + CARD - m, TOP + CARD - m],
         [x0 + m, TOP + CARD - m]], float)  # fmt: skip


@pytest.fixture(scope="module")
def two_dolls():
    frames = _frames()
    first = frames[0].astype(np.float32) / 255
    blobs = {
        "left": build_blob(first, _outline(LEFT0)),
        "right": build_blob(first, _outline(RIGHT0)),
    }
    troupe = Troupe(blobs)
    takes = track_dolls(troupe, ArraySource(frames, fps=30.0))
    return frames, blobs, troupe, takes


def test_both_dolls_are_followed_through_the_crossing(two_dolls):
    frames, blobs, troupe, takes = two_dolls
    assert list(takes) == ["left", "right"]
    for name, take in takes.items():
        assert len(take) == FRAMES and not take.lost.any(), name
    # the left doll's nodes follow its card; the right doll's stay on its still card
    left, right = takes["left"], takes["right"]
    for i in range(FRAMES):
        shift = _left_x(i) - LEFT0
        err = np.abs(left.vertices[i] - (blobs["left"].vertices + [shift, 0])).max()
        assert err < 1.0, (i, err)
    tri = blobs["right"].triangles
    for i in range(FRAMES):
        seen = np.unique(tri[right.visible[i]])  # nodes of the triangles in view
        err = np.linalg.norm(right.vertices[i, seen] - blobs["right"].vertices[seen], axis=1)
        assert err.mean() < 0.5, (i, err.mean())
    # uncovered again, the whole doll is back in place
    apart = [i for i in range(FRAMES) if _left_x(i) + CARD < RIGHT0 - 4]
    assert apart[-1] == FRAMES - 1 and len(apart) > 8
    back = np.linalg.norm(right.vertices[apart[-5:]] - blobs["right"].vertices, axis=2)
    assert back.max() < 0.5, back.max()


def test_several_dolls_tracked_both_ways_cross_again_backwards(two_dolls):
    """Both ways (``takes.both_ways``): backwards, the cards cross again from the other
    side; the merged takes keep each doll on its card and the one behind covered, not lost."""
    frames, blobs, _, takes = two_dolls
    both = track_both_ways(Troupe(blobs), ArraySource(frames, fps=30.0), takes)
    assert list(both) == ["left", "right"]
    for name, take in both.items():
        assert len(take) == FRAMES and not take.lost.any(), name
        np.testing.assert_array_equal(take.frame_indices, takes[name].frame_indices)
    shift = np.array([_left_x(i) - LEFT0 for i in range(FRAMES)])
    err = np.abs(both["left"].vertices - blobs["left"].vertices - shift[:, None, None] * [1, 0])
    assert err.max() < 1.0, err.max()
    still = np.linalg.norm(both["right"].vertices - blobs["right"].vertices, axis=2)
    assert np.median(still) < 0.5 and still[-5:].max() < 0.5


def test_the_doll_behind_is_covered_not_lost(two_dolls):
    frames, blobs, troupe, takes = two_dolls
    assert troupe.in_front("left", "right") == "left"
    right = takes["right"]
    corners_x = blobs["right"].vertices[blobs["right"].triangles][..., 0]
    deepest = int(np.argmax([_left_x(i) for i in range(FRAMES)]))
    mesh_edge = _left_x(deepest) + CARD - 8  # the left doll's outline, 8 px inside its card
    under = corners_x.max(axis=1) < mesh_edge  # under the front doll's mesh
    clear = corners_x.min(axis=1) > mesh_edge + 8 + 6  # clear of its card
    assert under.any() and clear.any()
    assert not right.visible[deepest, under].any()  # covered triangles: not visible
    assert right.visible[deepest, clear].mean() > 0.9  # the rest: seen
    assert right.visible[0].all() and right.visible[-1].all()  # before and after: all seen
    assert not right.lost.any()
    assert takes["left"].visible[deepest].mean() > 0.9  # the front doll is seen whole


def test_a_take_of_several_dolls_round_trips_and_one_doll_files_stay_readable(two_dolls, tmp_path):
    _, _, _, takes = two_dolls
    path = tmp_path / "take.npz"
    save_takes(path, takes)
    back = load_takes(path)
    assert list(back) == ["left", "right"]
    for name in takes:
        np.testing.assert_array_equal(back[name].vertices, takes[name].vertices)
        np.testing.assert_array_equal(back[name].visible, takes[name].visible)
    with pytest.raises(VoodooError, match="several dolls .left, right."):
        load_take(path)
    one = tmp_path / "solo.npz"
    save_take(one, takes["left"])
    assert list(load_takes(one)) == ["solo"]  # a one-doll file: one doll named after it
    assert list(takes_from_bytes(takes_to_bytes({"x": takes["left"]}))) == ["doll"]


def test_damaged_files_of_several_dolls_are_refused(two_dolls):
    _, _, _, takes = two_dolls
    data = dict(np.load(__import__("io").BytesIO(takes_to_bytes(takes))))
    for broken in (
        {k: v for k, v in data.items() if k != "doll1.params"},
        {**data, "dolls": np.array(["a", "a"])},
        {**data, "doll1.frame_indices": data["doll1.frame_indices"] + 1},
        {**data, "doll0.vertices": np.full_like(data["doll0.vertices"], np.nan)},
    ):
        buf = __import__("io").BytesIO()
        np.savez(buf, **broken)
        with pytest.raises(VoodooError):
            takes_from_bytes(buf.getvalue(), "broken.npz")


def test_names_must_be_given_and_distinct():
    assert doll_names([" a ", "b"]) == ["a", "b"]
    for bad in ([], ["a", "a"], ["a", " "]):
        with pytest.raises(VoodooError):
            doll_names(bad)


def test_outlines_that_overlap_or_cross_are_refused():
    check_apart({"a": _outline(40), "b": _outline(200)})
    with pytest.raises(VoodooError, match="'a' and 'b' overlap"):
        check_apart({"a": _outline(40), "b": _outline(80)})
    cross = np.array([[60, 40], [70, 40], [70, 200], [60, 200]], float)  # through a, no corner in
    with pytest.raises(VoodooError, match="overlap"):
        check_apart({"a": _outline(40), "b": cross})


def test_a_doll_is_named_by_its_outline_file(tmp_path):
    plain = tmp_path / "paw.contour.json"
    plain.write_text(json.dumps({"points": _outline(40).tolist()}))
    named = tmp_path / "x.json"
    named.write_text(json.dumps({"name": "Tail", "points": _outline(40).tolist()}))
    assert contour_name(plain) == "paw" and contour_name(named) == "Tail"


def test_dolls_on_frames_of_different_sizes_are_refused(two_dolls):
    frames, blobs, _, _ = two_dolls
    small = cv2.resize(frames[0], (300, 200)).astype(np.float32) / 255
    other = build_blob(small, _outline(40))
    with pytest.raises(VoodooError, match="different sizes"):
        Troupe({"left": blobs["left"], "small": other})


@pytest.fixture(scope="module")
def clip_on_disk(tmp_path_factory):
    """The two cards as a lossless clip, and each card's outline file."""
    d = tmp_path_factory.mktemp("troupe")
    write_frames(d / "clip.avi", [f.astype(np.float32) / 255 for f in _frames()[:40]])
    for name, x0 in (("left", LEFT0), ("right", RIGHT0)):
        (d / f"{name}.contour.json").write_text(json.dumps({"points": _outline(x0).tolist()}))
    return d


def cli(d, *args):
    cmd = [sys.executable, "-m", "voodoo_addon", *map(str, args)]
    return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=300)


def test_the_command_line_tracks_one_doll_per_outline_into_one_take(clip_on_disk, tmp_path):
    d, out = clip_on_disk, tmp_path / "take.npz"
    done = cli(d, "track", d / "clip.avi", "--contour", d / "left.contour.json", "--contour",
               d / "right.contour.json", "--out", out, "--quiet")  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "track: left: 40 frames" in done.stdout and "track: right: 40 frames" in done.stdout
    takes = load_takes(out)
    assert list(takes) == ["left", "right"] and all(len(t) == 40 for t in takes.values())
    judged = cli(d, "check", d / "clip.avi", out, "--json")
    assert judged.returncode == 0, judged.stderr
    report = json.loads(judged.stdout)["dolls"]
    for name in ("left", "right"):
        assert report[name]["frames"] == 40 and sum(report[name]["folded"]) == 0
        assert report[name]["consistency_mean"] > 0.8, report[name]
    text = cli(d, "check", d / "clip.avi", out)
    assert "check: left: 40 frames" in text.stdout and "check: right: 40 frames" in text.stdout


def test_the_command_line_refuses_overlapping_outlines_and_twin_names(clip_on_disk, tmp_path):
    d, out = clip_on_disk, tmp_path / "take.npz"
    (d / "wide.json").write_text(
        json.dumps({"name": "wide", "points": [[30, 70], [300, 70], [300, 170], [30, 170]]})
    )
    (d / "twin.json").write_text(json.dumps({"name": "left", "points": _outline(RIGHT0).tolist()}))
    for other, says in (("wide.json", "overlap"), ("twin.json", "Two dolls are named 'left'")):
        done = cli(d, "track", d / "clip.avi", "--contour", d / "left.contour.json",
                   "--contour", d / other, "--out", out)  # fmt: skip
        assert done.returncode == 2, done.stderr
        assert says in done.stderr and "Traceback" not in done.stderr
        assert not out.exists()


def test_voodoo_live_streams_every_doll_on_every_frame(clip_on_disk, tmp_path, osc_receiver):
    d, out = clip_on_disk, tmp_path / "live.npz"
    rx = osc_receiver(240.0)
    done = cli(d, "live", d / "clip.avi", "--contour", d / "left.contour.json", "--contour",
               d / "right.contour.json", "--osc", f"127.0.0.1:{rx.port}", "--fast", "--quiet",
               "--out", out)  # fmt: skip
    rx.close()
    assert done.returncode == 0, done.stderr
    assert "/voodoo/left, /voodoo/right" in done.stderr
    takes = load_takes(out)
    got = {}  # (doll, frame) -> that doll's messages of that frame
    for dgram in rx.datagrams:
        msgs = dict(rx.messages(dgram))
        (frame_address,) = [a for a in msgs if a.endswith("/frame")]
        doll = frame_address.split("/")[2]
        got[doll, msgs[frame_address][0]] = msgs
    assert len(got) == 2 * 40 == len(rx.datagrams)
    for doll, take in takes.items():
        for row in range(len(take)):
            msgs = got[doll, row]
            np.testing.assert_allclose(
                msgs[f"/voodoo/{doll}/pose"], take.params[row, :4].astype(np.float32), rtol=1e-6
            )
            assert msgs[f"/voodoo/{doll}/quality"][1] == int(take.lost[row])
    named = cli(d, "live", d / "clip.avi", "--contour", d / "left.contour.json", "--contour",
                d / "right.contour.json", "--name", "x", "--frames", "2")  # fmt: skip
    assert named.returncode == 2 and "--name names one doll" in named.stderr


def test_the_benchmark_part_judges_each_doll_and_times_them_together_and_alone(tmp_path):
    from voodoo_addon.devtools.dolls import format_dolls, run_dolls

    write_frames(tmp_path / "cards.mp4", [f.astype(np.float32) / 255 for f in _frames()[:30]])
    for name, x0 in (("left", LEFT0), ("right", RIGHT0)):
        (tmp_path / f"cards.{name}.json").write_text(json.dumps({"points": _outline(x0).tolist()}))
    (result,) = run_dolls(tmp_path)
    assert {(r["doll"], r["tracker"]) for r in result["rows"]} == {
        (d, t) for d in ("left", "right") for t in ("ours", "klt", "dis")
    }
    speed = result["speed"]
    assert (
        speed["frames"] == 30 and speed["dolls"] == 2 and set(speed["alone"]) == {"left", "right"}
    )
    assert speed["together"][0] > 0 and speed["sum_alone_median"] > 0
    table = format_dolls([result])
    assert "| cards | left | ours |" in table and "| cards | 30 | 2 |" in table


def test_a_cover_frees_what_lies_outside_it_at_every_level():
    from voodoo_addon.tracking.evaluation import Cover

    mask = np.zeros((10, 20), bool)
    mask[2:5, 3:8] = True  # frame pixels x 13..17, y 32..34
    cover = Cover(mask, (10, 30))
    free = cover.free(np.array([13.0, 17.0, 18.0, 12.0, 500.0]), np.array([32.0, 34, 34, 33, 0]), 1)
    assert free.tolist() == [False, False, True, True, True]
    # at level 1 (scale 0.5), level pixel 7 is frame pixel 14
    assert cover.free(np.array([7.0, 2.0]), np.array([16.5, 16.5]), 0.5).tolist() == [False, True]
    assert cover.free(np.array([100.0]), np.array([100.0]), 1) is None  # far away: nothing


def test_what_covers_a_doll_reaches_every_comparison_of_it(two_dolls):
    """The fit's levels, the local stage and the crease search all compare the doll's pixels:
    each must leave out what another doll covers."""
    from voodoo_addon.tracking import Tracker
    from voodoo_addon.tracking.evaluation import Cover

    _, blobs, _, _ = two_dolls
    fitter = Tracker(blobs["left"]).fitter
    cover = Cover(np.ones((4, 4), bool), (0, 0))
    fitter.set_cover(cover)
    steps = [*fitter.levels, fitter.refiner.sub_step, fitter.creases.step]
    assert all(step.cover is cover for step in steps)
    fitter.set_cover(None)
    assert all(step.cover is None for step in steps)


def test_a_doll_that_jumps_onto_another_does_not_drag_it():
    """First contact at 30 px a frame: the order is only known once they overlap."""

    def jump(i):
        return LEFT0 + min(30.0 * i, 120.0, max(0.0, 30.0 * (24 - i)))

    frames = _frames(jump, 26)
    first = frames[0].astype(np.float32) / 255
    blobs = {
        "left": build_blob(first, _outline(LEFT0)),
        "right": build_blob(first, _outline(RIGHT0)),
    }
    takes = track_dolls(Troupe(blobs), ArraySource(frames, fps=30.0))
    right, tri = takes["right"], blobs["right"].triangles
    assert not right.lost.any() and right.visible[5].mean() < 0.7
    for i in range(26):
        seen = np.unique(tri[right.visible[i]])
        err = np.linalg.norm(right.vertices[i, seen] - blobs["right"].vertices[seen], axis=1)
        assert err.mean() < 0.6, (i, err.mean())
    assert np.abs(right.vertices[-1] - blobs["right"].vertices).max() < 0.5
