"""Analyses of a scene or a plan that no planner needs to run: proven bounds and measures.

``regrasp_bound`` (the fewest regrasps any valid plan of a scene needs, proven on a
relaxation).
"""
