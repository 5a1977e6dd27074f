"""What an animator would use instead: OpenCV's point trackers run on the blob's mesh nodes.

Both follow the nodes frame to frame (no template), so they degrade gracefully but drift, and
nothing keeps their mesh from folding:

- :func:`track_klt` -- pyramidal Lucas-Kanade (``cv2.calcOpticalFlowPyrLK``) on the nodes;
- :func:`track_dis` -- dense DIS optical flow (``cv2.DISOpticalFlow``) sampled at the nodes.
"""

from __future__ import annotations

import time

import cv2
import numpy as np


def grey8(image: np.ndarray) -> np.ndarray:
    """uint8 grey of a float RGB [0, 1] or uint8 RGB picture."""
    img = np.asarray(image)
    if img.dtype != np.uint8:
        img = (np.clip(img, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)
    return cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)


def track_klt(frames, nodes, window: int = 21, levels: int = 3):
    """Pyramidal Lucas-Kanade on the nodes, frame to frame.

    Parameters
    ----------
    frames : sequence of (H, W, 3) pictures
    nodes : (m, 2) float64
        Node positions on the first frame.

    Returns
    -------
    vertices : (T, m, 2) float64
    lost : (T,) bool
        More than half of the nodes failed (status 0) in that frame.
    seconds : (T - 1,) float64
        Time spent tracking each frame after the first (grey conversion included).
    """
    prev = grey8(frames[0])
    pts = np.asarray(nodes, np.float32).reshape(-1, 1, 2)
    out, lost = [np.asarray(nodes, np.float64).copy()], [False]
    t = []
    for frame in frames[1:]:
        t0 = time.perf_counter()
        cur = grey8(frame)
        new, status, _ = cv2.calcOpticalFlowPyrLK(
            prev, cur, pts, None, winSize=(window, window), maxLevel=levels
        )
        t.append(time.perf_counter() - t0)
        ok = status.ravel() > 0
        pts = np.where(ok[:, None, None], new, pts)  # a failed node stays where it was
        out.append(pts.reshape(-1, 2).astype(np.float64))
        lost.append(bool(ok.mean() < 0.5))
        prev = cur
    return np.array(out), np.array(lost), np.array(t)


def track_dis(frames, nodes, preset: int = cv2.DISOPTICAL_FLOW_PRESET_MEDIUM):
    """DIS optical flow from each frame to the next, sampled (bilinearly) at the nodes.

    Returns (vertices (T, m, 2), lost (T,) all False, seconds) like :func:`track_klt`.
    """
    dis = cv2.DISOpticalFlow_create(preset)
    prev = grey8(frames[0])
    pts = np.asarray(nodes, np.float64).copy()
    out = [pts.copy()]
    t = []
    for frame in frames[1:]:
        t0 = time.perf_counter()
        cur = grey8(frame)
        flow = dis.calc(prev, cur, None)
        step = cv2.remap(
            flow,
            pts[:, 0].astype(np.float32).reshape(1, -1),
            pts[:, 1].astype(np.float32).reshape(1, -1),
            cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_REPLICATE,
        ).reshape(-1, 2)
        t.append(time.perf_counter() - t0)
        pts = pts + step
        out.append(pts.copy())
        prev = cur
    return np.array(out), np.zeros(len(out), bool), np.array(t)
