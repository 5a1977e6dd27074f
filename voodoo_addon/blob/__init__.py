"""Building the active blob: outline, quality mesh, FE modes with names, template, its file."""

from .build import BlobOptions, build_blob
from .model import ActiveBlob, blob_from_bytes, blob_to_bytes, load_blob, save_blob

__all__ = [
    "ActiveBlob",
    "BlobOptions",
    "blob_from_bytes",
    "blob_to_bytes",
    "build_blob",
    "load_blob",
    "save_blob",
]
