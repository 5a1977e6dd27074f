"""One doll of a take being recorded: its blob, target, tracker, journal, stand-in and stream.

:class:`~.recorder.Recorder` reads and tracks the frames once for every doll of the scene
(``dolls.doll_settings``); each doll keeps what is its own here. A take of one doll is what
it always was; with several dolls listed, every doll's take is stored with its own blob
under the take's name, and its action and OSC addresses are named after the doll.
"""

import bpy
import numpy as np

from ..voodoo_addon.blob.outline import check_apart
from ..voodoo_addon.errors import VoodooError
from ..voodoo_addon.stream import view_share
from ..voodoo_addon.takes.journal import SUFFIX, JournalWriter
from ..voodoo_addon.takes.rig import Rig, fit_mapping, unit
from ..voodoo_addon.takes.take import Take
from ..voodoo_addon.tracking.troupe import doll_names
from .apply import apply_take, check_target, layout_for, rest_vertices, shape_for_mode
from .storage import (
    blob_id,
    recovery_dir,
    store_take,
    stored_blob,
    stored_take,
    unique_take_name,
)


def alive(obj) -> bool:
    """False once a Blender object's data was deleted under us."""
    try:
        obj.name  # noqa: B018 - raises once the object is gone
    except ReferenceError:
        return False
    return True


class DollRun:
    """A doll in a take being recorded.

    Parameters
    ----------
    name : str
        The doll's name (the blob's when the scene has one doll).
    settings
        Its settings: the scene's fields or a listed doll (``blob``, ``target``, ``axes``,
        ``modes``, the apply switches).
    several : bool
        One of several dolls: its action and OSC addresses carry its name.
    """

    def __init__(self, name: str, settings, several: bool):
        self.name = name
        self.settings = settings
        self.several = several
        if settings.blob is None and several:
            raise VoodooError(f"Doll {name!r} has no blob: build it, or remove the doll.")
        self.blob_mesh = settings.blob
        self.blob = stored_blob(settings.blob)
        self.target = settings.target
        if self.target is not None:
            check_target(self.target)
            fit_mapping(self.blob, rest_vertices(self.target), settings.axes)  # fail early
        self.previous = None
        self.tracker = self.journal = self._preview = self._streamed = None

    @property
    def action_doll(self) -> str | None:
        """The name its action carries besides the take's (None for a scene's one doll)."""
        return self.name if self.several else None

    @property
    def osc_name(self) -> str:
        return self.name if self.several else self.blob_mesh.name

    def resume(self, take_name: str) -> None:
        """Continue the stored take ``take_name`` of this doll."""
        try:
            self.previous = stored_take(self.blob_mesh, take_name)
        except VoodooError:
            raise VoodooError(
                f"Take {take_name!r} is not stored with doll {self.name!r}; it cannot be resumed."
            ) from None

    def open_journal(self, take_name, fps, rest_frame, resume) -> JournalWriter:
        path = recovery_dir() / f"{blob_id(self.blob_mesh)}-{bpy.path.clean_name(take_name)}"
        self.journal = JournalWriter(
            f"{path}{SUFFIX}",
            self.blob.triangles,
            self.blob.n_nodes,
            self.tracker.parameter_names,
            fps,
            meta={
                "blob_id": blob_id(self.blob_mesh),
                "blob": self.blob_mesh.name,
                "doll": self.name,
                "take": take_name,
                "extends": resume,
                "rest_frame": rest_frame,
            },
        )
        return self.journal

    # ------------------------------------------------------------------ live stand-in

    def prepare_preview(self) -> None:
        """Pose a stand-in copy of the target live; the target stays untouched (hidden).

        The copy goes away when the take ends; only then is the target animated.
        """
        s = self.settings
        src = self.target
        copy = src.copy()
        copy.data = src.data.copy()
        copy.name = f"{src.name} (recording)"
        copy.animation_data_clear()
        if copy.data.shape_keys is not None:
            copy.data.shape_keys.animation_data_clear()
        for coll in src.users_collection:
            coll.objects.link(copy)
        src.hide_set(True)
        rest = rest_vertices(copy)
        modes = [m for m in s.modes if m.enabled and m.index < self.blob.n_modes]
        use = (s.apply_location, s.apply_rotation, s.apply_scale)
        rig = Rig(self.blob, self.tracker.layout, rest, s.axes, [m.index for m in modes], use)
        keys = [
            shape_for_mode(copy, self.blob_mesh, m, rig.offsets[i], rest)
            for i, m in enumerate(modes)
        ]
        self._preview = (copy, rig, keys, np.array(copy.matrix_basis))

    def pose(self, params, notes: list) -> None:
        from mathutils import Matrix

        if self._preview is None:
            return
        copy, rig, keys, rest_matrix = self._preview
        if not alive(copy):  # the animator deleted the stand-in: record on without it
            self.drop_preview()
            notes.append("The live stand-in was deleted; the take was recorded without it.")
            return
        values, transform = rig.pose(params)
        for kb, value in zip(keys, values, strict=True):
            kb.value = float(np.clip(value, kb.slider_min, kb.slider_max))
        copy.matrix_basis = Matrix((rest_matrix @ transform).tolist())

    def drop_preview(self) -> None:
        if self._preview is not None:
            copy = self._preview[0]
            self._preview = None
            if alive(copy):
                mesh = copy.data
                bpy.data.objects.remove(copy)
                if mesh.users == 0:
                    bpy.data.meshes.remove(mesh)
        if self.target is not None and alive(self.target):
            self.target.hide_set(False)

    # ------------------------------------------------------------------ stream

    def prepare_stream(self) -> None:
        """Which modes go out, and their scale: the modes that apply, times their gains."""
        lay = self.tracker.layout
        on = [m for m in self.settings.modes if m.enabled and m.index < lay.n_modes]
        self._streamed = (
            [m.name for m in on],
            np.array([lay.modes.start + m.index for m in on], dtype=np.int64),
            np.array([m.gain for m in on]) / unit(self.blob),
        )

    def send(self, stream, frame, res) -> None:
        names, cols, scale = self._streamed
        values = dict(zip(names, (res.params[cols] * scale).tolist(), strict=True))
        stream.send(
            self.osc_name,
            frame.index,
            frame.time,
            res.params[:4],
            values,
            res.confidence,
            res.lost,
            view_share(res),
        )

    # ------------------------------------------------------------------ end

    def take_of(self, rows, fps: float) -> Take:
        """The take of ``rows`` (index, time, scene frame, results) for this doll."""
        return Take.from_results(
            [results[self.name] for *_, results in rows],
            self.blob.triangles,
            self.tracker.parameter_names,
            [i for i, *_ in rows],
            [t for _, t, *_ in rows],
            fps,
        )

    def keep(self, take_name: str, rows, rest_frame, fps: float, take: Take | None = None) -> None:
        """Store this doll's take with its blob; ``rows`` (index, time, scene frame, results).

        ``take``: what to store for these rows instead of their results as tracked (the take
        tracked both ways).
        """
        take = self.take_of(rows, fps) if take is None else take
        layout_for(self.blob, take)  # sanity: the layout must round-trip
        frames = [f for *_, f, _ in rows]
        if self.previous is not None:
            take = self.previous.take.extended(take)
            frames = self.previous.frames.tolist() + frames
        store_take(self.blob_mesh, take_name, take, frames, rest_frame)
        self.journal.discard()

    def apply(self, scene, take_name: str) -> dict | None:
        """Apply the stored take to the target, if it is still there."""
        if self.target is None or not alive(self.target):
            return None
        return apply_take(
            scene, self.target, self.blob_mesh, take_name, settings=self.settings,
            doll=self.action_doll,
        )  # fmt: skip


def check_dolls(dolls) -> None:
    """Several dolls: distinct names, distinct blobs and targets, outlines apart."""
    if len(dolls) < 2:
        return
    doll_names([d.name for d in dolls])
    for kind in ("blob_mesh", "target"):
        seen = {}
        for d in dolls:
            thing = getattr(d, kind)
            if thing is None:
                continue
            if thing.name in seen:
                what = "blob" if kind == "blob_mesh" else "target"
                raise VoodooError(
                    f"Dolls {seen[thing.name]!r} and {d.name!r} have the same {what} "
                    f"{thing.name!r}: give each doll its own."
                )
            seen[thing.name] = d.name
    check_apart({d.name: d.blob.contour for d in dolls})


def unique_name(dolls, base: str) -> str:
    """A take name no doll has a take or an action of yet (``base``, ``base.002``, ...)."""
    name = base
    for _ in range(1000):
        unique = [unique_take_name(d.blob_mesh, name) for d in dolls]
        taken = {f"{name} {d.name}" for d in dolls if d.several} & set(bpy.data.actions.keys())
        if all(u == name for u in unique) and not taken:
            return name
        name = next((u for u in unique if u != name), None) or _bump(name)
    raise VoodooError(f"No free take name after {base!r}.")


def _bump(name: str) -> str:
    stem, _, number = name.rpartition(".")
    if stem and number.isdigit():
        return f"{stem}.{int(number) + 1:03d}"
    return f"{name}.002"
