"""Pivoting kinematics: the three-rotation inverse, Reeds-Shepp curves, the steering method.

``kinematics`` (rotations about the supporting edge's ends, the closed-form 3R inverse),
``reeds_shepp`` (OMPL's curves), ``steering`` (a Reeds-Shepp path turned into bounded pivot
rotations) and ``transfer`` (pivot sequences written as plan phases).
"""
