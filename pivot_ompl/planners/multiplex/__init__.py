"""Roadmap multiplexing (the regrasp paper, Section IV): the graph and its lazy search.

``graph`` (:class:`~.graph.MultiplexedGraph`: manipulation nodes ``(object node, grasp)``,
transfer and regrasp edges, the half-turn frame parity, the reachable set) and ``search``
(:class:`~.search.PathSearch`: lazy weighted A* over it, then the full checks of the path
found, searching again while one fails).
"""
