"""The whole Active Voodoo Dolls job, headless, on the bundled sample take.

Run with the project's virtual environment (Blender as a Python module)::

    .venv/bin/python scripts/demo.py [--out out] [--frames N]

Everything goes through the add-on's public operators, loaded the way a user's extension is:
the sample clip becomes the scene's movie clip, frame 0 is captured, the bundled outline
becomes a Mask and then the blob's outline, the blob "Doll" is built, the clip is tracked onto
a flat cut-out bunny and the take applied to a 3D cracker box too. Writes into ``--out``:

``demo.blend``
    The scene: clip (path relative to the file), capture, outline, blob, take, both characters
    animated (shape keys + transform keys), a camera framing their whole motion, a light.
``preview.mp4``
    Per frame: the clip with the tracked mesh drawn on it, beside a Workbench render of the
    characters at that frame.
``modes.png``
    The keyed mode amplitudes (shape-key values) and the similarity (translation, rotation,
    scale) over the take.

``--frames N`` tracks and renders only the first N frames (quick runs); the default is the
whole clip.
"""

import argparse
import importlib
import json
import os
import shutil
import sys
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

# Blender's user folders must point at a scratch folder before bpy is first imported, so the
# user's own settings and extensions are never touched.
SCRATCH = Path(tempfile.mkdtemp(prefix="voodoo-demo-"))
os.environ["BLENDER_USER_RESOURCES"] = str(SCRATCH / "user")

import bpy  # noqa: E402

# isort: split
import blender_addon  # noqa: E402  (scripts/ is on sys.path when this file runs)
import characters  # noqa: E402
import cv2  # noqa: E402
import numpy as np  # noqa: E402
from mathutils import Euler, Vector  # noqa: E402
from plot_take import plot_take  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SAMPLE_CLIP = ROOT / "samples" / "sample_take.mp4"
SAMPLE_OUTLINE = ROOT / "samples" / "sample_take.json"
DEFAULT_OUT = ROOT / "out"
BLEND_NAME = "demo.blend"
PREVIEW_NAME = "preview.mp4"
MODES_NAME = "modes.png"

DOLL_NAME = "Doll"
MASK_NAME = "Outline"
TAKE_NAME = "Sample Take"
AXES = "XZ"  # both characters stand in the XZ plane, facing -Y

# Characters side by side: bunny on the left, box on the right (world X of their rest centres).
BUNNY_X = -1.6
BOX_X = 1.9

# Camera: nearly a front view, raised and turned a little so the box shows its depth; it is
# pulled back until the characters' whole motion fits, with this much margin around it.
CAMERA_ELEVATION_DEG = 12.0
CAMERA_AZIMUTH_DEG = 18.0
CAMERA_LENS_MM = 50.0
FRAMING_MARGIN = 1.12
# Render size (wide: the characters stand side by side) and Workbench look.
RENDER_SIZE = (640, 360)
RENDER_AA = "5"
WORLD_COLOUR = (0.045, 0.05, 0.06)
SUN_ROTATION_DEG = (50.0, 10.0, 30.0)

# Preview video drawing (BGR).
LIVE_MESH = (60, 230, 255)
LOST_MESH = (40, 40, 255)
LABEL_SCALE = 0.5


class DemoError(Exception):
    """A step of the demo failed; the message says which and why."""


# ---------------------------------------------------------------------------------- reporting


class Steps:
    """Numbered progress lines for the demo's steps, with their run times."""

    def __init__(self, total: int):
        self.total = total
        self.times: list[tuple[str, float]] = []

    @contextmanager
    def __call__(self, title: str):
        """Announce a step, run the body, then print and keep how long it took."""
        print(f"[{len(self.times) + 1}/{self.total}] {title} ...", flush=True)
        start = time.perf_counter()
        yield
        seconds = time.perf_counter() - start
        self.times.append((title, seconds))
        print(f"      done in {seconds:.1f} s", flush=True)

    def summary(self) -> str:
        """Run time per step and in total, one line each."""
        lines = [f"  {seconds:6.1f} s  {title}" for title, seconds in self.times]
        total = sum(seconds for _, seconds in self.times)
        return "\n".join([*lines, f"  {total:6.1f} s  total"])


def run_operator(operator, **properties) -> None:
    """Run a bpy operator; raise DemoError when it does not finish.

    Operators report their errors with ``self.report``: the bpy module prints them as
    ``Error: ...`` lines and, when called from Python, raises RuntimeError with the message.
    """
    name = operator.idname_py()
    try:
        result = operator(**properties)
    except RuntimeError as exc:
        raise DemoError(
            f"bpy.ops.{name} failed: {str(exc).strip().removeprefix('Error: ')}"
        ) from None
    if "FINISHED" not in result:
        raise DemoError(f"bpy.ops.{name} returned {sorted(result)}; see the Error line above.")


def file_size(path: Path) -> str:
    """A file's size for people (kB or MB)."""
    size = path.stat().st_size
    return f"{size / 1e6:.1f} MB" if size >= 1e6 else f"{size / 1e3:.0f} kB"


# ---------------------------------------------------------------------------------- the scene


def start_blender(scratch: Path):
    """An empty scene with the checkout enabled as an extension; returns ``(addon, sub)``.

    ``addon`` is the add-on's module name, ``sub("operators.storage")`` imports its submodules.
    """
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.preferences.filepaths.save_version = 0  # no demo.blend1 backups
    addon = blender_addon.enable_from_checkout(repo_module="voodoo_demo", scratch=scratch)
    return addon, lambda name: importlib.import_module(f"{addon}.{name}")


def load_clip(scene, path: Path, frames: int | None):
    """Load the clip as the scene's active clip; the scene's frames and rate follow it."""
    clip = bpy.data.movieclips.load(str(path))
    scene.active_clip = clip
    count = clip.frame_duration if frames is None else min(frames, clip.frame_duration)
    scene.frame_start = clip.frame_start
    scene.frame_end = clip.frame_start + count - 1
    scene.render.fps = round(clip.fps)
    scene.render.fps_base = round(clip.fps) / clip.fps
    scene.frame_set(scene.frame_start)
    return clip


def add_outline_mask(frames_module, points, size):
    """A Mask with one closed, straight-edged spline through the outline's pixel points."""
    co = frames_module.pixels_to_mask(np.asarray(points, dtype=float), size)
    mask = bpy.data.masks.new(MASK_NAME)
    spline = mask.layers.new(name="Layer").splines.new()
    spline.points.add(len(co) - 1)
    for point, (x, y) in zip(spline.points, co, strict=True):
        point.co = (x, y)
        point.handle_type = "VECTOR"
        point.handle_left = point.handle_right = (x, y)
    spline.use_cyclic = True
    return mask


def build_doll(sub, clip) -> None:
    """Capture the clip's first frame, outline it from the bundled contour, build the blob."""
    run_operator(bpy.ops.voodoo.capture_frame)
    points = json.loads(SAMPLE_OUTLINE.read_text())["points"]
    add_outline_mask(sub("operators.pixels"), points, tuple(clip.size))
    run_operator(bpy.ops.voodoo.contour_from_mask, mask=MASK_NAME)
    run_operator(bpy.ops.voodoo.build_blob, name=DOLL_NAME)


def make_characters(scene):
    """The flat cut-out bunny and the 3D cracker box, side by side in front view."""
    bunny = characters.make_cutout(collection=scene.collection)
    box = characters.make_extruded(collection=scene.collection)
    bunny.location.x = BUNNY_X
    box.location.x = BOX_X
    return bunny, box


def track_and_apply(scene, bunny, box, frames: int | None) -> str:
    """Track the clip onto the bunny, apply the take to the box too; returns the take's name."""
    s = scene.voodoo
    s.axes = AXES
    s.take_name = TAKE_NAME
    s.target = bunny
    run_operator(bpy.ops.voodoo.track_clip, max_frames=frames or 0)
    take = s.last_take
    view_layer = bpy.context.view_layer
    for obj in view_layer.objects:
        obj.select_set(obj == box)
    view_layer.objects.active = box
    run_operator(bpy.ops.voodoo.apply_take, take=take, selected=True)
    return take


def motion_corners(scene, objects) -> np.ndarray:
    """World corners (8, 3) of the box holding ``objects`` in every frame of the scene."""
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        for obj in objects:
            evaluated = obj.evaluated_get(depsgraph)
            mesh = evaluated.to_mesh()
            co = np.empty(3 * len(mesh.vertices))
            mesh.vertices.foreach_get("co", co)
            evaluated.to_mesh_clear()
            matrix = np.array(evaluated.matrix_world)
            world = co.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]
            lo, hi = np.minimum(lo, world.min(axis=0)), np.maximum(hi, world.max(axis=0))
    scene.frame_set(scene.frame_start)
    return np.array([[(lo, hi)[(i >> k) & 1][k] for k in range(3)] for i in range(8)])


def add_camera_and_light(scene, corners: np.ndarray):
    """A camera that frames ``corners`` (8, 3) with a margin, and a sun light."""
    data = bpy.data.cameras.new("Camera")
    data.lens = CAMERA_LENS_MM
    camera = bpy.data.objects.new("Camera", data)
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.rotation_euler = Euler(
        (np.radians(90.0 - CAMERA_ELEVATION_DEG), 0.0, np.radians(CAMERA_AZIMUTH_DEG))
    )
    centre = corners.mean(axis=0)
    padded = centre + FRAMING_MARGIN * (corners - centre)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    location, _ = camera.camera_fit_coords(depsgraph, padded.ravel().tolist())
    camera.location = location
    data.clip_end = 10.0 * (Vector(location) - Vector(centre)).length

    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", type="SUN"))
    sun.rotation_euler = Euler(np.radians(SUN_ROTATION_DEG).tolist())
    scene.collection.objects.link(sun)
    return camera


def setup_render(scene) -> None:
    """Workbench: material colours, studio light, shadows, cavity, outlines, a dark world."""
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = RENDER_SIZE
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = "//render/"  # where an animation render from the file goes
    scene.display.render_aa = RENDER_AA
    shading = scene.display.shading
    shading.light = "STUDIO"
    shading.color_type = "MATERIAL"
    shading.show_shadows = True
    shading.show_cavity = True
    shading.show_object_outline = True
    scene.view_settings.view_transform = "Standard"  # the materials' colours, unfiltered
    world = bpy.data.worlds.new("World")
    world.color = WORLD_COLOUR
    scene.world = world


def save_blend(path: Path, clip) -> None:
    """Save the scene, with the clip's path relative to the file where that is possible."""
    path.parent.mkdir(parents=True, exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=str(path), check_existing=False)
    try:
        clip.filepath = bpy.path.relpath(str(SAMPLE_CLIP))
    except ValueError:  # another drive (Windows): keep the absolute path
        return
    bpy.ops.wm.save_mainfile()


# ---------------------------------------------------------------------------------- preview


def render_frames(scene, folder: Path, progress_bar) -> dict[int, Path]:
    """Render every scene frame to a PNG with Workbench; returns {scene frame: file}."""
    folder.mkdir(parents=True, exist_ok=True)
    frames = range(scene.frame_start, scene.frame_end + 1)
    bar = progress_bar(len(frames), label="rendering")
    files = {}
    for done, frame in enumerate(frames, start=1):
        scene.frame_set(frame)
        files[frame] = folder / f"frame_{frame:04d}.png"
        scene.render.filepath = str(files[frame])
        with quiet_stdout():
            run_operator(bpy.ops.render.render, write_still=True)
        bar(done)
    return files


@contextmanager
def quiet_stdout():
    """Silence what C code prints on stdout (Blender's per-render status lines)."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "w") as devnull:
            os.dup2(devnull.fileno(), 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)


def label(canvas: np.ndarray, text: str, org: tuple[int, int]) -> None:
    """White text with a dark outline, readable on any background."""
    for colour, thickness in (((0, 0, 0), 3), ((255, 255, 255), 1)):
        cv2.putText(
            canvas, text, org, cv2.FONT_HERSHEY_SIMPLEX, LABEL_SCALE, colour, thickness, cv2.LINE_AA
        )


def write_preview(path: Path, take, frames: np.ndarray, renders: dict, draw_mesh) -> int:
    """Clip frame + tracked mesh beside the render, per take row; returns frames written.

    Parameters
    ----------
    take : Take
        ``vertices`` (T, m, 2) tracked nodes in clip pixels, ``triangles`` (t, 3).
    frames : (T,) int
        Scene frame of each take row.
    renders : dict
        Scene frame -> rendered PNG.
    draw_mesh : callable
        The engine's ``preview.draw_mesh(canvas, vertices, triangles, colour, scale=...)``.
    """
    render_width, height = RENDER_SIZE
    capture = cv2.VideoCapture(str(SAMPLE_CLIP))
    capture.set(cv2.CAP_PROP_POS_FRAMES, int(take.frame_indices[0]))
    scale = height / capture.get(cv2.CAP_PROP_FRAME_HEIGHT)  # the clip at the render's height
    width = round(capture.get(cv2.CAP_PROP_FRAME_WIDTH) * scale)
    writer = cv2.VideoWriter(
        str(path), cv2.VideoWriter_fourcc(*"mp4v"), float(take.fps), (width + render_width, height)
    )
    if not capture.isOpened() or not writer.isOpened():
        raise DemoError(f"OpenCV could not read {SAMPLE_CLIP} or write {path}.")
    written = 0
    try:
        for row, frame in enumerate(frames):
            ok, image = capture.read()
            if not ok or int(frame) not in renders:
                break
            left = cv2.resize(image, (width, height), interpolation=cv2.INTER_AREA)
            colour = LOST_MESH if take.lost[row] else LIVE_MESH
            draw_mesh(left, take.vertices[row], take.triangles, colour, scale=scale)
            status = "LOST" if take.lost[row] else f"confidence {take.confidence[row]:.2f}"
            label(left, f"clip frame {take.frame_indices[row]}  {status}", (10, 22))
            right = cv2.imread(str(renders[int(frame)]))
            label(right, f"scene frame {frame}  (Workbench)", (10, 22))
            writer.write(np.hstack([left, right]))
            written += 1
    finally:
        capture.release()
        writer.release()
    return written


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="output folder")
    parser.add_argument(
        "--frames", type=int, default=None, help="track and render only the first N frames"
    )
    args = parser.parse_args(argv)
    if args.frames is not None and args.frames < 1:
        parser.error("--frames must be 1 or more")
    return args


def run(args: argparse.Namespace) -> None:
    """The demo's steps; raises DemoError when one fails."""
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    steps = Steps(total=7)
    with steps("Start Blender and enable the add-on"):
        addon, sub = start_blender(SCRATCH)
        scene = bpy.context.scene
        print(f"      {addon} (Blender {bpy.app.version_string})")
    with steps(f"Load {SAMPLE_CLIP.name}, capture frame 0, outline it, build the blob"):
        clip = load_clip(scene, SAMPLE_CLIP, args.frames)
        build_doll(sub, clip)
    with steps("Track the clip onto the bunny, apply the take to the cracker box"):
        bunny, box = make_characters(scene)
        take_name = track_and_apply(scene, bunny, box, args.frames)
    with steps("Frame the characters' motion, save demo.blend"):
        corners = motion_corners(scene, (bunny, box))
        add_camera_and_light(scene, corners)
        setup_render(scene)
        save_blend(out / BLEND_NAME, clip)

    store, apply = sub("operators.storage"), sub("operators.apply")
    blob = store.stored_blob(scene.voodoo.blob)
    take = store.stored_take(scene.voodoo.blob, take_name).take
    frames = store.stored_take(scene.voodoo.blob, take_name).frames
    with steps(f"Render {scene.frame_end - scene.frame_start + 1} frames with Workbench"):
        renders = render_frames(
            scene, SCRATCH / "frames", sub("voodoo_addon.takes.take").ProgressBar
        )
    with steps("Compose preview.mp4"):
        draw_mesh = sub("voodoo_addon.blob.preview").draw_mesh
        written = write_preview(out / PREVIEW_NAME, take, frames, renders, draw_mesh)
        print(f"      {written} frames")
    with steps("Plot the modes"):
        modes = apply.layout_for(blob, take).modes
        values = take.params[:, modes] / sub("voodoo_addon.takes.rig").unit(blob)
        names = [str(n) for n in take.param_names[modes]]
        title = f"{DOLL_NAME}: take '{take_name}' on {SAMPLE_CLIP.name}, {len(take)} frames"
        plot_take(out / MODES_NAME, take, frames, values, names, title)

    print(f"\nTracked {len(take)} frames, blob lost in {int(take.lost.sum())}. Run times:")
    print(steps.summary())
    print("\nWritten:")
    for name in (BLEND_NAME, PREVIEW_NAME, MODES_NAME):
        print(f"  {out / name}  ({file_size(out / name)})")


def main(argv=None) -> int:
    args = parse_args(argv)
    try:
        run(args)
    except (DemoError, OSError) as exc:
        print(f"demo: {exc}", file=sys.stderr)
        return 1
    finally:
        shutil.rmtree(SCRATCH, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
