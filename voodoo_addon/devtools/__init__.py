"""Development tools: synthetic takes with ground truth, the benchmark, baseline trackers.

Not part of the extension (its build excludes this folder): they read ``samples/`` of the
repository and exist to measure the engine, not to run it.
"""
