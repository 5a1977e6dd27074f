"""Takes (the tracked motion of a blob through a source) and rigs (a take laid on a mesh)."""
