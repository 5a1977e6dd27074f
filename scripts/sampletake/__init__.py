"""The sample take's scene (``scene``) and its ground truth and outline (``truth``).

``make_sample.py`` is the command line; ``scripts/`` must be on ``sys.path`` (it is when a script
there runs), as these modules import its shared helpers.
"""
