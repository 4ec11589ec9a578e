"""Spreading small objects over the supports that have room for them.

A hierarchy is drawn before any size is known, so it can pile a dozen objects onto a small
dresser while the desk beside it stays bare. Rejection sampling on a crowded surface then
burns its candidates: on the bundled bedrooms, objects on supports filled past 40 % of
their area took 8.4 resamples each, those below 20 % took 0.1-0.2.

:func:`balance_supports` walks each support's dependents largest first and, once their
footprints fill :attr:`BalanceRules.max_load` of the support's surface area (its largest
dependent always stays, whatever its footprint), moves the rest
to another object of the scene that the curated statistics say carries that category
(a remote control from a full dresser to the side table), the one with the most free
area; an object no support has room for is reported as overflow (placement drops it with
that reason). Objects resting on a moved object move with it; a moved object loses its
functional anchor (which stays on the old support).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from pair2scene.assembly.records import Dropped, Moved
from pair2scene.assets.mesh import Asset
from pair2scene.assets.surfaces import surfaces_of
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.model import FLOOR


@dataclass(frozen=True)
class BalanceRules:
    max_load: float
    """Share of a support's surface area its dependents' footprints may cover: random
    placement of boxes jams well before full packing (~0.5 for similar rectangles). No
    default here: placement passes :attr:`~pair2scene.assembly.place.AssemblyConfig.max_load`
    (the one default, with its measurements)."""


def surface_area(asset: Asset) -> float:
    """m^2 of upward surface an asset offers (every tier of a shelf counts)."""
    return float(sum(s.area for s in surfaces_of(asset) if s.clearance > 0.02))


def balance_supports(
    hierarchy: Hierarchy,
    assets: dict[str, Asset],
    sup_dep: dict[str, dict[str, int]],
    rules: BalanceRules,
    fixed: frozenset[str] | set[str] = frozenset(),
) -> tuple[Hierarchy, list[Moved], list[Dropped]]:
    """The hierarchy with overflowing objects moved; the moves; the overflow (objects no
    support has room for).
    ``fixed`` objects (kept by the user) never move and always count."""
    category = {n.id: n.category for n in hierarchy.nodes}
    area = _Areas({oid: a for oid, a in assets.items() if oid in category})
    load = dict.fromkeys(area.ids, 0.0)
    support = dict(hierarchy.support)
    functional = dict(hierarchy.functional)
    moves: list[Moved] = []
    overflow: list[Dropped] = []

    def footprint(oid: str) -> float:
        size = assets[oid].size
        return float(size[0] * size[1])

    order = [item.dependent.id for item in hierarchy.sequence()]
    rank = {oid: i for i, oid in enumerate(order)}
    by_support: dict[str, list[str]] = {}
    for oid in order:
        if support[oid] != FLOOR:
            by_support.setdefault(support[oid], []).append(oid)
    for sup in [s for s in order if s in by_support]:
        for oid in sorted(by_support[sup], key=lambda o: (-footprint(o), rank[o])):
            f = footprint(oid)
            # The first (largest) always stays: the load bounds clutter, and a television
            # whose box (screen and foot) covers most of its stand is what the stand is for.
            fits = load[sup] == 0 or load[sup] + f <= rules.max_load * area[sup]
            if fits or oid in fixed or _is_own_dependent(functional, oid):
                load[sup] += f
                continue
            target = _free_support(oid, f, category, support, sup_dep, area, load, rules)
            if target is None:
                overflow.append(Dropped(oid, category[oid], f"no free surface: {sup} is full"))
                continue
            support[oid] = target
            functional.pop(oid, None)
            for other, anchor in list(functional.items()):
                if anchor == oid:  # its functional dependents stay where they are
                    del functional[other]
            load[target] += f
            moves.append(Moved(oid, sup, target))
    balanced = replace(hierarchy, support=support, functional=functional,
                       notes=list(hierarchy.notes))  # fmt: skip
    return balanced, moves, overflow


class _Areas:
    """object id -> :func:`surface_area` of its asset, computed when first asked: most
    objects (a book, a mug) are never asked, and their surfaces cost more than the rest of
    the balance."""

    def __init__(self, assets: dict[str, Asset]) -> None:
        self._assets = assets
        self._known: dict[str, float] = {}
        self.ids = sorted(assets)
        """Every object id, sorted."""

    def __getitem__(self, oid: str) -> float:
        if oid not in self._known:
            self._known[oid] = surface_area(self._assets[oid])
        return self._known[oid]


def _is_own_dependent(functional: dict[str, str], oid: str) -> bool:
    """Objects others are placed relative to (a plate with a fork beside it) stay."""
    return oid in functional.values()


def _free_support(oid, f, category, support, sup_dep, area, load, rules) -> str | None:
    """The scene's object with the most free area that carries ``oid``'s category in the
    statistics, is not ``oid`` nor rests on it, and has room for ``f`` m^2."""
    below = {oid}
    changed = True
    while changed:  # oid's own subtree: never a support for it
        new = {o for o, s in support.items() if s in below} - below
        changed = bool(new)
        below |= new
    best, best_free = None, 0.0
    for cand in area.ids:
        if cand in below or sup_dep.get(category[cand], {}).get(category[oid], 0) <= 0:
            continue
        free = rules.max_load * area[cand] - load[cand]
        if free >= f and free > best_free:
            best, best_free = cand, free
    return best
