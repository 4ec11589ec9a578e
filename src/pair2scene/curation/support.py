"""Support extraction: which object (or the floor) each object rests on, from geometry alone.

For every object the candidates are the floor and the objects that can carry things
(:data:`SUPPORTER_CATEGORIES`) under it. A candidate qualifies when

* **horizontal containment**: the dependent's footprint centre lies over the
  candidate's footprint (in the candidate's own frame, grown by a small margin), or a
  large fraction of the dependent's footprint does; and
* **vertical proximity**: one of the candidate's support heights lies just below the
  dependent's bottom — at most :attr:`SupportConfig.max_gap_m` below it, at most
  :attr:`SupportConfig.penetration_m` above it (source meshes interpenetrate).

A candidate's support heights are its box top, and, for a dependent whose bottom lies
*inside* the candidate's box, the support surfaces of the candidate's asset
(:func:`pair2scene.assets.surfaces_of`): a book on a bookcase's second tier rests on
that tier, not on the floor. Tiered furniture (shelving units, TV stands, dressers...)
is fitted to the scene first (instance fitting): it is generated with tiers at the
bottoms of the objects resting inside its footprint. That uses only the scene's
geometry, never its annotations. When no surface matches, an object inside a
candidate's box is still carried by it (a spoon in a drawer), below any real surface.

The highest qualifying height wins: the nearest surface below. Objects hanging from a
towel rail or a toilet-paper holder are carried by it (the rails themselves are mounted
on walls). Parts (drawers, shelves, cabinet doors) belong to the smallest piece of
furniture containing them, objects an adapter built into another (``part_of``: a faucet
of a sink, pair2scene.data.fixtures) to that one, and anything resting on a part is
supported by the part's owner. Wall objects, rails and others that nothing carries get
``support = None`` from :func:`find_supports`; :func:`extract_support` then mounts those
touching a wall on it (``wall:<i>``, :func:`pair2scene.curation.wall_objects.mount_on_walls`).

:func:`support_scores` compares the result with the sources' own annotations
(AI2-THOR ``parentReceptacles``, ProcTHOR child nesting), resolved the way the
adapters resolve them (:func:`pair2scene.data.support.resolve_part_hosts`).
"""

from __future__ import annotations

from collections import Counter, OrderedDict
from dataclasses import dataclass, field, replace

import numpy as np

from pair2scene.assets.identity import asset_seed
from pair2scene.categories import SuperCategory
from pair2scene.scene.model import FLOOR, Scene, SceneObject

__all__ = [
    "BACKED_CATEGORIES",
    "HANGER_CATEGORIES",
    "INSET_CATEGORIES",
    "SUPPORTER_CATEGORIES",
    "SupportConfig",
    "SupportError",
    "SupportScores",
    "extract_support",
    "find_supports",
    "support_scores",
    "support_truth",
]

# Objects that carry other objects. AI2-THOR calls them receptacles
# (databases/receptacles.json plus its parts: Drawer, Cabinet, Shelf, SinkBasin,
# BathtubBasin); ProcTHOR nests children only under furniture. A book lying on
# another book is "on the table" in both sources, so small objects carry nothing
# except the few that are containers or trays.
SUPPORTER_CATEGORIES: frozenset[str] = frozenset(
    {
        # large furniture
        "bed", "sofa", "armchair", "chair", "stool", "ottoman", "dining_table",
        "coffee_table", "side_table", "desk", "dressing_table", "dresser", "wardrobe",
        "cabinet", "tv_stand", "shelving_unit", "garbage_can", "fridge", "laundry_hamper",
        "safe", "dog_bed", "cart",
        # fixtures
        "counter_top", "sink", "toilet", "bathtub", "stove", "towel_holder",
        "toilet_paper_hanger",
        # parts
        "drawer", "cabinet_door", "shelf", "sink_basin", "bathtub_basin",
        # small containers and trays
        "plate", "bowl", "pot", "pan", "box",
    }
)  # fmt: skip
"""Categories that can be a support anchor (besides the floor)."""

HANGER_CATEGORIES: frozenset[str] = frozenset({"towel_holder", "toilet_paper_hanger"})
"""Supporters that carry things hanging from them rather than resting on them. They are
mounted on walls: nothing supports them (``support = None``)."""

BACKED_CATEGORIES: frozenset[str] = frozenset({"chair", "armchair", "sofa", "bed", "toilet"})
"""Supporters whose box top is a backrest, headboard or cistern, not a place to put
things: only their asset's surfaces count (a plate at a table's edge over a tucked-in
chair's backrest rests on the table)."""

INSET_CATEGORIES: frozenset[str] = frozenset({"sink"})
"""Objects set into a cut-out of another (a drop-in sink in a counter): carried by their
rim where their top is level with the supporter's."""

PART_OWNER_SUPERS = frozenset(
    {SuperCategory.LARGE_FURNITURE, SuperCategory.FIXTURE, SuperCategory.UNKNOWN}
)
"""Super-categories that can own a part (a shelf belongs to furniture, never to a vase)."""


@dataclass(frozen=True)
class SupportConfig:
    """Named thresholds of support extraction (metres unless said otherwise)."""

    penetration_m: float = 0.05
    """A support height may lie this far *above* the dependent's bottom: AI2-THOR and
    ProcTHOR meshes interpenetrate by a few centimetres (the adapters' resting
    tolerance is the same 5 cm), while real tiers are at least ~15 cm apart."""
    max_gap_m: float = 0.12
    """... and at most this far below it. Stacks of things that carry nothing in the
    sources' sense (a book on two books on a desk, 10 cm up) still reach the desk; a
    painting 30 cm above a dresser does not."""
    wall_contact_m: float = 0.06
    """Wall objects (paintings, mirrors, curtains) need near contact: a mirror 10 cm
    above a sink hangs on the wall; curtains reaching within a few cm of the floor are
    annotated as standing on it (AI2-THOR)."""
    xy_margin_m: float = 0.02
    """A candidate's footprint is grown by this for the containment test: boxes of
    objects placed at a table's edge poke out by a centimetre or two."""
    min_overlap: float = 0.5
    """When the dependent's footprint centre is off the candidate, this fraction of its
    footprint (3x3 sample points of the bottom face) over it still counts: an
    overhanging laptop, a sink set into a counter."""
    inside_min_m: float = 0.005
    """A dependent counts as inside a floor-standing candidate (cabinet, lower shelf)
    only when its bottom is this far above the candidate's bottom: a chair pushed under
    a table shares the table's bottom (to a few mm) and stands on the floor, while a pan
    in a base cabinet rests on its bottom panel, ~1 cm up. Inside an elevated candidate
    (a sink, a wall cabinet) the dependent may rest at the box bottom."""
    tier_round_m: float = 0.01
    """Instance fitting: resting heights within a candidate are rounded to this and
    de-duplicated before tiers are built there (items on one tier differ by mm)."""
    min_tier_m: float = 0.05
    """... and heights lower than this above the candidate's bottom build no tier: the
    floor, or the bottom panel every cabinet already has, is there."""
    tilt_tol: float = 0.02
    """A candidate whose up axis deviates from world z by more than this (|1 - R_zz|)
    offers its box only: its asset surfaces would not be horizontal."""
    hang_margin_m: float = 0.03
    """A dependent hangs from a rail when its box, grown by this, overlaps the rail's."""
    part_host_margin_m: float = 0.03
    """A part belongs to furniture whose box, grown by this, contains the part's centre
    (the adapters use the same margin)."""
    use_asset_surfaces: bool = True
    """Look up the support surfaces of the candidates' assets for dependents inside
    their box. Off: box tops plus the inside fallback only (faster, less exact)."""


DEFAULT_CONFIG = SupportConfig()

_SURFACE_CACHE: OrderedDict[tuple, list[tuple[float, object]]] = OrderedDict()
_SURFACE_CACHE_ENTRIES = 4096
"""Assets' surfaces, by (category, size in mm, seed, tier heights in cm): the corpus
is curated more than once (scores, physics, the CLI) and repeats its furniture."""


@dataclass(frozen=True)
class SupportError:
    """One object whose predicted support differs from the source's."""

    scene_id: str
    object_id: str
    category: str
    predicted: str | None
    truth: str


@dataclass(frozen=True)
class SupportScores:
    precision: float
    recall: float
    f1: float
    n_true: int
    n_pred: int
    n_correct: int
    include_floor: bool = True
    """Whether edges to the floor are counted (the headline figure counts them)."""
    errors: tuple[SupportError, ...] = field(default=(), repr=False)
    """Every mismatch (missed or wrong), for per-category analysis."""

    def errors_by_category(self) -> Counter[str]:
        return Counter(e.category for e in self.errors)


# -- extraction -----------------------------------------------------------------------
def _box_arrays(objects: list[SceneObject]) -> tuple[np.ndarray, ...]:
    """centres (N, 3), half sizes (N, 3), rotations (N, 3, 3), bottoms (N,), tops (N,)."""
    c = np.array([o.box.center for o in objects]).reshape(-1, 3)
    h = np.array([o.box.half_size for o in objects]).reshape(-1, 3)
    r = np.array([o.box.rotation for o in objects]).reshape(-1, 3, 3)
    extent_z = np.einsum("nj,nj->n", np.abs(r[:, 2, :]), h)  # (N,) world z half extent
    return c, h, r, c[:, 2] - extent_z, c[:, 2] + extent_z


def _part_owners(
    objects: list[SceneObject], c: np.ndarray, h: np.ndarray, r: np.ndarray, margin: float
) -> dict[int, int]:
    """Part index -> index of the smallest furniture/fixture box containing its centre."""
    parts = [i for i, o in enumerate(objects) if o.super is SuperCategory.PART]
    hosts = np.array([o.super in PART_OWNER_SUPERS for o in objects])
    if not parts or not hosts.any():
        return {}
    local = np.einsum("hji,phj->phi", r, c[parts][:, None, :] - c[None, :, :])  # (P, N, 3)
    inside = np.all(np.abs(local) <= h[None] + margin, axis=-1) & hosts[None]  # (P, N)
    volume = np.prod(2 * h, axis=1)
    owners = {}
    for k, i in enumerate(parts):
        cand = np.flatnonzero(inside[k])
        if cand.size:
            owners[i] = int(cand[np.argmin(volume[cand])])
    return owners


def _resolve_owners(owners: dict[int, int]) -> dict[int, int]:
    """Owner chains followed to their end (a basin inside a faucet that is part of a
    sink belongs to the sink); a chain that loops leaves its parts unowned."""
    out = {}
    for i in owners:
        seen, k = {i}, owners[i]
        while k in owners and k not in seen:
            seen.add(k)
            k = owners[k]
        if k not in seen:
            out[i] = k
    return out


def _built_in_owners(objects: list[SceneObject]) -> dict[int, int]:
    """Index -> owner index for objects the adapters built into another (``part_of``:
    a faucet of a sink, a burner of a counter, a cabinet door of a counter run)."""
    index = {o.id: i for i, o in enumerate(objects)}
    return {
        i: index[o.part_of]
        for i, o in enumerate(objects)
        if o.part_of is not None and o.part_of in index and o.part_of != o.id
    }


def _surfaces(
    obj: SceneObject, seed: int, heights: tuple[float, ...] | None, library
) -> list[tuple[float, object]]:
    """(z above the box bottom, SupportSurface) of the object's asset, cached."""
    from pair2scene.assets.registry import generate, generators
    from pair2scene.assets.surfaces import surfaces_of

    size = obj.box.size
    gen = generators().get(obj.category)
    fitted = heights is not None and gen is not None and gen.fits_support_heights
    key = (
        obj.category,
        tuple(np.round(size * 1000).astype(int)),
        seed,
        heights if fitted else None,
    )
    found = _SURFACE_CACHE.get(key)
    if found is not None:
        _SURFACE_CACHE.move_to_end(key)
        return found
    if fitted:
        asset = generate(obj.category, size, rng=seed, support_heights=heights)
    else:
        asset = library.retrieve(obj.category, size, rng=seed)
    found = [(float(s.z + size[2] / 2), s) for s in surfaces_of(asset)]
    _SURFACE_CACHE[key] = found
    while len(_SURFACE_CACHE) > _SURFACE_CACHE_ENTRIES:
        _SURFACE_CACHE.popitem(last=False)
    return found


def find_supports(
    scene: Scene, library=None, config: SupportConfig = DEFAULT_CONFIG
) -> dict[str, str | None]:
    """Object id -> ``floor``, the supporting object's id, or None, from geometry alone.

    Structure objects are skipped (absent from the result). Never reads ``support``
    or ``source_support``. See the module docstring for the method.
    """
    objects = [o for o in scene.objects if o.super is not SuperCategory.STRUCTURE]
    n = len(objects)
    if n == 0:
        return {}
    cfg = config
    c, h, r, bottom, top = _box_arrays(objects)
    cats = [o.category for o in objects]
    is_part = np.array([o.super is SuperCategory.PART for o in objects])
    is_wall = np.array([o.super is SuperCategory.WALL_OBJECT for o in objects])
    is_small = np.array([o.super is SuperCategory.SMALL_OBJECT for o in objects])
    can_support = np.array([k in SUPPORTER_CATEGORIES for k in cats])
    is_hanger = np.array([k in HANGER_CATEGORIES for k in cats])
    is_backed = np.array([k in BACKED_CATEGORIES for k in cats])
    is_inset = np.array([k in INSET_CATEGORIES for k in cats])
    owners = _part_owners(objects, c, h, r, cfg.part_host_margin_m)
    owners = _resolve_owners({**owners, **_built_in_owners(objects)})
    not_self = ~np.eye(n, dtype=bool)

    # -- horizontal containment ------------------------------------------------------
    # Footprint samples of each dependent: a 3x3 grid on its box's bottom face.
    g = np.array([-0.5, 0.0, 0.5])
    grid = np.stack(np.meshgrid(g, g, indexing="ij"), -1).reshape(-1, 2)  # (9, 2), centre 4
    offs = np.concatenate([grid, np.full((9, 1), -1.0)], 1)  # (9, 3) in half sizes
    samples = c[:, None, :] + np.einsum("nij,nkj->nki", r, offs[None] * h[:, None, :])
    # Samples of dependent i in candidate j's frame: (N_i, N_j, 9, 3).
    local = np.einsum("jmk,ijsm->ijsk", r, samples[:, None] - c[None, :, None, :])
    over = np.all(np.abs(local[..., :2]) <= h[None, :, None, :2] + cfg.xy_margin_m, -1)
    base_local = local[:, :, 4, :]  # (N_i, N_j, 3) the dependent's bottom centre
    # The candidate's centre under the dependent's footprint: a pot on a small burner.
    rev = np.einsum("imk,ijm->ijk", r, c[None, :, :] - c[:, None, :])  # (N_i, N_j, 3)
    under = np.all(np.abs(rev[..., :2]) <= h[:, None, :2], -1)
    loose = (over.mean(-1) >= cfg.min_overlap) | under
    # Trays and containers carry what lies over their middle, not what merely touches
    # them: a pencil beside a pot lies on the table.
    contained = over[:, :, 4] | (loose & ~is_small[None, :])  # (N_i, N_j)
    pair_ok = contained & can_support[None, :] & not_self
    for p, o in owners.items():  # a part never carries its own owner
        pair_ok[o, p] = False

    # -- vertical proximity ----------------------------------------------------------
    max_gap = np.where(is_wall, cfg.wall_contact_m, cfg.max_gap_m)  # (N_i,)
    gap_top = bottom[:, None] - top[None, :]  # (N_i, N_j)
    near_top = pair_ok & (gap_top >= -cfg.penetration_m) & (gap_top <= max_gap[:, None])
    # real[i, j]: the height of a surface of j that i rests on (-inf: none).
    real = np.where(near_top & ~is_backed[None, :], top[None, :], -np.inf)
    elevated = bottom > max_gap  # (N_j,) a candidate not standing on the floor
    low_enough = np.where(
        elevated[None, :],
        bottom[:, None] >= bottom[None, :] - cfg.penetration_m,
        bottom[:, None] > bottom[None, :] + cfg.inside_min_m,
    )
    within = pair_ok & (gap_top < -cfg.penetration_m) & low_enough
    base_in = within & np.all(np.abs(base_local[..., :2]) <= h[None, :, :2] + cfg.xy_margin_m, -1)

    # Asset surfaces: for dependents inside a candidate's box (a seat under the armrests,
    # a side table's lower shelf).
    # Only where it can change the answer: a dependent with a single candidate gets it
    # whether or not a surface matches (the box fallback below), so the asset (~10-40 ms)
    # is built only for dependents with rival candidates.
    upright = np.abs(1.0 - r[:, 2, 2]) <= cfg.tilt_tol
    rivals = np.count_nonzero(near_top | base_in, axis=1) >= 2  # (N_i,)
    ask = within & upright[None, :] & rivals[:, None]
    if cfg.use_asset_surfaces and ask.any():
        from pair2scene.assets import AssetLibrary
        from pair2scene.assets.registry import generators

        library = library if library is not None else AssetLibrary()
        fitted_categories = {k for k, g in generators().items() if g.fits_support_heights}
        for j in np.flatnonzero(ask.any(0)):
            if cats[j] in fitted_categories:
                # Instance fitting builds a tier at every resting height inside the box
                # (above min_tier_m), so each such dependent rests on its own tier; the
                # asset need not be built to know it.
                deps = within[:, j] & (bottom > bottom[j] + cfg.min_tier_m) & base_in[:, j]
                real[deps, j] = np.maximum(real[deps, j], bottom[deps])
                continue
            rest = np.flatnonzero(
                ~is_part & (np.arange(n) != j)
                & np.all(np.abs(base_local[:, j, :2]) <= h[j, :2], -1)
                & (bottom > bottom[j] + cfg.min_tier_m)
                & (bottom < top[j] - cfg.penetration_m)
            )  # fmt: skip
            tiers = np.unique(np.round((bottom[rest] - bottom[j]) / cfg.tier_round_m))
            heights = tuple(float(t * cfg.tier_round_m) for t in tiers)
            surfs = _surfaces(objects[j], asset_seed(objects[j].id), heights, library)
            zs = bottom[j] + np.array([z for z, _ in surfs]).reshape(-1)  # (S,) world
            for i in np.flatnonzero(ask[:, j]):
                rel = bottom[i] - zs
                ok = (rel >= -cfg.penetration_m) & (rel <= max_gap[i])
                for k in np.flatnonzero(ok)[::-1]:  # highest first
                    if surfs[k][1].contains(base_local[i, j, :2])[0]:
                        real[i, j] = max(real[i, j], zs[k])
                        break

    # A small object hanging from a rail: their boxes meet and it reaches above the
    # rail's bottom; ranked at the rail's top, above whatever is under the towel.
    reach = np.abs(rev) <= h[None] + h[:, None] + cfg.hang_margin_m  # (N_i, N_j, 3)
    hangs = (
        is_hanger[None, :] & is_small[:, None] & not_self & np.all(reach, -1)
        & (top[:, None] >= bottom[None, :]) & (bottom[:, None] < bottom[None, :])
    )  # fmt: skip
    real = np.where(hangs, np.maximum(real, top[None, :]), real)
    # A sink set into a counter hangs by its rim: tops level, sink over the counter.
    inset = (
        is_inset[:, None] & pair_ok & ~is_inset[None, :]
        & (np.abs(top[:, None] - top[None, :]) <= cfg.penetration_m)
        & (bottom[:, None] < top[None, :] - cfg.penetration_m)
    )  # fmt: skip
    real = np.where(inset, np.maximum(real, top[None, :]), real)
    # ... and its supporter has a hole there: what lies over the sink is in the sink.
    # Fixtures (a faucet) are mounted on the counter's deck behind the basin.
    is_fixture = np.array([o.super is SuperCategory.FIXTURE for o in objects])
    for k, j in zip(*np.nonzero(inset), strict=True):
        real[over[:, k, 4] & np.isfinite(real[:, k]) & ~is_fixture, j] = -np.inf

    # Inside a candidate's box with no surface of it matched: the box carries it. Of
    # several, the one whose top is nearest above. It beats a real surface only when
    # that surface is at the container's bottom or lower (the container stands on it).
    # Seating's box top (a backrest, a headboard) counts the same way when no surface
    # of its asset matched: a pillow at the head of a bed, a roll on a cistern.
    box_in = (base_in | (near_top & is_backed[None, :])) & ~np.isfinite(real)
    fall_key = np.where(box_in, top[None, :] - bottom[:, None], np.inf)

    best = np.argmax(real, axis=1)  # (N_i,)
    best_h = real[np.arange(n), best]
    fall = np.argmin(fall_key, axis=1)
    has_fall = np.isfinite(fall_key[np.arange(n), fall])
    out: dict[str, str | None] = {}
    for i, o in enumerate(objects):
        if i in owners:
            out[o.id] = objects[owners[i]].id
            continue
        if is_hanger[i]:
            out[o.id] = None  # mounted on a wall, whatever stands below it
            continue
        j = None
        if has_fall[i] and best_h[i] <= bottom[fall[i]] + cfg.penetration_m:
            j = int(fall[i])
        elif np.isfinite(best_h[i]):
            j = int(best[i])
        if j is not None:
            out[o.id] = objects[owners.get(j, j)].id
        elif bottom[i] <= max_gap[i]:
            out[o.id] = FLOOR
        else:
            out[o.id] = None
    return out


def extract_support(scene: Scene, library=None, config: SupportConfig = DEFAULT_CONFIG) -> Scene:
    """A copy of ``scene`` whose objects' ``support`` is found from geometry alone
    (``source_support`` is left as the source gave it; structure objects keep theirs), and
    objects nothing carries that touch a wall mounted on it (``wall:<i>``, their box
    turned to have its back against it: :func:`~pair2scene.curation.wall_objects.mount_on_walls`).

    library : an :class:`~pair2scene.assets.AssetLibrary` for the candidates' support
    surfaces (default: the procedural one).
    """
    from pair2scene.curation.wall_objects import mount_on_walls

    found = find_supports(scene, library, config)
    objects = [replace(o, support=found[o.id]) if o.id in found else o for o in scene.objects]
    return mount_on_walls(replace(scene, objects=objects))


# -- evaluation -----------------------------------------------------------------------
def support_truth(scene: Scene) -> dict[str, str]:
    """Object id -> the source's support, parts resolved to their owner as the adapters
    do, for every object the source annotated (``source_support`` not None)."""
    from pair2scene.data.support import resolve_part_hosts

    resolved = resolve_part_hosts(scene.objects)
    ids = {o.id for o in scene.objects}
    return {
        # an object the adapter built into another (a faucet of a sink) belongs to it
        a.id: a.part_of if a.super is not SuperCategory.PART and a.part_of in ids else b.support
        for a, b in zip(scene.objects, resolved, strict=True)
        if a.source_support is not None and b.support is not None
    }


def support_scores(scenes: list[Scene], include_floor: bool = True) -> SupportScores:
    """Precision/recall/F1 of ``support`` against the sources' own annotation.

    Counted over the objects the source annotated. An edge is (object, support);
    include_floor counts edges to the floor too (the headline figure does); without
    them, only object-on-object edges are scored. A prediction of None is no edge.
    """
    n_true = n_pred = n_correct = 0
    errors = []
    for scene in scenes:
        truth = support_truth(scene)
        pred = {o.id: o.support for o in scene.objects}
        for oid, t in truth.items():
            p = pred.get(oid)
            t_counts = include_floor or t != FLOOR
            p_counts = p is not None and (include_floor or p != FLOOR)
            n_true += t_counts
            n_pred += p_counts
            hit = t_counts and p_counts and p == t
            n_correct += hit
            if (t_counts or p_counts) and not hit:
                cat = scene.get(oid).category
                errors.append(SupportError(scene.id, oid, cat, p, t))
    precision = n_correct / n_pred if n_pred else 0.0
    recall = n_correct / n_true if n_true else 0.0
    f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
    return SupportScores(
        precision, recall, f1, n_true, n_pred, n_correct, include_floor, tuple(errors)
    )
