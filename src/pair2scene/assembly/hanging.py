"""Cloth hung on a holder: a towel folded over a towel rail, or through a towel ring.

A towel on a towel holder rests on no level surface: it hangs folded over a bar. In the
AI2-THOR bathrooms all 24 hand towels and 15 bath towels on a holder hang so, the top of
the towel 3 cm above the bar's centre, centred on it along the wall (0.02 of the
holder's half width on average). Placement used to ask the holder for a surface to rest
them on, found none and dropped every one (31 towels in 30 bathrooms, 72 holders left
bare).

Here the towel is hung by rule, as curtains are at a window: its asset is the draped
form of its category (an upright thin box: the fold on top, a front and a back layer
below it with a gap between, :func:`~pair2scene.assets.generators.household.towel`), as
wide as the holder's free span allows and thick enough that the bar fits between the
layers; it is centred on the bar along the wall and over it in depth, and lowered until
its fold sits on the bar (on a ring, on the inside of the ring's lower half). A towel
that would touch the holder anywhere else by more than the contact tolerance does not
hang there; the next bar is tried (a ladder's rails, a double rail's back one). One that
would reach into what stands under the holder is shortened to clear it
(:func:`clear_length`). Hung, it is fixed as its holder is in every physics of the
package (:func:`hung_on_holder`): a rigid stand-in of a cloth balanced on a round bar
slides off where the cloth stays.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pair2scene.assembly.collision import MeshWorld, Shape, Tolerances
from pair2scene.assets.mesh import Asset, Part
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import SceneObject

HANGERS = frozenset({"towel_holder"})
"""Categories cloth hangs on."""
CLOTHS = frozenset({"hand_towel", "towel"})
"""Categories that hang on a holder (in their draped form)."""
FOLD = "fold"
"""The part of a draped cloth that lies over the bar."""
LAYER_GAP_SHARE = 0.2
"""A draped cloth of depth d leaves about 0.22 d on each side of its middle between its
layers; a bar of radius r fits between them when d is at least (r + 1 mm) / this."""
SPAN_SHARE = 0.9
"""A cloth is at most this share of its bar's free span wide."""
RING_SPAN = 0.75
"""A ring's free span is this share of its inside width: a fold as wide as the ring
would rest on its sides, halfway up, and touch them above."""
STEP_M = 0.001
"""Step of the lowering that finds where the fold meets the bar."""


@dataclass(frozen=True)
class Bar:
    """Where cloth hangs on a holder, in the holder's local frame (metres)."""

    parts: tuple[Part, ...]
    """The parts the fold comes to rest on (a rail; the lower half of a ring)."""
    span: tuple[float, float]
    """Free stretch along x (between the arms that hold a rail; inside a ring)."""
    y: float
    """Depth of the bar's axis."""
    top: float
    """Height above which the fold starts to come down onto the bar."""
    radius: float
    """Half the bar's thickness in depth."""
    reach: float
    """How far below ``top`` the bar's parts go (the lowering stops there)."""

    @property
    def width(self) -> float:
        return self.span[1] - self.span[0]


def bars(holder: Asset) -> list[Bar]:
    """The bars of ``holder`` a cloth may hang on, best first: rails from the top down (a
    double rail's two at once, then the front one, then the back one); a ring's lower
    half. Empty when the holder has no rail or ring (a user mesh, a box fallback)."""
    out = []
    rails = [p for p in holder.parts if p.name.startswith("rail")]
    others = [p for p in holder.parts if not p.name.startswith(("rail", "ring"))]
    for rail in sorted(rails, key=lambda p: (-p.mesh.bounds[1][2], -p.mesh.bounds[1][1])):
        lo, hi = rail.mesh.bounds
        x0, x1 = float(lo[0]), float(hi[0])
        for p in others:  # arms, posts and plates at the rail's height bound its span
            plo, phi = p.mesh.bounds
            if phi[2] < lo[2] or plo[2] > hi[2]:
                continue
            if (plo[0] + phi[0]) / 2 < (x0 + x1) / 2:
                x0 = max(x0, float(phi[0]))
            else:
                x1 = min(x1, float(plo[0]))
        if x1 > x0:
            y, r = float(lo[1] + hi[1]) / 2, float(hi[1] - lo[1]) / 2
            out.append(Bar((rail,), (x0, x1), y, float(hi[2]), r, float(hi[2] - lo[2])))
    # a double rail (two at one height, one behind the other): over both at once, first
    for k, bar in enumerate(list(out)):
        pair = [b for b in out if b is not bar and abs(b.top - bar.top) < bar.radius]
        if pair and bar.y > pair[0].y:
            back = pair[0]
            y0, y1 = back.y - back.radius, bar.y + bar.radius
            span = (max(bar.span[0], back.span[0]), min(bar.span[1], back.span[1]))
            both = Bar(bar.parts + back.parts, span, (y0 + y1) / 2, bar.top, (y1 - y0) / 2,
                       max(bar.reach, back.reach))  # fmt: skip
            out.insert(k, both)
            break
    ring = [p for p in holder.parts if p.name.startswith("ring")]
    if ring:
        lo = np.min([p.mesh.bounds[0] for p in ring], axis=0)
        hi = np.max([p.mesh.bounds[1] for p in ring], axis=0)
        mid = (lo + hi) / 2
        r = float(hi[1] - lo[1]) / 2
        lower = tuple(p for p in ring if p.mesh.vertices[:, 2].mean() < mid[2])
        half = RING_SPAN * (float(hi[0] - lo[0]) / 2 - 2 * r)
        inner = (float(mid[0]) - half, float(mid[0]) + half)
        if lower and inner[1] > inner[0]:
            out.append(Bar(lower, inner, float(mid[1]), float(mid[2]), r, float(mid[2] - lo[2])))
    return out


def hung_size(size: np.ndarray, holder: Asset) -> np.ndarray | None:
    """``size`` (3,) made a cloth's draped form that hangs on ``holder``'s first bar: at
    most :data:`SPAN_SHARE` of the bar's free span wide, deep enough for the bar to pass
    between its layers, taller than twice its depth (what makes the generators drape
    it); None when the holder has no bar."""
    found = bars(holder)
    if not found:
        return None
    bar = found[0]
    w, d0, h = (float(v) for v in size)
    w = min(w, SPAN_SHARE * bar.width)
    d = max(min(d0, h), (bar.radius + 0.001) / LAYER_GAP_SHARE)  # a folded one's thickness
    return np.array([w, d, max(h, d0, 2.5 * d)])  # its length hangs down


def hang(cloth: Asset, holder: Asset, holder_box: OrientedBox,
         tolerances: Tolerances | None = None) -> OrientedBox | None:  # fmt: skip
    """The pose (world box of ``cloth``) at which the draped ``cloth`` hangs on
    ``holder`` standing at ``holder_box``: on the first of :func:`bars` where its fold
    comes to rest on the bar and nothing else of it meets the holder beyond the contact
    tolerance; None where it hangs on none (too wide, not draped, no bar)."""
    tol = tolerances or Tolerances()
    folds = [p for p in cloth.parts if p.name == FOLD]
    if not folds:
        return None
    fold_bottom = float(folds[0].mesh.bounds[0][2])
    world = MeshWorld(tol)
    fold = Shape(Asset(cloth.category, cloth.size, tuple(folds)))
    whole, frame = Shape(cloth), Shape(holder)
    half_w = cloth.size[0] / 2
    for bar in bars(holder):
        if 2 * half_w > bar.width:
            continue
        rest = Shape(Asset(holder.category, holder.size, bar.parts))
        x = (bar.span[0] + bar.span[1]) / 2
        z = bar.top + STEP_M - fold_bottom  # the fold's bottom just above the bar
        fold.set_pose(np.eye(3), np.array([x, bar.y, z]))
        if world.penetration(fold, rest) > 0.0:
            continue  # the fold does not fit inside (a ring too narrow for it)
        for _ in range(int(np.ceil((bar.reach + 2 * bar.radius) / STEP_M)) + 1):
            fold.set_pose(np.eye(3), np.array([x, bar.y, z - STEP_M]))
            if world.penetration(fold, rest) > 0.0:
                break
            z -= STEP_M
        else:
            continue  # passed the bar by: nothing to hang on
        whole.set_pose(np.eye(3), np.array([x, bar.y, z]))
        if world.penetration(whole, frame) > world.touch_between(whole, frame):
            continue
        local = np.array([x, bar.y, z])
        center = holder_box.center + holder_box.rotation @ local
        return OrientedBox(center, cloth.size.copy(), holder_box.rotation.copy())
    return None


def hangs_on(category: str, holder: Asset) -> bool:
    """Whether an object of ``category`` resting on ``holder`` hangs on it by rule (a
    towel on a towel holder with a rail or a ring)."""
    return category in CLOTHS and holder.category in HANGERS and bool(bars(holder))


def draped(sizes: np.ndarray) -> np.ndarray:
    """(K,) whether each size (K, 3) is a cloth's draped form (upright, thin: taller than
    twice its depth), as the training rooms' towels on holders were: the sizes a towel
    to hang is drawn from."""
    sizes = np.asarray(sizes, dtype=float)
    return sizes[:, 2] > 2.0 * sizes[:, 1]


CLEAR_BELOW_M = 0.03
"""Gap a hanging towel keeps above what stands under it (a vanity, a cistern)."""


def clear_length(box: OrientedBox, others: list[OrientedBox]) -> float | None:
    """The longest a cloth hung at ``box`` may be to end :data:`CLEAR_BELOW_M` above the
    highest of ``others`` whose footprint meets its own and whose top is below the
    cloth's top, or None when none is under it or what is under it stands below the
    cloth's bottom already."""
    from pair2scene.scene.relations import footprint, footprint_gap

    mine = footprint(box)
    tops = [o.top for o in others if o.top < box.top and footprint_gap(mine, footprint(o)) <= 0.0]
    if not tops or max(tops) + CLEAR_BELOW_M <= box.bottom + 1e-6:
        return None
    return box.top - max(tops) - CLEAR_BELOW_M


def hung_on_holder(obj: SceneObject, by_id: dict[str, SceneObject]) -> bool:
    """Whether ``obj`` is a cloth resting on a towel holder (``by_id``: the scene's
    objects): it hangs there, and physics fixes it as it fixes the holder (a rigid towel
    balanced on a round bar would slide off where a cloth one stays)."""
    holder = by_id.get(obj.support if obj.support is not None else obj.source_support or "")
    return obj.category in CLOTHS and holder is not None and holder.category in HANGERS


def hang_clear(
    cloth: Asset,
    holder: Asset,
    holder_box: OrientedBox,
    under: list[OrientedBox],
    tolerances: Tolerances | None = None,
) -> tuple[Asset, OrientedBox | None]:
    """(the cloth, where it hangs: :func:`hang`), the cloth rebuilt shorter from its own
    seed when it would reach into one of ``under`` (:func:`clear_length`; a vanity or a
    cistern under the holder) and still drapes so; None for the pose where it hangs on
    no bar of ``holder``."""
    from pair2scene.assets.registry import generate

    box = hang(cloth, holder, holder_box, tolerances)
    short = None if box is None else clear_length(box, under)
    if short is not None and draped(np.array([[*cloth.size[:2], short]]))[0]:
        size = np.array([*cloth.size[:2], short])
        cloth = generate(cloth.category, size, cloth.extra.get("seed", 0))
        box = hang(cloth, holder, holder_box, tolerances)
    return cloth, box
