"""Built-in example pairs (the gallery), run by ``isotween demo NAME``.

The data files in ``examples/data/`` are made by ``scripts/build_examples.py``
from data that pip packages ship (DejaVu glyph outlines and a sample image of
matplotlib); ``data/index.json`` lists the examples in order, the first being
the default demo.
"""

import json
from functools import lru_cache
from pathlib import Path

from ..errors import ParameterError

__all__ = ["names", "describe", "load_example", "example_options", "interpolate_example", "example_paint"]

DATA = Path(__file__).with_name("data")


@lru_cache(maxsize=1)
def _index():
    with open(DATA / "index.json", encoding="utf-8") as f:
        return {entry["name"]: entry for entry in json.load(f)["examples"]}


def _entry(name):
    index = _index()
    if name not in index:
        raise ParameterError(f"unknown example '{name}'; available: {', '.join(index)}")
    return index[name]


def names():
    """Names of the built-in examples, the default demo first (list of str).

    Examples
    --------
    >>> from isotween.examples import names
    >>> names()[0], "bar" in names()
    ('worm', True)
    """
    return list(_index())


def describe(name):
    """One line saying what the example shows (str).

    Examples
    --------
    >>> from isotween.examples import describe
    >>> isinstance(describe("bar"), str)
    True
    """
    return _entry(name)["description"]


def example_paint(name):
    """Colours an example is drawn in: keyword arguments of `isotween.outputs.with_paint` (dict, maybe empty)."""
    return dict(_entry(name).get("paint", {}))


def load_example(name):
    """The source and target shapes of an example and how to interpolate them.

    Outline examples stored with different point counts are made compatible
    here by `isotween.resample` (their ``resample`` entry is the point count),
    drawings with different regions and holes by `isotween.correspond` (their
    ``correspond`` entry holds its keyword arguments).

    Parameters
    ----------
    name : str
        One of `names`.

    Returns
    -------
    source, target : Shape
        Compatible shapes.
    options : dict
        Keyword arguments of `isotween.interpolate` (``frames``, ...) and,
        for textured examples, ``texture``: the path of the image (str).

    Examples
    --------
    >>> import isotween
    >>> from isotween.examples import load_example
    >>> source, target, options = load_example("bar")
    >>> isotween.check_compatible(source, target)  # ready for interpolate
    >>> source.n_vertices == target.n_vertices
    True
    """
    from ..correspondence import correspond, resample
    from ..io import load

    entry = _entry(name)
    source, target = load(DATA / entry["source"]), load(DATA / entry["target"])
    if entry.get("resample"):
        source, target = resample(source, target, points=entry["resample"])
    if "correspond" in entry:
        source, target, _ = correspond(source, target, **entry["correspond"])
    return source, target, example_options(name)


def example_options(name):
    """An example's keyword arguments of `isotween.interpolate` (``frames``, ...) and its ``texture`` path, if any."""
    entry = _entry(name)
    options = dict(entry.get("options", {}))
    if entry.get("texture"):
        options["texture"] = str(DATA / entry["texture"])
    return options


def interpolate_example(name, **options):
    """An example's in-between sequence, made as `isotween.morph` makes one for two drawings.

    Examples with a ``correspond`` entry go through the whole pipeline
    (`isotween.pipeline.morph`): correspondence, the fold fallback, and their
    ends made the input drawings exactly (pieces that vanish collapsed,
    holes opened into notches closed again), which `load_example`'s
    compatible shapes alone do not give; the others are interpolated as
    `load_example` gives them.

    Parameters
    ----------
    name : str
        One of `names`.
    **options
        Keyword arguments of `isotween.interpolate` (``callback``, ...);
        the example's own (``frames``, ...) are used unless given.

    Returns
    -------
    Sequence
    """
    from ..interpolate import interpolate
    from ..io import load

    entry = _entry(name)
    options = {**entry.get("options", {}), **options}
    options.pop("texture", None)
    if "correspond" in entry:
        from ..pipeline import morph

        return morph(load(DATA / entry["source"]), load(DATA / entry["target"]), correspondence="always",
                     correspond_options=entry["correspond"], fold="fallback", **options)
    source, target, _ = load_example(name)
    return interpolate(source, target, **options)
