"""Pivoting kinematics: the three-rotation inverse, Reeds-Shepp curves, the steering method.

``kinematics`` (rotations about the supporting edge's ends, the closed-form 3R inverse),
``reeds_shepp`` and ``dubins`` (OMPL's curves; Dubins for the robot's forward walks),
``steering`` (a Reeds-Shepp path turned into bounded pivot rotations) and ``transfer`` (pivot
sequences written as plan phases).
"""
