"""Roadmap multiplexing (the regrasp paper, Section IV): the graph and its lazy search.

``edges`` (nodes ``(object node, grasp)``, search states with their half-turn frame parity,
transfer and regrasp edges), ``graph`` (:class:`~.graph.MultiplexedGraph`: the manipulation
nodes and candidate edges, the cheap test of transfers), ``reach``
(:class:`~.reach.ReachableSet`: the states a search may reach) and ``search``
(:class:`~.search.PathSearch`: lazy weighted A* over it, then the full checks of the path
found, searching again while one fails).
"""
