"""``python -m voodoo_addon``: the command line (see :mod:`voodoo_addon.cli`)."""

import sys

from .cli import main

sys.exit(main())
