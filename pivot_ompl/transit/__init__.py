"""The robot walking alone round the resting box (transit): the regrasping roadmap's walks.

``planner`` (:class:`~pivot_ompl.transit.planner.WalkPlanner`: lazy A* over the state lattice
of ``lattice``, guided by the floor distances and lattice costs of ``field`` that ``guides``
keeps per query, then smoothed).
"""
