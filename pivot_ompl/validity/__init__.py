"""What is valid, in pure Python (no OMPL, not even indirectly): collisions, sweeps, plan checks.

``collision`` (coal world of the scene), ``certify`` (a swept motion proved free from
clearances), ``footprints`` (the bodies' floor footprints on the obstacles, in numpy and
shapely) and ``plan_check`` (an independent check of a ``pivot-plan/1`` file against its
scene).
"""
