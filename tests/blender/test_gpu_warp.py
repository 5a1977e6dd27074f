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
        a = tracker.layout.identity()
        a[:4] += (3.3, -2.1, 0.2, 0.05)
        a[tracker.layout.modes] = rng.normal(0, 2.0, blob.n_modes)
        pos = level.positions(a)
        nodes = level.nodes(a)
        for backend in (gpu_backend, cpu):
            backend.bind(image)
        got = gpu_backend.sample(level.geometry, nodes, pos)
        ref = cpu.sample(level.geometry, None, pos)
        assert got.shape == ref.shape == (len(level), 3)
        assert np.abs(got - ref).mean() < 1.0 / 255.0
        assert np.isfinite(got).all()


def test_gpu_and_cpu_track_alike(gpu_backend, sub, clip_file):
    engine = sub("voodoo_addon")
    frames = clip_file["frames"][:8]
    blob = engine.build_blob(frames[0], clip_file["contour"])
    cpu = engine.Tracker(blob)
    gpu = engine.Tracker(blob, backend=gpu_backend)
    for i, f in enumerate(frames):
        rc, rg = cpu.track(f), gpu.track(f)
        assert not rc.lost and not rg.lost
        assert np.linalg.norm(rc.nodes - rg.nodes, axis=1).mean() < 0.05
        truth = clip_file["truth"](i, blob.vertices)
        assert np.linalg.norm(rg.nodes - truth, axis=1).mean() < 0.5


def test_backend_choice(ctx, sub):
    gw = sub("operators.gpu_warp")
    backend, note = gw.make_backend("AUTO")
    if gw.is_software_renderer():
        assert backend.name == "cpu" and "no hardware GPU" in note
    else:
        assert backend.name == "gpu"
    assert gw.make_backend("CPU")[0].name == "cpu"
    assert gw.make_backend("GPU")[0].name == "gpu"


@pytest.mark.xfail(
    reason="with the detail strengthened the GPU warp drifts from the CPU warp (BENCHMARKS.md)"
)
def test_gpu_and_cpu_track_alike_with_the_detail_strengthened(gpu_backend, sub, clip_file):
    """Faint dolls are compared with their detail strengthened: pictures whose values leave
    [0, 1], which the GPU texture and target (32-bit float) keep. The two warps should
    follow the clip alike, as they do without (within 0.05 px). They do not yet: forced on
    this clip (its paint is not faint), the GPU track is 0.73 px from the CPU track on
    frame 3 and 1.26 px on frame 5 (llvmpipe, bpy 5.0.1, 5.1.2 and 5.2.3), 1.08 px off the
    truth where the CPU track is 0.31. The strengthened detail weighs the sampling's last
    bits more; the GPU's bilinear filtering weights are likely the coarser ones."""
    engine = sub("voodoo_addon")
    frames = clip_file["frames"][:6]
    blob = engine.build_blob(frames[0], clip_file["contour"])
    options = engine.TrackerOptions(detail=5.0)
    cpu = engine.Tracker(blob, options=options)
    gpu = engine.Tracker(blob, options=options, backend=gpu_backend)
    assert cpu.fitter.detail == gpu.fitter.detail == 5.0
    for i, f in enumerate(frames):
        rc, rg = cpu.track(f), gpu.track(f)
        assert not rc.lost and not rg.lost
        assert np.linalg.norm(rc.nodes - rg.nodes, axis=1).mean() < 0.05
        truth = clip_file["truth"](i, blob.vertices)
        assert np.linalg.norm(rg.nodes - truth, axis=1).mean() < 1.0
