"""Routes of the held assembly: its state lattice, and the plan's phases re-routed on it.

``lattice`` (:class:`~.lattice.TransferLattice`: pushes, pulls and turns in place, A* in
seconds) and ``refine`` (:func:`~.refine.refine_phases`: each transfer phase along the
lattice's cheapest route, shortened by certified transfers, where that is cheaper).
"""
