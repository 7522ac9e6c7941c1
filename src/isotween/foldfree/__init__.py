"""Fold-free morphs: what the pipeline uses where AIAP's in-betweens fold.

- `repair`: the folding frames of a sequence moved as little as no flipped
  triangle allows (the first resort of ``interpolate(..., fold='fallback')``);
- `injective` (method ``'injective'``): every component completed to a disc,
  each frame an embedding made as isometric as it allows (barrier energy);
- `convex` (method ``'convex'``): the disc's convex-combination morph
  (Floater and Gotsman 1999), the start of 'injective' and its last resort.

``'convex'`` and ``'injective'`` are run as methods through
`isotween.baselines.run`, like the methods the paper compares with.
"""
