"""Pyramid levels of a blob: template pixels, their warp and the difference basis (§5.2).

Level ``l`` sees the capture frame at scale ``f = 2^-l`` (OpenCV ``pyrDown``: level pixel
``i`` sits on level-0 pixel ``2^l i``). Parameters stay in level-0 units at every level; only
the step sizes ``delta`` of the basis and the pixel units change.
"""

from __future__ import annotations

import copy

import numpy as np

from ..blob.mesh import TriMesh, rasterize
from ..blob.model import ActiveBlob
from . import kernels
from .params import ParamLayout, node_positions, placed_shape
from .photometry import Patches, group_triangles
from .pictures import emphasise, pyramid
from .warp import WarpBackend, WarpGeometry, padded

#: Parameter steps at every level: translations and modes move the blob by one level pixel
#: (RMS), rotation and log-scale move its RMS radius by one level pixel; photometric steps are
#: absolute. Steps of +-delta and +-2 delta form the basis (2 delta ~ the largest change
#: expected per iteration, §7).
PHOTOMETRIC_STEP = 0.04


class Level:
    """One pyramid level of a blob: template pixels, their triangles and mode fields.

    Parameters
    ----------
    blob : ActiveBlob
    index : int
        Pyramid level (0 = full resolution).
    layout : ParamLayout
    pixel_budget : int or None
        Use at most about this many template pixels (an even subsample) in the solve.
    patches : bool
        Group the pixels into lighting patches (see :mod:`.photometry`) whose gain and bias
        are projected out of every comparison.
    detail : float
        The texture's detail is strengthened by this (:func:`.pictures.emphasise`), as the
        frames' are.
    """

    def __init__(
        self,
        blob: ActiveBlob,
        index: int,
        layout: ParamLayout,
        pixel_budget: int | None = None,
        patches: bool = False,
        detail: float = 0.0,
    ):
        self.index = index
        self.scale = 2.0**-index
        #: The finest level the tracker uses (where occlusion is tested).
        self.finest = index == 0
        self.layout = layout
        f = self.scale
        self.centre = blob.centre * f
        self.vertices = blob.vertices * f
        self.modes = blob.modes[:, : layout.n_modes] * f  # level pixels per unit amplitude
        self.length = blob.length * f
        #: Node offsets (m, 2) the modal fit works on top of (the local stage's, level
        #: pixels, rest frame), or None (see ``CoarseToFineFitter.set_base``).
        self.offsets = None
        if index == 0:
            coords, tri, weights = blob.pixel_coords, blob.pixel_triangle, blob.pixel_weights
        else:
            ps = rasterize(TriMesh(self.vertices, blob.triangles, blob.boundary))
            coords, tri, weights = ps.coords, ps.triangle, ps.weights
        n_all = len(coords)
        if pixel_budget and len(coords) > pixel_budget:
            step = int(np.ceil(len(coords) / pixel_budget))
            coords, tri, weights = coords[::step], tri[::step], weights[::step]
        patch = None
        self.patch_of_triangle = None
        if patches:
            # Pixels stored patch by patch (each patch's sums are then one reduceat).
            centroids = self.vertices[blob.triangles].mean(axis=1)
            of_tri = group_triangles(centroids, tri, len(coords) / n_all)
            order = np.argsort(of_tri[tri], kind="stable")
            coords, tri, weights = coords[order], tri[order], weights[order]
            patch = of_tri[tri]
            self.patch_of_triangle = of_tri
        self.geometry = WarpGeometry(self.vertices, blob.triangles, coords, tri, weights)
        # Texture of this level: the blob's blurred crop taken down the same pyramid.
        origin = blob.texture_origin.astype(np.float64)
        plain = pyramid(blob.texture, index + 1)[-1]
        tex = emphasise(plain, detail)
        self.texture = tex
        self.texture_origin = origin * f
        local = (coords - self.texture_origin).round().astype(np.int64)
        local = np.clip(local, 0, np.array(tex.shape[1::-1]) - 1)
        self.template = np.ascontiguousarray(tex[local[:, 1], local[:, 0]])  # (n, 3) float32
        #: The template's colours as they are, without the detail strengthened (the
        #: confidence is measured on them, see :class:`.confidence.QualityMeter`).
        self.plain_template = (
            self.template if tex is plain else np.ascontiguousarray(plain[local[:, 1], local[:, 0]])
        )
        self.patches = None if patch is None else Patches(patch, self.template)
        # Pixel positions follow the warped nodes barycentrically (the warp is piecewise
        # affine): each pixel's three corners and weights. Padded to whole remap rows.
        n = len(coords)
        self.n_pad = padded(n)
        self.corners = np.ascontiguousarray(blob.triangles[tri], dtype=np.int32)  # (n, 3)
        self.weights = np.ascontiguousarray(weights, dtype=np.float32)  # (n, 3)
        self.all_valid = np.ones(n, dtype=bool)  # shared "every pixel is usable" mask
        # Triangles are the units of visibility: hidden (compressed by foreshortening),
        # occluded (outlying error) or off the picture, their pixels leave the solve.
        self.triangle = np.asarray(tri, dtype=np.int64)
        self.n_triangles = len(blob.triangles)
        self.triangle_size = np.bincount(self.triangle, minlength=self.n_triangles).astype(
            np.float64
        )

    def __len__(self) -> int:
        return len(self.geometry.coords)

    def every(self, step: int, patches: bool = True) -> tuple[Level, np.ndarray]:
        """The level on every ``step``-th of its pixels, and their rows (n',) in this one.

        The pixels stay grouped by lighting patch, so the subset keeps the patches (each
        with about a ``step``-th of its pixels, and at least its first); the texture, mesh
        and modes are shared. Without ``patches`` the rows are exactly every ``step``-th and
        the subset has no lighting patches (for sampling only).
        """
        rows = np.arange(0, len(self), max(int(step), 1))
        if self.patches is not None and patches:
            rows = np.union1d(rows, self.patches.starts)
        sub = copy.copy(self)
        g = self.geometry
        sub.geometry = WarpGeometry(
            g.vertices, g.triangles, g.coords[rows], g.triangle[rows], g.weights[rows]
        )
        sub.template = np.ascontiguousarray(self.template[rows])
        if sub.patches is not None:
            sub.patches = Patches(self.patches.of_pixel[rows], sub.template) if patches else None
        sub.n_pad = padded(len(rows))
        sub.corners = np.ascontiguousarray(self.corners[rows])
        sub.weights = np.ascontiguousarray(self.weights[rows])
        sub.all_valid = np.ones(len(rows), dtype=bool)
        sub.triangle = np.ascontiguousarray(self.triangle[rows])
        sub.triangle_size = np.bincount(sub.triangle, minlength=self.n_triangles).astype(np.float64)
        return sub, rows

    # ------------------------------------------------------------------ warping

    def positions(self, a: np.ndarray, nodes: np.ndarray | None = None, origin=(0.0, 0.0)):
        """Template pixels under the warp ``a``, level coordinates less ``origin``.

        Parameters
        ----------
        a : (P,) float64
        nodes : (m, 2) float64, optional
            ``self.nodes(a)`` when the caller has it already.
        origin : (2,) float
            Subtracted from every position (the picture's top-left corner).

        Returns
        -------
        (2, n_pad) float32
            x in row 0, y in row 1 (the layout ``remap`` wants); columns past ``len(self)``
            are padding.
        """
        if nodes is None:
            nodes = self.nodes(a)
        out = np.empty((2, self.n_pad), np.float32)
        nodes = np.ascontiguousarray(nodes, dtype=np.float64)
        kernels.positions(
            self.corners, self.weights, nodes, float(origin[0]), float(origin[1]), out
        )
        return out

    def nodes(self, a: np.ndarray) -> np.ndarray:
        """Mesh nodes under the warp ``a``, level coordinates (m, 2)."""
        shifted = a.copy()
        shifted[:2] *= self.scale
        return node_positions(
            shifted, self.layout, self.vertices, self.modes, self.centre, self.offsets
        )

    def translated_nodes(self, poses) -> list[np.ndarray]:
        """:meth:`nodes` of each pose: the same numbers.

        The shape is made once for poses that differ in their translation only.
        """
        out, shapes = [], {}
        for a in poses:
            key = a[2:].tobytes()
            if key not in shapes:
                shapes[key] = placed_shape(
                    a, self.layout, self.vertices, self.modes, self.centre, self.offsets
                )
            out.append(self.centre + a[:2] * self.scale + shapes[key])
        return out

    # ------------------------------------------------------------------ basis

    def steps(self) -> np.ndarray:
        """``delta`` per parameter (P,), level-0 units, for this level."""
        lay = self.layout
        d = np.full(lay.size, PHOTOMETRIC_STEP)
        d[:2] = 1.0 / self.scale
        d[2:4] = 1.0 / self.length
        d[lay.modes] = 1.0 / self.scale
        return d

    def basis(self, backend: WarpBackend, active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Difference images (Eq. 11) for +-delta, +-2 delta of every active parameter.

        Returns
        -------
        B : (3n, 4p) float64
            Columns ``I0 - W(I0, n_k)`` (with the lighting patches projected out).
        N : (p, 4p) float64
            Parameter displacement of each column (within the active parameters).
        """
        lay = self.layout
        delta = self.steps()
        steps = (-2.0, -1.0, 1.0, 2.0)
        kept, self.offsets = self.offsets, None  # the basis is of the template itself
        n = len(self)
        b = np.empty((3 * n, 4 * len(active)))
        nmat = np.zeros((len(active), 4 * len(active)))
        backend.bind(self.texture)
        i0 = self.template.astype(np.float64)
        bright = set(range(lay.size)[lay.brightness])
        contrast = set(range(lay.size)[lay.contrast])
        n_ch = len(bright)
        for j, k in enumerate(active):
            for s_i, s in enumerate(steps):
                col = 4 * j + s_i
                step = s * delta[k]
                nmat[j, col] = step
                if k in bright:
                    diff = np.zeros((n, 3))
                    ch = slice(None) if n_ch == 1 else sorted(bright).index(k)
                    diff[:, ch] = -step
                elif k in contrast:
                    diff = np.zeros((n, 3))
                    ch = slice(None) if n_ch == 1 else sorted(contrast).index(k)
                    diff[:, ch] = i0[:, ch] * (1.0 - np.exp(step))
                else:
                    a = lay.identity()
                    a[k] = -step  # the frame moved by +step looks like the template moved back
                    pos = self.positions(a, origin=self.texture_origin)
                    nodes = self.nodes(a) - self.texture_origin
                    diff = i0 - backend.sample(self.geometry, nodes, pos)
                b[:, col] = diff.ravel()
        self.offsets = kept
        if self.patches is not None:
            b = self.patches.project_basis(b.reshape(n, 3, -1)).reshape(3 * n, -1)
        return b, nmat
