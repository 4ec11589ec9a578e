"""The procedural generators, one per canonical category, and ``generate``.

A generator builds convex parts inside the box [-size/2, size/2] (local frame:
+z up, +y front, +x right, centred on the box). ``generate`` then maps the
parts' bounds exactly onto that box, so every asset fills the box it was asked
for whatever small overshoot a generator leaves.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from pair2scene.assets.mesh import Asset, Mesh, Part, box
from pair2scene.categories import BY_NAME, UNKNOWN
from pair2scene.errors import UserError

MIN_SIZE_M = 1e-3
"""Smallest extent an asset is built with along any axis (a credit card's thickness)."""

GeneratorFn = Callable[
    [np.ndarray, np.random.Generator, int, "Sequence[float] | None"], "list[Part]"
]
"""fn(size (3,), rng, style, support_heights) -> convex parts inside [-size/2, size/2].

support_heights: heights above the box bottom (metres, in [0, size z]) at which
the dataset object supports other objects; generators that model tiers put
their upward surfaces there (instance fitting); others ignore it.
"""


@dataclass(frozen=True)
class Generator:
    category: str
    fn: GeneratorFn
    variants: int
    """Number of style variants; ``style`` runs over range(variants)."""
    description: str
    fits_support_heights: bool = False
    solid: GeneratorFn | None = None
    """The same category as one solid piece, where ``fn`` may build it open (a counter
    as a block, not an L or a C of runs): ``generate(..., solid=True)``."""


REGISTRY: dict[str, Generator] = {}

BUILT_CACHE_ENTRIES = 2048
"""Assets :func:`generate` keeps, by (category, size, seed, style, support heights):
more than the asset library holds (1,569 assets) and a scene of the largest size, so a
long run keeps every library asset it met (with 1,024 the library's assets were built
over and over) and rebuilding a scene (a resumed run, a kept object, curtains cut to a
window tried twice) reuses its assets and everything computed from them (support
surfaces, point clouds); ~40 kB an asset, 80 MB at most."""
_BUILT: OrderedDict[tuple, Asset] = OrderedDict()


def register(
    *categories: str,
    variants: int,
    description: str = "",
    fits_support_heights: bool = False,
    solid: GeneratorFn | None = None,
) -> Callable[[GeneratorFn], GeneratorFn]:
    """Decorator: register ``fn`` as the generator of ``categories`` (``solid``: its
    one-piece form, :attr:`Generator.solid`)."""

    def deco(fn: GeneratorFn) -> GeneratorFn:
        for cat in categories:
            if cat not in BY_NAME:
                raise ValueError(f"register: {cat!r} is not a canonical category")
            if cat in REGISTRY:
                raise ValueError(f"register: {cat!r} already has a generator")
            doc = description or (fn.__doc__ or "").strip().splitlines()[0]
            REGISTRY[cat] = Generator(cat, fn, variants, doc, fits_support_heights, solid)
        return fn

    return deco


def _load_generators() -> None:
    import pair2scene.assets.generators  # noqa: F401  (registers on import)


def generators() -> dict[str, Generator]:
    _load_generators()
    return REGISTRY


def fit_to_box(parts: Sequence[Part], size: np.ndarray) -> list[Part]:
    """Map the parts' joint bounds exactly onto [-size/2, size/2] (per-axis affine)."""
    lo, hi = Mesh.concat([p.mesh for p in parts]).bounds
    extent = np.maximum(hi - lo, 1e-12)
    scale = size / extent
    center = (lo + hi) / 2
    out = []
    for p in parts:
        v = (p.mesh.vertices - center) * scale
        out.append(Part(p.name, Mesh(v, p.mesh.faces)))
    return out


def fallback_box(category: str, size: np.ndarray) -> Asset:
    """The labelled box for a category with no generator."""
    return Asset(category, size, (Part("box", box((0, 0, 0), size)),), style=0, source="box")


def generate(
    category: str,
    size: Sequence[float],
    rng: np.random.Generator | int | None = None,
    style: int | None = None,
    support_heights: Sequence[float] | None = None,
    solid: bool = False,
) -> Asset:
    """A procedural asset of ``category`` filling a box of ``size`` (3,) metres.

    rng : a numpy Generator or a seed; draws the style (when not given) and the
    generator's own variation. Same seed, same asset; an integer seed is kept in
    ``asset.extra["seed"]`` (scene.json records it to rebuild the asset exactly).
    Unknown categories (and ``unknown``) get a labelled box (``asset.source == "box"``).
    ``solid``: the category's one-piece form where it has one (:attr:`Generator.solid`:
    curation's physics check stands a source's objects on a counter whose shape, a
    straight run, an L, a C or an island, the box does not tell).
    """
    size = np.maximum(np.asarray(size, dtype=float).reshape(3), MIN_SIZE_M)
    if not np.all(np.isfinite(size)):
        raise UserError(f"asset size must be finite, got {size.tolist()}")
    key = None
    if isinstance(rng, (int, np.integer)):  # a seed: same key, same asset (assets are frozen)
        key = (category, size.tobytes(), int(rng), style,
               None if support_heights is None else tuple(map(float, support_heights)),
               solid)  # fmt: skip
        hit = _BUILT.get(key)
        if hit is not None:
            _BUILT.move_to_end(key)
            return hit
    asset = _build(category, size, rng, style, support_heights, solid)
    if key is not None:
        _BUILT[key] = asset
        if len(_BUILT) > BUILT_CACHE_ENTRIES:
            _BUILT.popitem(last=False)
    return asset


def _build(category, size, rng, style, support_heights, solid=False) -> Asset:
    gen = generators().get(category)
    if gen is None:
        if category != UNKNOWN and category not in BY_NAME:
            raise UserError(f"unknown category {category!r}")
        return fallback_box(category, size)
    extra = {"seed": int(rng)} if isinstance(rng, (int, np.integer)) else {}
    rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    if style is None:
        style = int(rng.integers(gen.variants))
    elif not 0 <= style < gen.variants:
        raise UserError(f"{category}: style {style} out of range 0..{gen.variants - 1}")
    heights = None
    if support_heights is not None and gen.fits_support_heights:
        heights = sorted(float(np.clip(h, 0.0, size[2])) for h in support_heights)
    fn = gen.solid if solid and gen.solid is not None else gen.fn
    parts = fn(size.copy(), rng, style, heights)
    if not parts:
        raise RuntimeError(f"generator for {category!r} returned no parts")
    return Asset(category, size, tuple(fit_to_box(parts, size)), style=style, extra=extra)
