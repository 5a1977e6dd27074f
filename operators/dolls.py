"""Several dolls in one scene: ``scene.voodoo.dolls``, and the doll the panels show.

Every panel and operator works on the scene's own fields -- ``contour``, ``blob``, ``modes``,
``active_mode``, ``target``, ``axes`` and the apply switches -- as it did with one doll. With
dolls listed, those fields hold the settings of the doll shown (``shown_doll``), and each
doll of the list keeps its own copy: choosing another doll (``active_doll``) stores the
fields into the doll that was shown and loads the chosen one's. :func:`doll_settings` gives
every doll's settings as they are now (the fields for the doll shown). A scene with no doll
listed has one doll, its fields: files made before dolls existed open unchanged.
"""

from contextlib import contextmanager

from ..voodoo_addon.errors import VoodooError

#: The fields a doll keeps besides its outline and modes.
FIELDS = ("blob", "target", "axes", "apply_location", "apply_rotation", "apply_scale")
#: What a mode keeps.
MODE_FIELDS = ("name", "index", "enabled", "gain", "stiffness")

_switching = [False]


def switching() -> bool:
    """True while a doll's settings are being copied (mode updates must not refresh then)."""
    return _switching[0]


@contextmanager
def _quiet():
    _switching[0] = True
    try:
        yield
    finally:
        _switching[0] = False


def _copy(src, dst) -> None:
    """A doll's settings from ``src`` into ``dst`` (the scene's fields or a listed doll)."""
    with _quiet():
        for name in FIELDS:
            setattr(dst, name, getattr(src, name))
        dst.contour.clear()
        for p in src.contour:
            dst.contour.add().co = p.co
        dst.modes.clear()
        for m in src.modes:
            new = dst.modes.add()
            for name in MODE_FIELDS:
                setattr(new, name, getattr(m, name))
        dst.active_mode = src.active_mode


def _blank(s) -> None:
    """The scene's fields with no doll in them (a new doll: outline, blob and target to come)."""
    with _quiet():
        s.blob = None
        s.target = None
        s.contour.clear()
        s.modes.clear()
        s.active_mode = 0
        s.axes = "XZ"
        s.apply_location = s.apply_rotation = s.apply_scale = True


def store_shown(s) -> None:
    """Keep the fields' settings in the listed doll they belong to."""
    if len(s.dolls):
        _copy(s, s.dolls[min(s.shown_doll, len(s.dolls) - 1)])


def show_doll(s, index: int) -> None:
    """Make the fields hold doll ``index`` (storing the one shown before)."""
    if not len(s.dolls):
        return
    index = max(0, min(index, len(s.dolls) - 1))
    if index == s.shown_doll and index == s.active_doll:
        return
    if s.shown_doll < len(s.dolls) and s.shown_doll != index:
        _copy(s, s.dolls[s.shown_doll])
    _copy(s.dolls[index], s)
    with _quiet():
        s.shown_doll = index
        if s.active_doll != index:
            s.active_doll = index


def _unique(s, base: str) -> str:
    names = {d.name for d in s.dolls}
    if base not in names:
        return base
    i = 2
    while f"{base} {i}" in names:
        i += 1
    return f"{base} {i}"


def add_doll(s, name: str = "") -> str:
    """A new doll, shown (its outline, blob and target empty); returns its name.

    The scene's one doll becomes the first of the list when the list was empty.
    """
    if not len(s.dolls):
        first = s.dolls.add()
        first.name = _unique(s, s.blob.name if s.blob is not None else "Doll")
        with _quiet():
            s.shown_doll = 0
            s.active_doll = 0
    store_shown(s)
    doll = s.dolls.add()
    doll.name = _unique(s, name.strip() or "Doll")
    _blank(s)
    _copy(s, doll)
    with _quiet():
        s.shown_doll = s.active_doll = len(s.dolls) - 1
    return doll.name


def remove_doll(s) -> str:
    """Remove the doll shown; the next one is shown. Returns the removed doll's name.

    Its blob and takes stay in the file (Remove Unused Blobs deletes them once nothing uses
    them), and the targets it animated keep their animation.
    """
    if len(s.dolls) < 2:
        raise VoodooError("The last doll cannot be removed; clear its outline instead.")
    index = min(s.shown_doll, len(s.dolls) - 1)
    name = s.dolls[index].name
    s.dolls.remove(index)
    nxt = min(index, len(s.dolls) - 1)
    _copy(s.dolls[nxt], s)
    with _quiet():
        s.shown_doll = s.active_doll = nxt
    return name


def doll_settings(s) -> list:
    """(name, settings) of every doll, the one shown as the scene's own fields.

    ``settings`` has the fields of :data:`FIELDS`, ``contour`` and ``modes``.
    """
    if not len(s.dolls):
        return [(s.blob.name if s.blob is not None else "Doll", s)]
    shown = min(s.shown_doll, len(s.dolls) - 1)
    return [(d.name, s if i == shown else d) for i, d in enumerate(s.dolls)]


def blobs_in_use(scene) -> set:
    """The blob meshes of every doll of a scene."""
    return {d.blob for _, d in doll_settings(scene.voodoo) if d.blob is not None}
