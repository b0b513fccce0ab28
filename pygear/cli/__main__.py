"""``python -m pygear.cli``: the same command line as ``pygear``."""

import sys

from .parser import main

sys.exit(main())
