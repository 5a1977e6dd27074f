"""The GPU warp backend: the blob's textured triangles drawn offscreen with Blender's ``gpu``.

Each template pixel is a fragment of a triangle whose corners sit at the template node
positions and whose texture coordinates are the warped node positions in the frame, so the
fragment reads the frame bilinearly at exactly the piecewise-affine warp of that pixel -- the
CPU backend's ``remap``, done by the rasteriser (paper §3, "texture mapping hardware").
Pixels the rasteriser leaves uncovered (exactly on the outline) are sampled on the CPU.
"""

import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from ..voodoo_addon.errors import VoodooError
from ..voodoo_addon.tracking.warp import CpuWarp, WarpBackend, WarpGeometry

#: Renderer names of software rasterisers (slower than the CPU backend).
SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swrast", "swiftshader", "software rasterizer")

_VERTEX = """
void main() {
  uv = (src + 0.5) / source_size;
  gl_Position = vec4((pos + 0.5) / target_size * 2.0 - 1.0, 0.0, 1.0);
}
"""
_FRAGMENT = """
void main() {
  color = vec4(texture(image, uv).rgb, 1.0);
}
"""


def _offscreen_works() -> bool:
    try:
        gpu.types.GPUOffScreen(4, 4).free()
        return True
    except Exception:  # noqa: BLE001 - any failure means "no GPU context"
        return False


def _initialise_background() -> None:
    """One tiny Workbench render brings the GPU up in background mode.

    See docs/design.md, *Blender facts*.
    """
    scene = bpy.data.scenes.new(".voodoo_gpu_init")
    cam_data = bpy.data.cameras.new(".voodoo_gpu_init")
    cam = bpy.data.objects.new(".voodoo_gpu_init", cam_data)
    try:
        scene.collection.objects.link(cam)
        scene.camera = cam
        scene.render.engine = "BLENDER_WORKBENCH"
        scene.render.resolution_x = scene.render.resolution_y = 8
        bpy.ops.render.render(write_still=False, scene=scene.name)
    finally:
        bpy.data.objects.remove(cam)
        bpy.data.cameras.remove(cam_data)
        bpy.data.scenes.remove(scene)


def ensure_gpu() -> bool:
    """True when offscreen drawing works (initialising it headless if needed)."""
    if _offscreen_works():
        return True
    if bpy.app.background:
        try:
            _initialise_background()
        except RuntimeError:
            return False
        return _offscreen_works()
    return False


def is_software_renderer() -> bool:
    name = gpu.platform.renderer_get().lower()
    return any(s in name for s in SOFTWARE_RENDERERS)


def _shader():
    info = gpu.types.GPUShaderCreateInfo()
    info.push_constant("VEC2", "target_size")
    info.push_constant("VEC2", "source_size")
    info.sampler(0, "FLOAT_2D", "image")
    iface = gpu.types.GPUStageInterfaceInfo("voodoo_warp_iface")
    iface.smooth("VEC2", "uv")
    info.vertex_in(0, "VEC2", "pos")
    info.vertex_in(1, "VEC2", "src")
    info.vertex_out(iface)
    info.fragment_out(0, "VEC4", "color")
    info.vertex_source(_VERTEX)
    info.fragment_source(_FRAGMENT)
    return gpu.shader.create_from_info(info)


class _Target:
    """An offscreen raster covering one geometry's template pixels."""

    def __init__(self, geometry: WarpGeometry):
        lo = np.floor(geometry.coords.min(axis=0)).astype(int)
        hi = np.ceil(geometry.coords.max(axis=0)).astype(int)
        self.width, self.height = int(hi[0] - lo[0] + 1), int(hi[1] - lo[1] + 1)
        self.offscreen = gpu.types.GPUOffScreen(self.width, self.height, format="RGBA32F")
        self.pos = np.ascontiguousarray(geometry.vertices - lo, dtype=np.float32)
        local = (geometry.coords - lo).astype(np.int64)
        self.flat = local[:, 1] * self.width + local[:, 0]
        self.indices = np.ascontiguousarray(geometry.triangles, dtype=np.int32)


class GpuWarp(WarpBackend):
    """Warp by drawing textured triangles into a ``GPUOffScreen`` and reading it back.

    Raises
    ------
    VoodooError
        When no GPU context can be had.
    """

    name = "gpu"
    needs_nodes = True

    def __init__(self):
        if not ensure_gpu():
            raise VoodooError("No GPU context for the GPU warp; use the CPU warp.")
        self._shader = _shader()
        self._targets: dict = {}
        self._texture = None
        self._size = (1, 1)
        self._cpu = CpuWarp()

    def bind(self, image: np.ndarray) -> None:
        h, w = image.shape[:2]
        rgba = np.ones((h, w, 4), dtype=np.float32)
        rgba[:, :, :3] = image
        buf = gpu.types.Buffer("FLOAT", w * h * 4, rgba.ravel())
        self._texture = gpu.types.GPUTexture((w, h), format="RGBA32F", data=buf)
        self._size = (w, h)
        self._cpu.bind(image)

    def _target(self, geometry: WarpGeometry) -> _Target:
        key = id(geometry)
        target = self._targets.get(key)
        if target is None or target.geometry is not geometry:
            target = _Target(geometry)
            target.geometry = geometry
            self._targets[key] = target
        return target

    def sample(self, geometry: WarpGeometry, nodes, positions: np.ndarray) -> np.ndarray:
        t = self._target(geometry)
        batch = batch_for_shader(
            self._shader,
            "TRIS",
            {"pos": t.pos, "src": nodes.astype(np.float32)},
            indices=t.indices,
        )
        with t.offscreen.bind():
            fb = gpu.state.active_framebuffer_get()
            fb.clear(color=(0.0, 0.0, 0.0, 0.0))
            self._shader.bind()
            self._shader.uniform_float("target_size", (t.width, t.height))
            self._shader.uniform_float("source_size", self._size)
            self._shader.uniform_sampler("image", self._texture)
            batch.draw(self._shader)
            buf = fb.read_color(0, 0, t.width, t.height, 4, 0, "FLOAT")
        buf.dimensions = t.width * t.height * 4
        raster = np.asarray(buf, dtype=np.float32).reshape(-1, 4)
        out = raster[t.flat]
        missing = out[:, 3] == 0.0
        if missing.any():
            out[missing, :3] = self._cpu.sample(geometry, None, positions)[missing]
        return np.ascontiguousarray(out[:, :3])

    def close(self) -> None:
        for t in self._targets.values():
            t.offscreen.free()
        self._targets.clear()
        self._texture = None


def make_backend(choice: str) -> tuple[WarpBackend, str]:
    """The warp backend for a setting ('AUTO', 'GPU', 'CPU') and a note on the choice."""
    if choice == "CPU":
        return CpuWarp(), "CPU warp"
    if choice == "GPU":
        return GpuWarp(), f"GPU warp ({gpu.platform.renderer_get()})"
    if ensure_gpu() and not is_software_renderer():
        return GpuWarp(), f"GPU warp ({gpu.platform.renderer_get()})"
    return CpuWarp(), "CPU warp (no hardware GPU)"
