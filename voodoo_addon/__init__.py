"""Active Voodoo Dolls engine: active blobs and their tracker (Isidoro & Sclaroff 1998).

Plain Python (numpy, SciPy, OpenCV, triangle); never imports Blender. Typical use::

    from voodoo_addon import build_blob, Tracker, open_source, track_source

    with open_source("take.mp4") as src:
        blob = build_blob(src.read_at(0).image, outline_points)
        src.seek(0)
        take = track_source(blob, src)
"""

from .blob.build import BlobOptions, build_blob
from .blob.interpolants import GaussianInterpolant
from .blob.model import ActiveBlob, blob_from_bytes, blob_to_bytes, load_blob, save_blob
from .blob.outline import load_contour_json, save_contour_json, simplify_contour, validate_contour
from .blob.segment import mask_contour, segment_contour, segment_mask
from .errors import VoodooError
from .media.images import to_float_rgb
from .media.sources import FrameSource, open_source, read_image
from .takes.dolls import load_takes, save_takes, track_dolls
from .takes.take import Take, load_take, save_take, track_source
from .tracking import Tracker, TrackerOptions, TrackResult
from .tracking.norms import LorentzianNorm, QuadraticNorm, RobustNorm
from .tracking.params import ParamLayout
from .tracking.troupe import Troupe
from .tracking.warp import CpuWarp, WarpBackend, WarpGeometry

__all__ = [
    "ActiveBlob",
    "BlobOptions",
    "CpuWarp",
    "FrameSource",
    "GaussianInterpolant",
    "LorentzianNorm",
    "ParamLayout",
    "QuadraticNorm",
    "RobustNorm",
    "Take",
    "TrackResult",
    "Tracker",
    "TrackerOptions",
    "Troupe",
    "VoodooError",
    "WarpBackend",
    "WarpGeometry",
    "blob_from_bytes",
    "blob_to_bytes",
    "build_blob",
    "load_blob",
    "load_contour_json",
    "load_take",
    "load_takes",
    "mask_contour",
    "open_source",
    "read_image",
    "save_blob",
    "save_contour_json",
    "save_take",
    "save_takes",
    "segment_contour",
    "segment_mask",
    "simplify_contour",
    "to_float_rgb",
    "track_dolls",
    "track_source",
    "validate_contour",
]
