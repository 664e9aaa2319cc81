"""The motion checker: states, transfer edges (pivot sequences) and transit walks, cached.

``pivot_checker`` (:class:`~pivot_ompl.checking.pivot_checker.PivotChecker`): what the OMPL
validators and our planners ask, so that every edge is converted and checked once.
"""
