"""Tracking an active blob through frames: the per-level algorithm, the fitter, the tracker."""

from .tracker import Tracker, TrackerOptions, TrackResult

__all__ = ["TrackResult", "Tracker", "TrackerOptions"]
