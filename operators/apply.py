"""Writing a take onto a mesh: one shape key per mode, rigid motion on the transform.

A take has one action, named after it: a slot for each target object (location, rotation,
scale, tracking quality) and one for its shape-key datablock (``key_blocks[...].value``, since
shape-key values belong to the Key). The first apply on a target pushes the animation already
there to the NLA (never overwritten); applying the same take again rewrites its curves in
place (one action, one undo step) unless a new layer is asked for. Mode toggles, gains and the
rigid switches act afterwards on the curves and shapes -- no re-tracking.
"""

import bpy
import numpy as np

from ..voodoo_addon.errors import VoodooError
from ..voodoo_addon.takes.rig import Rig, check_gain, mapping_from_list
from ..voodoo_addon.tracking.params import ParamLayout
from .animation import (
    active_channelbag,
    assign,
    find_action,
    in_nla,
    mark_attention,
    push_to_nla,
    transform_values,
    write_curve,
    write_quality,
)
from .storage import (
    SHAPE_GAIN_KEY,
    TargetLink,
    is_take_action,
    linked_to,
    read_link,
    stored_blob,
    stored_take,
    tag_action,
)

#: Shape-key values allowed by the sliders (doll units, see ``rig.UNIT_FRACTION``).
SLIDER_RANGE = 10.0
MODES_GROUP = "Modes"
TRANSFORM_GROUP = "Object Transforms"


def check_target(obj) -> None:
    """Raise VoodooError unless ``obj`` is a live mesh object with vertices."""
    try:
        kind = obj.type if obj is not None else None
    except ReferenceError:
        kind = None
    if kind is None:
        raise VoodooError("No target: pick a mesh object to animate.")
    if kind != "MESH":
        raise VoodooError(f"{obj.name!r} is a {kind.lower()}, not a mesh; pick a mesh object.")
    if len(obj.data.vertices) == 0:
        raise VoodooError(f"{obj.name!r} has no vertices to deform.")


def rest_vertices(obj) -> np.ndarray:
    """Local rest-pose vertices (n, 3): the Basis shape if any, else the mesh."""
    mesh = obj.data
    n = len(mesh.vertices)
    co = np.empty(n * 3, dtype=np.float64)
    if mesh.shape_keys is not None:
        mesh.shape_keys.reference_key.data.foreach_get("co", co)
    else:
        mesh.vertices.foreach_get("co", co)
    return co.reshape(n, 3)


def matrix_at(scene, obj, frame) -> np.ndarray:
    """The object's local transform at a scene frame (its own animation evaluated there)."""
    ad = obj.animation_data
    if frame is None or ad is None or (ad.action is None and not len(ad.nla_tracks)):
        return np.array(obj.matrix_basis)
    current, sub = scene.frame_current, scene.frame_subframe
    scene.frame_set(int(frame))
    matrix = np.array(obj.matrix_basis)
    scene.frame_set(current, subframe=sub)
    return matrix


def key_name(blob_mesh, label: str) -> str:
    return f"{blob_mesh.name}:{label}"


def layout_for(blob, take) -> ParamLayout:
    """The parameter layout a take was recorded with (by its parameters' names)."""
    try:
        return ParamLayout.from_names(blob.labels, take.param_names)
    except ValueError:
        raise VoodooError(
            "The take does not belong to this blob (its parameters differ)."
        ) from None


def _gain(mode) -> float:
    return check_gain(mode.gain, mode.name)


def shape_for_mode(obj, blob_mesh, mode, offsets_row, rest):
    """Create or refresh the shape key of one mode (its shape carries the gain)."""
    gain = _gain(mode)
    key = obj.data.shape_keys
    name = key_name(blob_mesh, mode.name)
    kb = key.key_blocks.get(name) if key is not None else None
    if kb is None:
        if key is None:
            obj.shape_key_add(name="Basis", from_mix=False)
        kb = obj.shape_key_add(name=name, from_mix=False)
        kb.slider_min, kb.slider_max = -SLIDER_RANGE, SLIDER_RANGE
    kb.data.foreach_set("co", (rest + gain * offsets_row).ravel())
    gains = obj.data.shape_keys.get(SHAPE_GAIN_KEY)
    if gains is None:
        obj.data.shape_keys[SHAPE_GAIN_KEY] = gains = {}
    gains[name] = gain
    kb.mute = not mode.enabled
    return kb


def _shape_is_current(obj, blob_mesh, mode) -> bool:
    """True when the mode's shape key exists and was written with the mode's gain."""
    key = obj.data.shape_keys
    name = key_name(blob_mesh, mode.name)
    if key is None or key.key_blocks.get(name) is None:
        return False
    return key.get(SHAPE_GAIN_KEY, {}).get(name) == _gain(mode)


def _chosen_modes(s, blob) -> list:
    return [m for m in s.modes if m.enabled and m.index < blob.n_modes]


def _mute_other_keys(obj, blob_mesh, s, chosen) -> None:
    key = obj.data.shape_keys
    if key is None:
        return
    names = {key_name(blob_mesh, m.name) for m in chosen}
    for m in s.modes:
        kb = key.key_blocks.get(key_name(blob_mesh, m.name))
        if kb is not None and kb.name not in names:
            kb.mute = True


def _take_action(obj, blob_mesh, take_name, new_layer, name):
    """The action (called ``name``) to write the take into, and whether it is rewritten in
    place.
    """
    ad = obj.animation_data
    active = ad.action if ad is not None else None
    if not new_layer and is_take_action(active, blob_mesh, take_name):
        return active, True
    existing = find_action(name)
    push_to_nla(obj)
    push_to_nla(obj.data.shape_keys)
    if not new_layer and is_take_action(existing, blob_mesh, take_name):
        if not in_nla(obj, existing) and not in_nla(obj.data.shape_keys, existing):
            return existing, False  # the take's action gets a slot for this target too
    action = bpy.data.actions.new(name)
    tag_action(action, blob_mesh, take_name)
    return action, False


def write_transforms(obj, bag, rig, take, frames, rest_matrix, use) -> None:
    """Location, rotation and scale curves: the take's where ``use`` is on, else one key at
    the rest value (so nothing freezes and no earlier layer shows through).
    """
    good = ~take.lost
    f = frames[good].astype(np.float64)
    moves = rig.transforms(take.params[good], use=(True, True, True))
    locs, rot_path, rots, scales = transform_values(obj, rest_matrix @ moves)
    rest_loc, _, rest_rot, rest_scale = transform_values(obj, rest_matrix[None])
    for path, data, rest, on in (
        ("location", locs, rest_loc, use[0]),
        (rot_path, rots, rest_rot, use[1]),
        ("scale", scales, rest_scale, use[2]),
    ):
        for i in range(data.shape[1]):
            if on:
                write_curve(bag, path, i, f, data[:, i], TRANSFORM_GROUP)
            else:
                write_curve(bag, path, i, f[:1], rest[:, i], TRANSFORM_GROUP)


def apply_take(
    scene, obj, blob_mesh, take_name: str, new_layer: bool = False, settings=None, doll=None
) -> dict:
    """Write a stored take onto ``obj`` (one undo step when called from an operator).

    ``settings`` are the doll's (modes, gains, axes, apply switches; default: the scene's
    fields, the doll shown). ``doll``: the doll's name, when it is one of several: its
    action is then named after the take and the doll.

    Returns
    -------
    dict
        ``action`` (the take's Action), ``in_place`` (an earlier apply was rewritten),
        ``keyed`` (frames keyed), ``lost`` (scene frames not keyed because the track was lost
        there), ``attention`` (marked stretches).
    """
    check_target(obj)
    s = settings if settings is not None else scene.voodoo
    blob = stored_blob(blob_mesh)
    stored = stored_take(blob_mesh, take_name)
    take, frames = stored.take, stored.frames
    good = ~take.lost
    if not good.any():
        raise VoodooError(f"Take {take_name!r} lost the blob in every frame; nothing to apply.")
    modes = _chosen_modes(s, blob)
    for m in modes:
        _gain(m)  # fail before anything changes
    rest = rest_vertices(obj)
    use = (s.apply_location, s.apply_rotation, s.apply_scale)
    rig = Rig(blob, layout_for(blob, take), rest, s.axes, [m.index for m in modes], use)
    link = read_link(obj)
    if link is not None:  # driven by a take already: its rest pose stays the rest pose
        rest_matrix = np.array(link.rest_matrix).reshape(4, 4)
    else:
        rest_matrix = matrix_at(scene, obj, stored.rest_frame)
    name = take_name if doll is None else f"{take_name} {doll}"
    action, in_place = _take_action(obj, blob_mesh, take_name, new_layer, name)

    shapes = [shape_for_mode(obj, blob_mesh, m, rig.offsets[i], rest) for i, m in enumerate(modes)]
    _mute_other_keys(obj, blob_mesh, s, modes)
    f = frames[good].astype(np.float64)
    key = obj.data.shape_keys
    if key is not None and (shapes or in_place):
        bag_key = assign(key, action)
        bag_key.fcurves.clear()
        values = rig.values(take.params[good])
        for i, kb in enumerate(shapes):
            write_curve(bag_key, f'key_blocks["{kb.name}"].value', 0, f, values[:, i], MODES_GROUP)
    bag_obj = assign(obj, action)
    bag_obj.fcurves.clear()
    write_transforms(obj, bag_obj, rig, take, frames, rest_matrix, use)
    quality = np.where(take.lost, 0.0, take.confidence)
    write_quality(obj, bag_obj, frames.astype(np.float64), quality, take.in_view())
    marked = mark_attention(scene, take_name, frames, quality)
    TargetLink(
        blob=blob_mesh.name,
        take=take_name,
        action=action.name,
        axes=rig.mapping.axes,
        mapping=rig.mapping.as_list(),
        rest_matrix=rest_matrix.ravel().tolist(),
        use=list(use),
    ).write(obj)
    return {
        "action": action,
        "in_place": in_place,
        "keyed": int(good.sum()),
        "lost": frames[~good].tolist(),
        "attention": marked,
    }


def linked_objects(scene, blob_mesh):
    """Objects of the scene driven by takes of ``blob_mesh``."""
    return [obj for obj in scene.objects if linked_to(obj, blob_mesh)]


def refresh_modes(scene) -> None:
    """Make mode toggles, gains and rigid switches take effect on every linked object.

    A mode switched on that was not applied yet gets its shape key and curve from the stored
    take; switched off, its key and curve are muted; a gain rescales its shape; a rigid switch
    rewrites that part of the transform curves.
    """
    s = scene.voodoo
    if s.blob is None:
        return
    try:
        blob = stored_blob(s.blob)
    except VoodooError:
        return
    for obj in linked_objects(scene, s.blob):
        _refresh_object(scene, obj, s, blob)


def _refresh_object(scene, obj, s, blob) -> None:
    link = read_link(obj)
    action = find_action(link.action)
    if action is None:
        return  # the take's action was deleted: nothing of ours to refresh
    mapping = mapping_from_list(link.axes, link.mapping)
    rest = rest_vertices(obj)
    key = obj.data.shape_keys
    present = {kb.name for kb in key.key_blocks} if key is not None else set()
    modes = [
        m
        for m in s.modes
        if m.index < blob.n_modes and (m.enabled or key_name(s.blob, m.name) in present)
    ]
    stale = [m for m in modes if not _shape_is_current(obj, s.blob, m)]
    if stale:  # new modes, or gains changed: (re)write only those shapes
        shapes = Rig(
            blob,
            ParamLayout(tuple(str(x) for x in blob.labels)),
            rest,
            modes=[m.index for m in stale],
            mapping=mapping,
        )
        for mode, offset in zip(stale, shapes.offsets, strict=True):
            shape_for_mode(obj, s.blob, mode, offset, rest)
    key_blocks = obj.data.shape_keys.key_blocks if modes else {}
    bag = active_channelbag(obj.data.shape_keys) if modes else None
    missing = []
    for mode in modes:
        kb = key_blocks[key_name(s.blob, mode.name)]
        kb.mute = not mode.enabled
        path = f'key_blocks["{kb.name}"].value'
        fc = bag.fcurves.find(path) if bag is not None else None
        if fc is None and mode.enabled:
            missing.append((mode.index, path))
        elif fc is not None:
            fc.mute = not mode.enabled
    use = [bool(s.apply_location), bool(s.apply_rotation), bool(s.apply_scale)]
    bag = active_channelbag(obj)
    rigid_changed = use != list(link.use) and bag is not None
    if not missing and not rigid_changed:
        return
    stored = stored_take(s.blob, link.take)
    take, good = stored.take, ~stored.take.lost
    frames = stored.frames[good].astype(np.float64)
    rig = Rig(blob, layout_for(blob, take), rest, modes=[i for i, _ in missing], mapping=mapping)
    if missing:  # modes switched on that were not applied yet: key them from the take
        key_bag = assign(obj.data.shape_keys, action)
        values = rig.values(take.params[good])
        for column, (_, path) in enumerate(missing):
            write_curve(key_bag, path, 0, frames, values[:, column], MODES_GROUP)
    if rigid_changed:
        rest_matrix = np.array(link.rest_matrix).reshape(4, 4)
        write_transforms(obj, bag, rig, take, stored.frames, rest_matrix, use)
        TargetLink(**{**link.__dict__, "use": use}).write(obj)
