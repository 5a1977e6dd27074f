"""Small helpers shared by the operators."""

import functools

from ..voodoo_addon.errors import VoodooError


def reports_errors(method):
    """Wrap ``execute``/``invoke``: a VoodooError becomes an error report and CANCELLED."""

    @functools.wraps(method)
    def wrapper(self, context, *args):
        try:
            return method(self, context, *args)
        except VoodooError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}

    return wrapper


def settings(context):
    return context.scene.voodoo


def store_contour(s, points) -> None:
    """Replace the outline stored in the settings."""
    s.contour.clear()
    for x, y in points:
        s.contour.add().co = (float(x), float(y))
