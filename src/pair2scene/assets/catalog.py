"""The asset catalogue behind ``pair2scene assets list``: per asset category its
generator (if any), style variants and typical size."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from pair2scene.assets.typical_sizes import asset_categories, typical_size
from pair2scene.errors import UserError

__all__ = ["AssetEntry", "asset_catalog", "parse_categories"]


@dataclass(frozen=True)
class AssetEntry:
    """What ``pair2scene assets list`` shows for one category."""

    category: str
    super_category: str
    module: str | None
    """Python module of the generator; None when the category falls back to a box."""
    variants: int
    fits_support_heights: bool
    typical_size: tuple[float, float, float]
    size_source: str
    box_fallback: bool

    def to_dict(self) -> dict:
        return {
            "category": self.category,
            "super_category": self.super_category,
            "module": self.module,
            "variants": self.variants,
            "fits_support_heights": self.fits_support_heights,
            "typical_size": list(self.typical_size),
            "size_source": self.size_source,
            "box_fallback": self.box_fallback,
        }


def parse_categories(spec: str | Sequence[str] | None) -> list[str]:
    """Asset categories from a comma-separated string or a list (None: all of them).
    Unknown names and room features raise a UserError naming them."""
    if spec is None:
        return asset_categories()
    names = [s.strip() for s in spec.split(",")] if isinstance(spec, str) else list(spec)
    names = [n for n in names if n]
    if not names:
        raise UserError("no categories given")
    allowed = set(asset_categories())
    bad = [n for n in names if n not in allowed]
    if bad:
        raise UserError(f"not an asset category: {', '.join(bad)} (see 'pair2scene assets list')")
    return list(dict.fromkeys(names))


def asset_catalog(categories: str | Sequence[str] | None = None) -> list[AssetEntry]:
    """One entry per asset category: its generator (if any) and typical size."""
    from pair2scene.assets.registry import generators
    from pair2scene.categories import super_category

    gens = generators()
    out = []
    for name in parse_categories(categories):
        gen = gens.get(name)
        ts = typical_size(name)
        out.append(
            AssetEntry(
                category=name,
                super_category=super_category(name).value,
                module=gen.fn.__module__ if gen else None,
                variants=gen.variants if gen else 1,
                fits_support_heights=bool(gen and gen.fits_support_heights),
                typical_size=ts.size,
                size_source=ts.source,
                box_fallback=gen is None,
            )
        )
    return out
