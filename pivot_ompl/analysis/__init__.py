"""Analyses of a scene or a plan that no planner needs to run: proven bounds and measures.

``regrasp_bound`` (the fewest regrasps any valid plan of a scene needs, proven on a
relaxation), ``raster_bound`` (the same relaxation on raster cells, fast on real floors) and
``bound_levels`` (the two coarse to fine, as exact as the answer needs).
"""
