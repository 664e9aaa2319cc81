"""HRP-2's constants under their former module name.

The profile lives in :mod:`pivot_ompl.humanoids.hrp2`; this module is kept so that code
importing ``pivot_ompl.hrp2`` still runs.
"""

from pivot_ompl.humanoids.hrp2 import *  # noqa: F403
from pivot_ompl.humanoids.hrp2 import __all__  # noqa: F401
