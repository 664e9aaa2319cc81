"""The OMPL adapters, mirroring ``ompl.base``: state, space, validators and the problem object.

``state`` (reading/writing the compound state), ``space`` (Reeds-Shepp SE(2) x grasp index),
``validity_checker`` and ``motion_validator`` (OMPL's interfaces over the pure-Python
``PivotChecker``), ``problem`` (``PivotProblem``/``make_setup``: everything OMPL needs for one
scene, owned together) and ``path_conversion`` (an OMPL path written as a plan).
"""
