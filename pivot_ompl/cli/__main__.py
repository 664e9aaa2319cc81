"""``python -m pivot_ompl.cli <verb> ...``."""

import sys

from pivot_ompl.cli.main import main

sys.exit(main())
