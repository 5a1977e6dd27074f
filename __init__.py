# SPDX-License-Identifier: GPL-3.0-or-later
"""Active Voodoo Dolls: animate a character by squeezing a real object in front of a camera.

The extension's entry point only hands off to the Blender layer (``operators``); the engine
(``voodoo_addon``) is plain Python and never imports Blender.
"""


def register():
    from . import operators

    operators.register()


def unregister():
    from . import operators

    operators.unregister()
