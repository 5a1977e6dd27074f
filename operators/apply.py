"""Writing a take onto a mesh: one shape key per mode, rigid motion on the transform.

Everything lands in a new layered action named after the take: one slot for the object
(location, rotation, scale) and one for its shape-key datablock (``key_blocks[...].value``,
since shape-key values belong to the Key). Animation already on the object or its Key is
pushed to the NLA first, never overwritten. Mode toggles and gains act afterwards by muting
curves and rescaling shapes -- no re-tracking.
"""

import bpy
import numpy as np
from bpy_extras import anim_utils
from mathutils import Matrix

from ..voodoo_addon.errors import VoodooError
from ..voodoo_addon.takes.rig import Rig, mapping_from_list
from ..voodoo_addon.tracking.params import ParamLayout
from .store import load_blob, load_take

#: Custom property on a target: which blob/take drive it and how the doll was laid on it.
LINK_KEY = "voodoo"
#: Shape-key values allowed by the sliders (doll units, see ``retarget.UNIT_FRACTION``).
SLIDER_RANGE = 10.0
#: Custom property of a target whose F-curve is the take's per-frame tracking quality.
QUALITY_PROP = "voodoo_quality"
#: Stretches of frames whose quality falls below this (or that were lost) get a timeline
#: marker: the places an animator should look at before trusting the take.
ATTENTION_BELOW = 0.5


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


def push_to_nla(id_data) -> None:
    """Move the active action of an ID onto a new NLA track (nothing is lost)."""
    ad = id_data.animation_data
    if ad is None or ad.action is None:
        return
    action, slot = ad.action, ad.action_slot
    track = ad.nla_tracks.new()
    track.name = f"Before {action.name}"
    start = int(action.frame_range[0])
    strip = track.strips.new(action.name, start, action)
    if slot is not None and hasattr(strip, "action_slot"):
        strip.action_slot = slot
    ad.action = None


def _channelbag(action, id_data, name):
    slot = action.slots.new(id_type=id_data.id_type, name=name)
    return slot, anim_utils.action_ensure_channelbag_for_slot(action, slot)


def _write_curve(bag, path: str, index: int, frames, values, group: str):
    fc = bag.fcurves.new(path, index=index)
    fc.group = bag.groups.get(group) or bag.groups.new(group)
    fc.keyframe_points.add(len(frames))
    fc.keyframe_points.foreach_set("co", np.column_stack([frames, values]).ravel())
    fc.update()
    return fc


def shape_for_mode(obj, blob_mesh, mode, offsets_row, rest):
    """Create or refresh the shape key of one mode (its shape carries the gain)."""
    key = obj.data.shape_keys
    name = key_name(blob_mesh, mode.name)
    kb = key.key_blocks.get(name) if key is not None else None
    if kb is None:
        if key is None:
            obj.shape_key_add(name="Basis", from_mix=False)
        kb = obj.shape_key_add(name=name, from_mix=False)
        kb.slider_min, kb.slider_max = -SLIDER_RANGE, SLIDER_RANGE
    kb.data.foreach_set("co", (rest + mode.gain * offsets_row).ravel())
    kb.mute = not mode.enabled
    return kb


def _transform_curves(obj, matrices):
    """Location, rotation (in the object's rotation mode) and scale per frame."""
    locs, rots, scales = [], [], []
    prev = None
    quat_mode = obj.rotation_mode in {"QUATERNION", "AXIS_ANGLE"}
    for m in matrices:
        loc, quat, scale = Matrix(m.tolist()).decompose()
        if quat_mode:
            if prev is not None and quat.dot(prev) < 0:
                quat.negate()
            prev = quat.copy()
            rots.append(tuple(quat))
        else:
            eul = (
                quat.to_euler(obj.rotation_mode, prev)
                if prev is not None
                else quat.to_euler(obj.rotation_mode)
            )
            prev = eul.copy()
            rots.append(tuple(eul))
        locs.append(tuple(loc))
        scales.append(tuple(scale))
    path = "rotation_quaternion" if quat_mode else "rotation_euler"
    return np.array(locs), path, np.array(rots), np.array(scales)


def apply_take(scene, obj, blob_mesh, take_name: str) -> dict:
    """Write a stored take onto ``obj`` (one undo step when called from an operator).

    Returns
    -------
    dict
        ``action`` (the new Action), ``keyed`` (frames keyed), ``lost`` (scene frames not
        keyed because the track was lost there).
    """
    check_target(obj)
    s = scene.voodoo
    blob = load_blob(blob_mesh)
    take = load_take(blob_mesh, take_name)
    frames = take_frames(blob_mesh, take_name, take)
    rest = rest_vertices(obj)
    modes = [m for m in s.modes if m.enabled and m.index < blob.n_modes]
    use = (s.apply_location, s.apply_rotation, s.apply_scale)
    rig = Rig(blob, layout_for(blob, take), rest, s.axes, [m.index for m in modes], use)
    good = ~take.lost
    if not good.any():
        raise VoodooError(f"Take {take_name!r} lost the blob in every frame; nothing to apply.")

    push_to_nla(obj)
    if obj.data.shape_keys is not None:
        push_to_nla(obj.data.shape_keys)

    rest_matrix = np.array(obj.matrix_basis)
    shapes = [shape_for_mode(obj, blob_mesh, m, rig.offsets[i], rest) for i, m in enumerate(modes)]
    action = bpy.data.actions.new(take_name)
    slot_obj, bag_obj = _channelbag(action, obj, obj.name)
    f = frames[good].astype(np.float64)
    if shapes:
        key = obj.data.shape_keys
        slot_key, bag_key = _channelbag(action, key, key.name)
        values = rig.values(take.params[good])
        for i, (m, kb) in enumerate(zip(modes, shapes, strict=True)):
            path = f'key_blocks["{kb.name}"].value'
            fc = _write_curve(bag_key, path, 0, f, values[:, i], "Modes")
            fc.mute = not m.enabled
        key.animation_data_create()
        key.animation_data.action = action
        key.animation_data.action_slot = slot_key
    # All of the similarity is keyed; the switches mute curves (see refresh_modes).
    moves = rig.transforms(take.params[good], use=(True, True, True))
    locs, rot_path, rots, scales = _transform_curves(obj, rest_matrix @ moves)
    for path, data, on in (
        ("location", locs, s.apply_location),
        (rot_path, rots, s.apply_rotation),
        ("scale", scales, s.apply_scale),
    ):
        for i in range(data.shape[1]):
            fc = _write_curve(bag_obj, path, i, f, data[:, i], "Object Transforms")
            fc.mute = not on
    quality = np.where(take.lost, 0.0, take.confidence)
    _write_quality(obj, bag_obj, frames.astype(np.float64), quality)
    obj.animation_data_create()
    obj.animation_data.action = action
    obj.animation_data.action_slot = slot_obj
    marked = mark_attention(scene, take_name, frames, quality)
    obj[LINK_KEY] = {
        "blob": blob_mesh.name,
        "take": take_name,
        "action": action.name,
        "axes": rig.mapping.axes,
        "mapping": rig.mapping.as_list(),
        "rest_matrix": rest_matrix.ravel().tolist(),
    }
    return {
        "action": action,
        "keyed": int(good.sum()),
        "lost": frames[~good].tolist(),
        "attention": marked,
    }


def attention_message(stretches) -> str | None:
    """One line for the report about the marked stretches (None when there are none)."""
    if not stretches:
        return None
    first, last = stretches[0]
    where = f"frame {first}" if first == last else f"frames {first}-{last}"
    more = f" and {len(stretches) - 1} more" if len(stretches) > 1 else ""
    return (
        f"Tracking quality is low at {where}{more}: see the timeline markers and the "
        f"'{QUALITY_PROP}' curve of the target."
    )


def _write_quality(obj, bag, frames, quality) -> None:
    """The take's quality as an F-curve of the target's ``voodoo_quality`` property."""
    obj[QUALITY_PROP] = float(quality[0])
    obj.id_properties_ui(QUALITY_PROP).update(
        min=0.0,
        max=1.0,
        description="How well the doll was tracked in this frame (0: lost, 1: perfect)",
    )
    fc = _write_curve(bag, f'["{QUALITY_PROP}"]', 0, frames, quality, "Tracking Quality")
    for kp in fc.keyframe_points:
        kp.interpolation = "CONSTANT"


def mark_attention(scene, take_name: str, frames, quality) -> list:
    """Timeline markers on the stretches of a take that need an animator's eye.

    Markers of an earlier apply of the same take are replaced. Returns the marked
    stretches as (first, last) scene frames.
    """
    prefix = f"{take_name}: "
    for marker in list(scene.timeline_markers):
        if marker.name.startswith(prefix):
            scene.timeline_markers.remove(marker)
    bad = np.asarray(quality) < ATTENTION_BELOW
    stretches = []
    i = 0
    while i < len(bad):
        if not bad[i]:
            i += 1
            continue
        j = i
        while j + 1 < len(bad) and bad[j + 1]:
            j += 1
        first, last = int(frames[i]), int(frames[j])
        label = f"check frame {first}" if first == last else f"check {first}-{last}"
        scene.timeline_markers.new(prefix + label, frame=first)
        stretches.append((first, last))
        i = j + 1
    return stretches


def take_frames(blob_mesh, take_name, take) -> np.ndarray:
    """Scene frame of every row of a take (stored when it was recorded)."""
    stored = blob_mesh.get("voodoo_take_frames", {}).get(take_name)
    if stored is None or len(stored) != len(take):
        raise VoodooError(f"Take {take_name!r} has no frame numbers; record it again.")
    return np.asarray(stored, dtype=np.int64)


def linked_objects(scene, blob_mesh):
    """Objects of the scene driven by takes of ``blob_mesh``."""
    out = []
    for obj in scene.objects:
        link = obj.get(LINK_KEY)
        if obj.type == "MESH" and link is not None and link.get("blob") == blob_mesh.name:
            out.append(obj)
    return out


def active_channelbag(id_data):
    """The channelbag of an ID's assigned action slot, or None."""
    ad = id_data.animation_data if id_data is not None else None
    if ad is None or ad.action is None or ad.action_slot is None:
        return None
    return anim_utils.action_get_channelbag_for_slot(ad.action, ad.action_slot)


def refresh_modes(scene) -> None:
    """Make mode toggles, gains and rigid toggles take effect on every linked object.

    A mode switched on that was not applied yet gets its shape key and curve from the
    stored take; switched off, its key and curve are muted; a gain rescales its shape.
    """
    s = scene.voodoo
    if s.blob is None:
        return
    try:
        blob = load_blob(s.blob)
    except VoodooError:
        return
    for obj in linked_objects(scene, s.blob):
        _refresh_object(obj, s, blob)


def _refresh_object(obj, s, blob) -> None:
    link = obj[LINK_KEY]
    mapping = mapping_from_list(link["axes"], link["mapping"])
    rest = rest_vertices(obj)
    key = obj.data.shape_keys
    present = {kb.name for kb in key.key_blocks} if key is not None else set()
    modes = [
        m
        for m in s.modes
        if m.index < blob.n_modes and (m.enabled or key_name(s.blob, m.name) in present)
    ]
    layout = ParamLayout(tuple(str(x) for x in blob.labels))
    rig = Rig(blob, layout, rest, modes=[m.index for m in modes], mapping=mapping)
    offsets = rig.offsets
    for mode, offset in zip(modes, offsets, strict=True):
        kb = shape_for_mode(obj, s.blob, mode, offset, rest)
        path = f'key_blocks["{kb.name}"].value'
        bag = active_channelbag(obj.data.shape_keys)
        fc = bag.fcurves.find(path) if bag is not None else None
        if fc is None and mode.enabled:
            fc = _add_mode_curve(obj, s.blob, blob, link, mode, path)
        if fc is not None:
            fc.mute = not mode.enabled
    bag = active_channelbag(obj)
    if bag is not None:
        for fc in bag.fcurves:
            if fc.data_path == "location":
                fc.mute = not s.apply_location
            elif fc.data_path.startswith("rotation"):
                fc.mute = not s.apply_rotation
            elif fc.data_path == "scale":
                fc.mute = not s.apply_scale


def _add_mode_curve(obj, blob_mesh, blob, link, mode, path):
    """Key a newly enabled mode from the stored take into the object's take action.

    Returns the new F-curve, or None when the take's action is gone.
    """
    action = bpy.data.actions.get(link["action"])
    if action is None:
        return None
    take = load_take(blob_mesh, link["take"])
    rig = Rig(
        blob,
        layout_for(blob, take),
        rest_vertices(obj),
        modes=[mode.index],
        mapping=mapping_from_list(link["axes"], link["mapping"]),
    )
    frames = take_frames(blob_mesh, link["take"], take)
    good = ~take.lost
    key = obj.data.shape_keys
    key.animation_data_create()
    if key.animation_data.action is None:
        key.animation_data.action = action
        key.animation_data.action_slot = action.slots.new(id_type="KEY", name=key.name)
    values = rig.values(take.params[good])[:, 0]
    return _write_curve(
        active_channelbag(key), path, 0, frames[good].astype(np.float64), values, "Modes"
    )
