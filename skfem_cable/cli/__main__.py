"""``python -m skfem_cable.cli``."""

import sys

from .command import main

sys.exit(main())
