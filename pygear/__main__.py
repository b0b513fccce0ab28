"""``python -m pygear``: the same command line as ``pygear``."""

import sys

from .cli import main

sys.exit(main())
