"""Lighting that varies across the surface: a gain and a bias per patch, projected out.

The paper's Eq. 4 gives the whole blob one brightness and one contrast. A sheet bending under
a lamp is lit differently in every part, and a webcam's exposure and white balance drift by
channel. Here the template pixels are grouped into small *patches* (a few triangles, a few
hundred pixels each) and every patch gets its own gain and bias, the same for the three
channels (shading is grey: a lamp or a hand's shadow dims red, green and blue alike):

    frame_c(W(x)) ~ g_p * template_c(x) + b_p        for x in patch p

while what differs between channels -- white balance, a coloured lamp -- is global and left
to the brightness and contrast parameters of each channel (paper Eq. 4). Keeping the
patches grey keeps colour telling the fit where it is: a patch that may take any gain and
bias per channel would match a red square to a blue one.

The gains and biases are not parameters of the fit: for any geometry their least-squares
values are a closed form, so they are *projected out* (variable projection, Golub & Pereyra
1973; the illumination subspace of Hager & Belhumeur 1998). Within each patch the
difference image, and every column of the difference basis, lose their mean and their
component along the template's own variation; what is left is what no lighting change can
explain -- misalignment, occlusion, highlights. Pixels are stored patch by patch, so the
projection of a difference image is one pass per patch (:func:`.kernels.project`).

The same sums give each patch's correlation with the template: a patch that a lighting
change cannot make look like the template (a hand over it, a flat card) correlates poorly,
which the occlusion test uses -- the projection alone would happily explain a flat occluder
as a patch whose gain fell to zero.
"""

from __future__ import annotations

import numpy as np

from . import kernels

#: A patch gathers triangles until it holds about this many of the level's pixels...
PATCH_PIXELS = 48
#: ... or about this fraction of them, whichever is more.
PATCH_SHARE = 1.0 / 32


def group_triangles(centroids: np.ndarray, pixel_triangle: np.ndarray, n_pixels_per_area):
    """Patch index of every triangle: neighbouring triangles gathered to ~PATCH_PIXELS pixels.

    Triangles are binned on a square grid of their centroids whose cells hold about
    :data:`PATCH_PIXELS` pixels or :data:`PATCH_SHARE` of the level's, whichever is more; a
    triangle with that many pixels of its own is a patch of its own; a bin left with fewer
    than half that many pixels joins the nearest bigger one.

    Parameters
    ----------
    centroids : (t, 2) float64
        Triangle centroids, level pixels.
    pixel_triangle : (n,) int
        The triangle of each level pixel in use.
    n_pixels_per_area : float
        Pixels in use per square level pixel (1, or less when subsampled).

    Returns
    -------
    (t,) int64
        Patch of each triangle, 0..n_patches-1.
    """
    t = len(centroids)
    count = np.bincount(pixel_triangle, minlength=t).astype(np.float64)
    target = max(PATCH_PIXELS, PATCH_SHARE * float(count.sum()))
    side = np.sqrt(target / max(n_pixels_per_area, 1e-9))
    cell = np.floor((centroids - centroids.min(axis=0)) / side).astype(np.int64)
    key = cell[:, 0] * (int(cell[:, 1].max()) + 1) + cell[:, 1]
    own = count >= target
    key = np.where(own, key.max() + 1 + np.arange(t), key)
    _, patch = np.unique(key, return_inverse=True)
    # Small bins join the nearest bin that is big enough (by centroid).
    n_patch = int(patch.max()) + 1
    size = np.bincount(patch, weights=count, minlength=n_patch)
    centre = (
        np.stack(
            [
                np.bincount(patch, weights=centroids[:, d] * (count + 1e-9), minlength=n_patch)
                for d in range(2)
            ],
            axis=1,
        )
        / (size + 1e-9 * np.bincount(patch, minlength=n_patch))[:, None]
    )
    big = size >= 0.5 * target
    if big.any() and not big.all():
        small = np.nonzero(~big)[0]
        targets = np.nonzero(big)[0]
        dist = np.linalg.norm(centre[small, None] - centre[None, targets], axis=2)
        remap = np.arange(n_patch)
        remap[small] = targets[dist.argmin(axis=1)]
        patch = remap[patch]
    _, patch = np.unique(patch, return_inverse=True)
    return patch.astype(np.int64)


class Patches:
    """The lighting patches of one level, whose pixels are stored patch by patch.

    Parameters
    ----------
    patch : (n,) int64
        Patch of each pixel, non-decreasing.
    template : (n, c) float32
        Template colours.
    """

    def __init__(self, patch: np.ndarray, template: np.ndarray):
        patch = np.asarray(patch, np.int64)
        if len(patch) and np.any(np.diff(patch) < 0):
            raise ValueError("pixels must be grouped by patch")
        self.of_pixel = patch
        self.starts = np.r_[0, np.nonzero(np.diff(patch))[0] + 1].astype(np.int64)
        self._repeat = np.diff(np.r_[self.starts, len(patch)])
        t = np.asarray(template, np.float64)
        self.channels = t.shape[1]
        self.count = self._repeat.astype(np.float64) * self.channels  # values per patch
        self.template = t
        self.dev = t - self._spread(self._sum(t) / self.count)  # (n, c)
        self.energy = self._sum(self.dev * self.dev)  # (G,) sum of squared deviations
        self._energy = self.energy + 1e-12
        per_value = self.energy / self.count
        #: Patches with enough texture for their correlation to mean something.
        self.textured = per_value >= 0.1 * float(np.median(per_value))
        self._bounds = np.r_[self.starts, len(patch)].astype(np.int64)
        self._template32 = np.ascontiguousarray(t, dtype=np.float32)
        self._everything = np.ones(len(patch), dtype=bool)

    def __len__(self) -> int:
        return len(self.starts)

    def _sum(self, x: np.ndarray) -> np.ndarray:
        """Per-patch sums over pixels and channels: (G,) for (n, c), (G, q) for (n, c, q)."""
        return np.add.reduceat(x, self.starts, axis=0).sum(axis=1)

    def _spread(self, per_patch: np.ndarray) -> np.ndarray:
        """Per-patch values back to pixels, broadcastable against (n, c[, q])."""
        out = np.repeat(per_patch, self._repeat, axis=0)
        return out[:, None] if out.ndim == 1 else out[:, None, :]

    def project_basis(self, x: np.ndarray) -> np.ndarray:
        """Remove each patch's best gain and bias from every column of ``x`` (n, c, q)."""
        dev = self.dev[:, :, None]
        mean = self._sum(x) / self.count[:, None]
        along = self._sum(x * dev) / self._energy[:, None]
        return x - self._spread(mean) - dev * self._spread(along)

    def project(self, d: np.ndarray, mask: np.ndarray | None = None):
        """The difference image ``d = template - frame`` (n, c) without each patch's lighting.

        Parameters
        ----------
        d : (n, c) float32
        mask : (n,) bool, optional
            Fit the lighting on these pixels only (the rest come out zero).

        Returns
        -------
        projected : (n, c) float32
        correlation : (G,) float64
            Each patch's correlation of frame and template (NaN where the patch has no
            pixel in the mask or too little texture).
        """
        d = np.ascontiguousarray(d, dtype=np.float32)
        one, zero = np.ones(self.channels, np.float32), np.zeros(self.channels, np.float32)
        return self.compare(d, np.zeros_like(d), one, zero, mask)

    def compare(self, target, samples, gain, bias, mask=None, out=None):
        """:meth:`project` of ``target - (samples * gain - bias)``, in one pass.

        ``target`` and ``samples`` (n, c) float32, ``gain`` and ``bias`` (c,) float32: the
        global lighting undone (see :func:`.kernels.project`). ``out`` (n, c) float32
        receives the projection (a new array by default).
        """
        if out is None:
            out = np.empty(target.shape, np.float32)
        mask = self._everything if mask is None else np.ascontiguousarray(mask, dtype=bool)
        correlation = np.empty(len(self.starts))
        kernels.project(
            samples,
            target,
            gain,
            bias,
            self._template32,
            self._bounds,
            mask,
            self.textured,
            out,
            correlation,
        )
        return out, correlation
