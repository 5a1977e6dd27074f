"""The panels: the Clip Editor's (source to take) and the 3D Viewport's (target and modes)."""

from . import clip_panels, doll_list, mode_list, target_panel

classes = mode_list.classes + doll_list.classes + clip_panels.classes + target_panel.classes
