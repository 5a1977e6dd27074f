"""Track the sample take and bend a card with it: Blender headless, from a script.

Run from any folder: ``.venv/bin/python examples/track_and_apply.py [OUT.blend]``
(default ``out/example.blend`` in the checkout). tests/blender/test_readme.py runs it, and
checks that the README shows this file as it is.
"""

import json
import os
import sys
import tempfile
from pathlib import Path

os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp()  # keep your own settings untouched
import bpy

ROOT = Path(__file__).resolve().parents[1]  # the checkout
sys.path.insert(0, str(ROOT / "scripts"))
from blender_addon import enable_from_checkout

enable_from_checkout()  # inside Blender, the installed extension is already enabled

bpy.ops.wm.read_homefile(use_empty=True)
scene = bpy.context.scene
scene.active_clip = bpy.data.movieclips.load(str(ROOT / "samples" / "sample_take.mp4"))
bpy.ops.voodoo.capture_frame()  # frame 0 of the clip
points = json.loads((ROOT / "samples" / "sample_take.json").read_text())["points"]
bpy.ops.voodoo.sketch_contour(coords=", ".join(f"{x} {y}" for x, y in points))
bpy.ops.voodoo.build_blob(name="Doll")
print([m.name for m in scene.voodoo.modes])  # bend-x, shear, stretch-x, ...

bpy.ops.mesh.primitive_grid_add(x_subdivisions=20, y_subdivisions=20, rotation=(1.5708, 0, 0))
scene.voodoo.target = bpy.context.active_object  # a flat card in the XZ plane...
scene.voodoo.axes = "XY"  # ...whose own mesh lies in its XY plane
bpy.ops.voodoo.select_modes(preset="BENDING")  # bending only, no rotation or translation
bpy.ops.voodoo.track_clip(max_frames=60)  # tracks and applies, as action "Take"
bpy.ops.voodoo.smooth_take(cutoff=4.0)

out = Path(sys.argv[1] if len(sys.argv) > 1 else ROOT / "out" / "example.blend").resolve()
out.parent.mkdir(parents=True, exist_ok=True)
bpy.ops.wm.save_as_mainfile(filepath=str(out))
print(f"saved {out}")
