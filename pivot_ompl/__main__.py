"""``python -m pivot_ompl VERB ...``: the same command line as ``pivot-ompl``."""

import sys

from pivot_ompl.cli.main import main

sys.exit(main())
