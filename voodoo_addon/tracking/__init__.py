"""Tracking an active blob through frames: the per-level algorithm, the fitter, the tracker."""

from .options import TrackerOptions
from .tracker import Tracker, TrackResult

__all__ = ["TrackResult", "Tracker", "TrackerOptions"]
