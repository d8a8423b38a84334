"""The mathematics under every layer: numbers and exact parsing (:mod:`.numbers`), the number
fields every derivation runs on -- float, exact rational, symbolic, mpmath (:mod:`.fields`) --
and the type of their elements (:mod:`.scalar`), first-order jets (:mod:`.jet`), exact and
pivoted elimination (:mod:`.elimination`), 3-D rotations and the cross-product algebra
(:mod:`.spatial`, :mod:`.rotations_snap`) and the joint configurations a state is made of
(:mod:`.configuration`).

Nothing here knows a scene, a model or a file format: what the typed signatures need of a scene
or a spanning tree is a :class:`typing.Protocol` declared here (``JointDeclarations``,
``JointTree``).
"""
