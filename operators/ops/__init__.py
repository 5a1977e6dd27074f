"""The operators, one per module, in the order an animator meets them."""

from . import (
    add_doll,
    apply_take,
    build_blob,
    capture_frame,
    clear_contour,
    contour_auto,
    contour_from_mask,
    record_take,
    recover_takes,
    remove_doll,
    remove_unused_blobs,
    select_modes,
    sketch_contour,
    smooth_take,
    track_clip,
)

_modules = (
    add_doll,
    remove_doll,
    capture_frame,
    contour_from_mask,
    contour_auto,
    sketch_contour,
    clear_contour,
    build_blob,
    remove_unused_blobs,
    record_take,
    track_clip,
    recover_takes,
    apply_take,
    select_modes,
    smooth_take,
)
classes = tuple(cls for mod in _modules for cls in mod.classes)
