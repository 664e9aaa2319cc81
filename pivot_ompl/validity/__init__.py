"""What is valid, in pure Python (no OMPL): collisions, certified sweeps, walks, plan checks.

``collision`` (coal world of the scene), ``certify`` (a swept motion proved free from
clearances), ``walking`` (the robot's transit walks round the resting box: A* over the state
lattice of ``walk_lattice`` guided by the floor distances of ``walk_field``), ``pivot_checker``
(states, transfer edges and walks, cached: what the OMPL validators and our planners ask) and
``plan_check`` (an independent check of a ``pivot-plan/1`` file against its scene).
"""
