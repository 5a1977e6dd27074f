"""What the operators share: error reporting, the settings, and the preconditions their
buttons are greyed out by (each with the reason Blender shows in the tooltip).
"""

import functools

from ...voodoo_addon.errors import VoodooError
from ..clips import active_clip
from ..storage import is_blob, read_link


def reports_errors(method):
    """Wrap ``execute(self, context)`` or ``invoke(self, context, event)``: a VoodooError
    becomes an error report and CANCELLED.

    Blender checks the argument count of the registered function itself, so the wrapper
    spells out the same arguments as the method it wraps.
    """

    def guarded(self, context, *args):
        try:
            return method(self, context, *args)
        except VoodooError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}

    if method.__code__.co_argcount == 3:

        def wrapper(self, context, event):
            return guarded(self, context, event)

    else:

        def wrapper(self, context):
            return guarded(self, context)

    return functools.wraps(method)(wrapper)


def settings(context):
    return context.scene.voodoo


def store_contour(s, points) -> None:
    """Replace the outline stored in the settings."""
    s.contour.clear()
    for x, y in points:
        s.contour.add().co = (float(x), float(y))


def needs(cls, context, *checks) -> bool:
    """True when every precondition holds; otherwise tell Blender why the button is grey.

    Each check is a name of :data:`CHECKS`.
    """
    for name in checks:
        ok, reason = CHECKS[name]
        if not ok(context):
            cls.poll_message_set(reason)
            return False
    return True


def _has_source(context) -> bool:
    s = settings(context)
    return s.source == "CAMERA" or active_clip(context) is not None


def _has_target(context) -> bool:
    target = settings(context).target
    try:
        return target is not None and target.type == "MESH"
    except ReferenceError:
        return False


CHECKS = {
    "source": (_has_source, "Open a movie clip in the Movie Clip Editor (or choose Camera)"),
    "capture": (
        lambda c: settings(c).capture_image is not None,
        "Capture a frame first",
    ),
    "outline": (
        lambda c: len(settings(c).contour) >= 3,
        "Outline the object first (mask, automatic or sketch)",
    ),
    "blob": (lambda c: is_blob(settings(c).blob), "Build a blob first"),
    "take": (lambda c: bool(settings(c).last_take), "Record a take first"),
    "target": (_has_target, "Pick a mesh object as the target"),
    "modes": (lambda c: len(settings(c).modes) > 0, "Build a blob to list its modes"),
    "applied": (
        lambda c: read_link(settings(c).target or c.active_object) is not None,
        "The target has no applied take",
    ),
}
