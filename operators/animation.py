"""Actions, slots, F-curves, NLA and timeline markers: the animation side of a take.

Blender 5 actions are layered: one action holds a slot per animated ID (here the target
object and its shape-key datablock), and a slot's F-curves live in its channelbag.
"""

import bpy
import numpy as np
from bpy_extras import anim_utils
from mathutils import Matrix

from .storage import IN_VIEW_PROP, QUALITY_PROP

#: Stretches of frames whose quality falls below this (or that were lost) get a timeline
#: marker: the places an animator should look at before trusting the take.
ATTENTION_BELOW = 0.5


def push_to_nla(id_data) -> None:
    """Move the active action of an ID onto a new NLA track (nothing is lost)."""
    ad = id_data.animation_data if id_data is not None else None
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


def in_nla(id_data, action) -> bool:
    """Whether an action is already on one of the ID's NLA strips."""
    ad = id_data.animation_data if id_data is not None else None
    if ad is None:
        return False
    return any(strip.action == action for track in ad.nla_tracks for strip in track.strips)


def active_channelbag(id_data):
    """The channelbag of an ID's assigned action slot, or None."""
    ad = id_data.animation_data if id_data is not None else None
    if ad is None or ad.action is None or ad.action_slot is None:
        return None
    return anim_utils.action_get_channelbag_for_slot(ad.action, ad.action_slot)


def assign(id_data, action):
    """Make ``action`` drive ``id_data`` through the ID's own slot; returns its channelbag.

    The slot the ID already has in this action is reused (re-applying in place), else a new
    slot named after the ID is made.
    """
    ad = id_data.animation_data_create()
    slot = ad.action_slot if ad.action == action else None
    if slot is None:
        slot = action.slots.new(id_type=id_data.id_type, name=id_data.name)
        ad.action = action
        ad.action_slot = slot
    return anim_utils.action_ensure_channelbag_for_slot(action, slot)


def write_curve(bag, path: str, index: int, frames, values, group: str):
    """An F-curve with one key per frame (replacing the curve of that path, if any)."""
    old = bag.fcurves.find(path, index=index)
    if old is not None:
        bag.fcurves.remove(old)
    fc = bag.fcurves.new(path, index=index)
    fc.group = bag.groups.get(group) or bag.groups.new(group)
    fc.keyframe_points.add(len(frames))
    fc.keyframe_points.foreach_set("co", np.column_stack([frames, values]).ravel())
    fc.update()
    return fc


def transform_values(obj, matrices):
    """Location, rotation (in the object's rotation mode) and scale of each matrix.

    Returns ``(locations, rotation path, rotations, scales)``; rotations stay continuous
    (quaternion signs and Euler angles follow the previous frame).
    """
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


def write_quality(obj, bag, frames, quality, in_view) -> None:
    """The take's quality and share in view as F-curves of two properties of the target.

    ``voodoo_quality``: how well the doll was tracked; ``voodoo_in_view``: how much of it
    was in view (the rest folded under, turned away, covered or off the picture, holding
    its last seen shape). Keyed on every tracked frame, held constant between keys, so the
    Graph Editor shows where a take is partial and a driver can read it.
    """
    tracked = "How well the doll was tracked in this frame (0: lost, 1: perfect)"
    seen = "Share of the doll in view in this frame (0: lost, 1: all of it)"
    shares = ((QUALITY_PROP, quality, tracked), (IN_VIEW_PROP, in_view, seen))
    for prop, values, description in shares:
        obj[prop] = float(values[0])
        obj.id_properties_ui(prop).update(min=0.0, max=1.0, description=description)
        fc = write_curve(bag, f'["{prop}"]', 0, frames, values, "Tracking Quality")
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


def find_action(name: str):
    return bpy.data.actions.get(name) if name else None
