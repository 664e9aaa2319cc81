"""The object roadmap (box poses alone) and the samplers that grow it.

``roadmap`` (:class:`~.roadmap.Roadmap`: poses, nearest neighbours, components; the box's
half-turn symmetry), ``visibility`` (the one Visibility PRM, on any configurations),
``critical`` (critical configurations found along its edges), ``slots`` (box-only passages
read from the scene's geometry), ``bridge`` (the bridge test for narrow passages) and
``diffusion`` (random targets and extensions towards them).
"""
