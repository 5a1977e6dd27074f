"""The hard test clips of ``render_hard_clips.py``, one module per concern.

``scene``
    Frame size, seeds, the ``Clip`` description and ``new_scene`` (render settings, camera,
    world, backdrop).
``materials``
    Lamps and the sheet's materials.
``sheet``
    The painted sheet (a grid mesh with a back and rim) and its bend deformers.
``scenarios``
    One ``build_*`` function per clip and ``CLIPS``, the list of clips.
``truth``
    The ground-truth lattice, its visibility and the frame-0 region outline.
``video``
    Rendering, the camera post (exposure, white balance, sensor noise) and H.264 encoding.
``make``
    One clip's files, and the folder's README.
``heldout``, ``multi``, ``folds``, ``heldout_folds`` to ``heldout_folds8``
    The held-out clips, the clips of several dolls in one take, the clips of folds and the
    eight batches of held-out clips of folds (``heldout_folds``, ``heldout_folds2``,
    ``heldout_folds3``, ``heldout_folds4``, ``heldout_folds5``, ``heldout_folds6``,
    ``heldout_folds7``, ``heldout_folds8``; each group made only when named).

Importing the package pins the process to one CPU core: Cycles' thread pool sizes itself from
the CPUs the process may use, so this has to happen before bpy starts it (import ``hardclips``
before bpy), or a second worker spins on the other core while the first renders. ``scripts/``
must be on ``sys.path`` (it is when a script there runs).
"""

import os

os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})
