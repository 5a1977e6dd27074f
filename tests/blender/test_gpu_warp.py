"""The GPU warp (Blender's gpu module, offscreen) against the CPU warp, on Mesa llvmpipe."""

import numpy as np
import pytest


@pytest.fixture
def gpu_backend(ctx, sub):
    gw = sub("operators.gpu_warp")
    if not gw.ensure_gpu():
        pytest.fail("no GPU context even after the Workbench initialisation")
    backend = gw.GpuWarp()
    yield backend
    backend.close()


def test_gpu_matches_cpu_sampling(gpu_backend, sub, clip_file):
    engine = sub("voodoo_addon")
    frames = clip_file["frames"]
    blob = engine.build_blob(frames[0], clip_file["contour"])
    tracker = engine.Tracker(blob)
    level = tracker.levels[0]
    cpu = engine.CpuWarp()
    rng = np.random.default_rng(3)
    for image in (frames[5], frames[12]):
        a = _warped(tracker, rng)
        pos = level.positions(a)
        nodes = level.nodes(a)
        for backend in (gpu_backend, cpu):
            backend.bind(image)
        got = gpu_backend.sample(level.geometry, nodes, pos)
        ref = cpu.sample(level.geometry, None, pos)
        assert got.shape == ref.shape == (len(level), 3)
        assert np.abs(got - ref).mean() < 1.0 / 255.0
        assert np.isfinite(got).all()


def _bilinear(image, pos):
    """Bilinear samples of ``image`` at ``pos`` (2, n) with exact (float64) weights."""
    h, w = image.shape[:2]
    x = np.clip(pos[0].astype(np.float64), 0, w - 1)
    y = np.clip(pos[1].astype(np.float64), 0, h - 1)
    x0 = np.minimum(np.floor(x).astype(int), w - 2)
    y0 = np.minimum(np.floor(y).astype(int), h - 2)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    im = image.astype(np.float64)
    top = im[y0, x0] * (1 - fx) + im[y0, x0 + 1] * fx
    bottom = im[y0 + 1, x0] * (1 - fx) + im[y0 + 1, x0 + 1] * fx
    return top * (1 - fy) + bottom * fy


def test_gpu_samples_a_strengthened_picture_exactly(gpu_backend, sub, clip_file):
    """A picture with its detail strengthened leaves [0, 1] (here -1.5 to 2.8): the GPU
    keeps it in 32-bit floats and weighs the four pixels exactly, where OpenCV's remap
    weighs them in 1/32 px steps (0.002 off on the mean here)."""
    engine = sub("voodoo_addon")
    pictures = sub("voodoo_addon.tracking.pictures")
    frames = clip_file["frames"]
    blob = engine.build_blob(frames[0], clip_file["contour"])
    tracker = engine.Tracker(blob, options=engine.TrackerOptions(detail=5.0))
    level = tracker.levels[0]
    image = pictures.FramePyramid(frames[5], blob.blur_sigma, 0, 5.0)[0]
    assert image.min() < -0.5 and image.max() > 1.5
    a = _warped(tracker, np.random.default_rng(3))
    pos = level.positions(a)
    gpu_backend.bind(image)
    got = gpu_backend.sample(level.geometry, level.nodes(a), pos)
    exact = _bilinear(image, pos[:, : len(level)])
    assert np.abs(got - exact).mean() < 1e-4


def _warped(tracker, rng):
    """A pose moved, turned and scaled a little, with random modes."""
    a = tracker.layout.identity()
    a[:4] += (3.3, -2.1, 0.2, 0.05)
    a[tracker.layout.modes] = rng.normal(0, 2.0, tracker.blob.n_modes)
    return a


def _track_alike(engine, gpu_backend, frames, clip_file, detail=None):
    """Track ``frames`` with the CPU and the GPU warp side by side: the two tracks within
    0.05 px of each other and the GPU's within 0.5 px of the truth on every frame."""
    blob = engine.build_blob(frames[0], clip_file["contour"])
    cpu = engine.Tracker(blob)
    gpu = engine.Tracker(blob, backend=gpu_backend)
    if detail is not None:
        assert cpu.fitter.detail == gpu.fitter.detail == detail
    for i, f in enumerate(frames):
        rc, rg = cpu.track(f), gpu.track(f)
        assert not rc.lost and not rg.lost
        assert np.linalg.norm(rc.nodes - rg.nodes, axis=1).mean() < 0.05
        truth = clip_file["truth"](i, blob.vertices)
        assert np.linalg.norm(rg.nodes - truth, axis=1).mean() < 0.5


def test_gpu_and_cpu_track_alike(gpu_backend, sub, clip_file):
    _track_alike(sub("voodoo_addon"), gpu_backend, clip_file["frames"][:8], clip_file)


def test_backend_choice(ctx, sub):
    gw = sub("operators.gpu_warp")
    backend, note = gw.make_backend("AUTO")
    if gw.is_software_renderer():
        assert backend.name == "cpu" and "no hardware GPU" in note
    else:
        assert backend.name == "gpu"
    assert gw.make_backend("CPU")[0].name == "cpu"
    assert gw.make_backend("GPU")[0].name == "gpu"


def test_gpu_and_cpu_track_a_faint_doll_alike(gpu_backend, sub, clip_file):
    """A faint doll is compared with its detail strengthened (pictures whose values leave
    [0, 1], which the 32-bit float texture and target keep); the two warps still follow it
    alike. The clip is the usual one with its contrast cut to 0.3, so the contrast rule
    strengthens the detail 5x. (Forced on the clip's printed paint, the detail makes any
    two samplers part by up to 0.7 px: OpenCV's remap, which weighs in 1/32 px steps,
    against exact bilinear weights; the GPU's are exact to 3e-5.)"""
    frames = [np.clip(0.5 + 0.3 * (f - 0.5), 0.0, 1.0) for f in clip_file["frames"][:8]]
    _track_alike(sub("voodoo_addon"), gpu_backend, frames, clip_file, detail=5.0)
