"""Carrying a take onto a character: the doll-to-target mapping and mode shapes (paper §6).

The doll lives in pixel coordinates (x right, y down). A target mesh lives in its own local
coordinates; two of its axes (``"XY"``, ``"XZ"`` or ``"YZ"``) form the plane the doll is laid
onto: the doll's bounding box is centred on the target's and scaled uniformly (so rotations
stay rotations), image-down becoming the plane's second axis pointing down. Each mode's
displacement reaches the target's vertices through the Gaussian interpolants,
``phi'_j = H(X_model) phi_j`` (Eq. 17); the similarity becomes a rigid transform about the
doll's centre.

Shape-key values are in *doll units*: a value of 1 is a mode amplitude of
:data:`UNIT_FRACTION` of the blob's RMS radius (pixels RMS), so curves read about -1..1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..blob.model import ActiveBlob
from ..checks import finite
from ..errors import VoodooError
from ..tracking.params import ParamLayout

#: Plane axes (first, second) and the remaining depth axis, by name.
AXES = {"XY": (0, 1, 2), "XZ": (0, 2, 1), "YZ": (1, 2, 0)}
#: One shape-key unit is this fraction of the blob's RMS radius.
UNIT_FRACTION = 0.1
#: Gains beyond this are refused: a hundred times the tracked motion is already far off the
#: target, and Blender keeps an infinite gain as 3.4e38, whose shapes overflow.
MAX_GAIN = 100.0


def check_gain(value, mode: str = "") -> float:
    """A mode's gain as a float; NaN, infinite and huge gains are refused (VoodooError).

    Parameters
    ----------
    value : real number
    mode : str
        The mode's name, for the message.
    """
    what = f"the gain of mode {mode!r}" if mode else "a mode's gain"
    return finite(value, what, -MAX_GAIN, MAX_GAIN)


@dataclass(frozen=True)
class DollMapping:
    """Affine map from doll pixels to a target's local plane.

    Attributes
    ----------
    axes : str
        "XY", "XZ" or "YZ".
    doll_centre : (2,) float64
        Pixel point mapped to ``target_centre``.
    target_centre : (3,) float64
        Local point of the target the doll centre lands on.
    scale : float
        Target units per pixel.
    """

    axes: str
    doll_centre: np.ndarray
    target_centre: np.ndarray
    scale: float

    @property
    def plane(self) -> tuple[int, int, int]:
        return AXES[self.axes]

    def to_doll(self, points: np.ndarray) -> np.ndarray:
        """Local target points (n, 3) -> doll pixels (n, 2) (depth is dropped)."""
        a, b, _ = self.plane
        rel = points - self.target_centre
        x = self.doll_centre[0] + rel[:, a] / self.scale
        y = self.doll_centre[1] - rel[:, b] / self.scale
        return np.column_stack([x, y])

    def to_target(self, doll_points: np.ndarray, depth: float = 0.0) -> np.ndarray:
        """Doll pixels (n, 2) -> local target points (n, 3) at the target centre's depth."""
        out = np.tile(self.target_centre, (len(doll_points), 1)).astype(np.float64)
        a, b, c = self.plane
        out[:, a] += (doll_points[:, 0] - self.doll_centre[0]) * self.scale
        out[:, b] -= (doll_points[:, 1] - self.doll_centre[1]) * self.scale
        out[:, c] += depth
        return out

    def vectors(self, disp: np.ndarray) -> np.ndarray:
        """Pixel displacements (..., 2) -> local displacements (..., 3)."""
        a, b, _ = self.plane
        out = np.zeros(disp.shape[:-1] + (3,))
        out[..., a] = disp[..., 0] * self.scale
        out[..., b] = -disp[..., 1] * self.scale
        return out

    def as_list(self) -> list[float]:
        """Flat numbers for storing on a Blender ID (see :func:`mapping_from_list`)."""
        return [*map(float, self.doll_centre), *map(float, self.target_centre), float(self.scale)]


def mapping_from_list(axes: str, values) -> DollMapping:
    v = [float(x) for x in values]
    if len(v) != 6 or axes not in AXES:
        raise VoodooError("The stored doll mapping is damaged; apply the take again.")
    return DollMapping(axes, np.array(v[:2]), np.array(v[2:5]), v[5])


def fit_mapping(blob: ActiveBlob, vertices: np.ndarray, axes: str = "XZ") -> DollMapping:
    """Lay the doll's bounding box onto the target's (centred, uniform scale).

    Parameters
    ----------
    blob : ActiveBlob
    vertices : (n, 3) float64
        The target's rest-pose local vertex positions.
    axes : {"XY", "XZ", "YZ"}

    Raises
    ------
    VoodooError
        If the target is flat or degenerate in the chosen plane.
    """
    if axes not in AXES:
        raise VoodooError(f"Axes must be one of {', '.join(AXES)}; got {axes!r}.")
    v = np.asarray(vertices, dtype=np.float64)
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0 or not np.isfinite(v).all():
        raise VoodooError("The target has no usable vertices.")
    a, b, _ = AXES[axes]
    lo, hi = v.min(axis=0), v.max(axis=0)
    t_size = np.array([hi[a] - lo[a], hi[b] - lo[b]])
    d_lo, d_hi = blob.vertices.min(axis=0), blob.vertices.max(axis=0)
    d_size = d_hi - d_lo
    if (t_size <= 1e-9 * max(float(np.abs(v).max()), 1.0)).any():
        raise VoodooError(
            f"The target is flat in the {axes} plane; choose the axes it extends along."
        )
    scale = float(np.sqrt((t_size[0] / d_size[0]) * (t_size[1] / d_size[1])))
    return DollMapping(axes, 0.5 * (d_lo + d_hi), 0.5 * (lo + hi), scale)


def unit(blob: ActiveBlob) -> float:
    """Pixels RMS of mode amplitude per shape-key unit."""
    return UNIT_FRACTION * blob.length


def mode_offsets(
    blob: ActiveBlob, mapping: DollMapping, vertices: np.ndarray, modes=None
) -> np.ndarray:
    """Shape-key offsets per unit value (Eq. 17 through the mapping).

    Parameters
    ----------
    blob : ActiveBlob
    mapping : DollMapping
    vertices : (n, 3) float64
        The target's rest-pose local vertices.
    modes : sequence of int, optional
        Mode indices (default: all).

    Returns
    -------
    (len(modes), n, 3) float64
        Local displacement of every vertex for a shape-key value of 1.
    """
    idx = range(blob.n_modes) if modes is None else list(modes)
    h = blob.interpolant(mapping.to_doll(np.asarray(vertices, dtype=np.float64)))  # (n, m)
    out = np.empty((len(idx), len(vertices), 3))
    for row, j in enumerate(idx):
        out[row] = mapping.vectors(h @ blob.mode_shape(j)) * unit(blob)
    return out


def axis_angle_matrix(axis: np.ndarray, angle: float) -> np.ndarray:
    """3x3 rotation by ``angle`` (radians, right-handed) about a unit axis."""
    x, y, z = axis
    c, s = np.cos(angle), np.sin(angle)
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + s * k + (1 - c) * (k @ k)


def rigid_transforms(
    params: np.ndarray,
    layout: ParamLayout,
    blob: ActiveBlob,
    mapping: DollMapping,
    use=(True, True, True),
) -> np.ndarray:
    """The doll's similarity in every frame as target-local 4x4 transforms.

    ``Delta = T(C + D t) Rot(n, -theta) Scale(s) T(-C)`` with ``C`` the doll centre on the
    target, ``D`` the mapping and ``n`` the plane normal; image rotations (clockwise on
    screen for positive angles, y being down) become rotations of the opposite sign about
    the plane normal.

    Parameters
    ----------
    params : (T, P) float64
    layout : ParamLayout
    blob : ActiveBlob
    mapping : DollMapping
    use : (bool, bool, bool)
        Whether translation, rotation and scale take part.

    Returns
    -------
    (T, 4, 4) float64
    """
    a, b, _ = mapping.plane
    normal = np.cross(np.eye(3)[a], np.eye(3)[b])
    pivot = mapping.to_target(blob.centre[None, :])[0]
    out = np.tile(np.eye(4), (len(params), 1, 1))
    for i, p in enumerate(np.asarray(params)):
        shift = mapping.vectors(p[:2]) if use[0] else np.zeros(3)
        rot = axis_angle_matrix(normal, -p[2]) if use[1] else np.eye(3)
        s = np.exp(p[3]) if use[2] else 1.0
        lin = s * rot
        out[i, :3, :3] = lin
        out[i, :3, 3] = pivot + shift - lin @ pivot
    return out


class Rig:
    """A blob laid on a target mesh: the shape of each mode there, and any frame's pose.

    The one place where doll parameters become what Blender shows: shape-key values (doll
    units, :func:`unit`), a per-unit shape offset per mode, and the rigid transform of the
    target. The live stand-in, Apply and the tests all go through it.

    Parameters
    ----------
    blob : ActiveBlob
    layout : ParamLayout
        How the parameters of the takes to pose are laid out.
    rest : (n, 3) float64
        The target's rest-pose local vertices.
    axes : {"XY", "XZ", "YZ"}
        The target's plane the doll is laid onto (ignored when ``mapping`` is given).
    modes : sequence of int, optional
        The modes the rig poses (default: all).
    use : (bool, bool, bool)
        Whether translation, rotation and scale reach the target.
    mapping : DollMapping, optional
        An existing mapping (a re-mix of an applied take must keep the one it was applied
        with); fitted to ``rest`` by default.

    Raises
    ------
    VoodooError
        If the target is flat or degenerate in the chosen plane.
    """

    def __init__(
        self,
        blob: ActiveBlob,
        layout: ParamLayout,
        rest: np.ndarray,
        axes: str = "XZ",
        modes=None,
        use=(True, True, True),
        mapping: DollMapping | None = None,
    ):
        self.blob = blob
        self.layout = layout
        self.rest = np.asarray(rest, dtype=np.float64)
        self.mapping = mapping or fit_mapping(blob, self.rest, axes)
        self.modes = list(range(blob.n_modes) if modes is None else modes)
        self.use = tuple(bool(u) for u in use)
        self.unit = unit(blob)
        #: (k, n, 3): local displacement of every vertex per unit shape-key value.
        self.offsets = mode_offsets(blob, self.mapping, self.rest, self.modes)

    def values(self, params: np.ndarray) -> np.ndarray:
        """Shape-key values (T, k) -- or (k,) for one frame -- of the rig's modes."""
        p = np.asarray(params, dtype=np.float64)
        cols = [self.layout.modes.start + j for j in self.modes]
        return p[..., cols] / self.unit

    def transforms(self, params: np.ndarray, use=None) -> np.ndarray:
        """Target-local 4x4 transforms (T, 4, 4) of the doll's similarity, per frame.

        ``use`` overrides which of translation, rotation and scale take part.
        """
        p = np.atleast_2d(np.asarray(params, dtype=np.float64))
        on = self.use if use is None else use
        return rigid_transforms(p, self.layout, self.blob, self.mapping, on)

    def pose(self, params: np.ndarray):
        """One frame: shape-key values (k,) and the target's transform (4, 4)."""
        return self.values(params), self.transforms(params)[0]

    def gains(self, gains=None) -> np.ndarray:
        """The rig's modes' gains (k,) checked by :func:`check_gain`; 1 for all by default."""
        if gains is None:
            return np.ones(len(self.modes))
        g = np.asarray(gains, dtype=object).ravel()
        if len(g) != len(self.modes):
            raise VoodooError(f"{len(g)} gains for {len(self.modes)} modes.")
        names = [str(self.blob.labels[j]) for j in self.modes]
        return np.array([check_gain(v, name) for v, name in zip(g, names, strict=True)])

    def shape(self, row: int, gain=1.0) -> np.ndarray:
        """The target's vertices (n, 3) at a shape-key value of 1 of the rig's mode ``row``.

        What a mode's shape key holds: the rest pose plus the mode's offsets times its gain
        (checked by :func:`check_gain`, so a NaN or infinite gain never reaches the mesh).
        """
        name = str(self.blob.labels[self.modes[row]])
        return self.rest + check_gain(gain, name) * self.offsets[row]

    def vertices(self, params: np.ndarray, gains=None) -> np.ndarray:
        """Where the target's vertices (n, 3) are in one frame (what Blender should show)."""
        values, transform = self.pose(params)
        offsets = self.offsets * self.gains(gains)[:, None, None]
        return predict_vertices(self.rest, offsets, values, transform)


def predict_vertices(
    vertices: np.ndarray,
    offsets: np.ndarray,
    values: np.ndarray,
    transform: np.ndarray | None = None,
) -> np.ndarray:
    """Target vertices for shape-key values and a transform (what Blender should show).

    Parameters
    ----------
    vertices : (n, 3) float64
        Rest-pose local vertices.
    offsets : (k, n, 3) float64
        Per-unit shape offsets (already scaled by any gain).
    values : (k,) float64
        Shape-key values.
    transform : (4, 4) float64, optional
        Applied after the shapes.
    """
    v = vertices + np.tensordot(values, offsets, axes=1)
    if transform is not None:
        v = v @ transform[:3, :3].T + transform[:3, 3]
    return v
