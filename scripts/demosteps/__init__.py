"""The steps of ``demo.py``, the whole job on the bundled sample take, one module per stage.

``report``
    Numbered progress lines with run times, operator calls that raise ``DemoError``.
``doll``
    Blender with the add-on enabled, the sample clip loaded, the blob "Doll" built on frame 0.
``stage``
    The two characters, the tracked take applied to them, a camera framing their motion, a
    light and the Workbench render settings; the saved .blend.
``preview``
    The characters rendered per frame and the preview video beside the clip.

``demo.py`` sets ``BLENDER_USER_RESOURCES`` before bpy is first imported, so import these only
from there (or after doing the same). ``scripts/`` must be on ``sys.path``.
"""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SAMPLE_CLIP = ROOT / "samples" / "sample_take.mp4"
SAMPLE_OUTLINE = ROOT / "samples" / "sample_take.json"
