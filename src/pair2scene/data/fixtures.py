"""Kitchens and bathrooms as people build them: counters as cabinet runs, fixture parts
folded into their fixtures. Shared by the AI2-THOR and ProcTHOR adapters.

**Counters.** AI2-THOR stores a counter as a thin ``CounterTop`` slab (1-3 cm) over
cabinet doors and drawers (``Cabinet``/``Drawer`` parts). A slab is turned into one or
more *cabinet runs*: boxes from the floor to the slab's top whose tops carry what rested
on the slab. A slab whose shorter side is at most :data:`SINGLE_RUN_MAX_DEPTH_M` is one
run (a straight counter, an island). A larger slab is an L or U around the room's corner
(its box would fill the kitchen): it is cut into strips along its edges where cabinets,
appliances or objects on it show a counter, each strip as deep as those reach; unless
something rests on the slab outside every strip (then the slab is one solid block). Each run's
long side is its local x and its front (+y) faces the room's centre. Cabinet doors and
drawers under a run become its parts (``part_of``, ``support``); objects on the slab rest
on the run under them. ProcTHOR's counters are already whole bodies (0.94 m): untouched.

**Fixture parts** (:data:`FIXTURE_PARTS`): faucets, stove burners and knobs, shower heads,
curtains and screens are parts of the fixture they are built into (``part_of``), never
loose objects; one with no fixture to belong to is dropped and counted. Towel holders and
toilet-paper hangers are mounted on walls: kept (towels hang on them) with no support.
Shower doors and glass standing on the floor away from a bathtub are the shower itself.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pair2scene.data.base import SourceReport
from pair2scene.scene.geometry import OrientedBox, yaw_to_matrix
from pair2scene.scene.model import FLOOR, SceneObject

SLAB_MAX_HEIGHT_M = 0.1
"""A counter top thinner than this ..."""
SLAB_MIN_BOTTOM_M = 0.4
"""... whose bottom is at least this high is a slab over cabinets."""
SINGLE_RUN_MAX_DEPTH_M = 1.2
"""A slab whose shorter side is at most this is one run (straight counter or island)."""
EDGE_BAND_M = 0.3
"""Evidence whose near side lies within this of a slab edge belongs to that edge's strip."""
RUN_DEPTH_M = (0.5, 1.0)
"""A strip's depth is what its evidence reaches, clipped to this range."""
MIN_RUN_LENGTH_M = 0.3
"""Shorter strips are not runs (a stray object near an edge)."""
MIN_AISLE_M = 0.8
"""Two runs facing each other across less than this are one block (no one stands there)."""
RUN_END_SNAP_M = 0.35
"""A strip whose evidence ends this close to the slab's end runs to it."""
UNDER_RUN_MARGIN_M = 0.05
"""A cabinet door or drawer whose centre is within this of a run's footprint is its part."""
BASE_UNITS = frozenset({"cabinet_door", "drawer"})
"""Parts under a counter that a run absorbs."""
EVIDENCE_CATEGORIES = BASE_UNITS | {"sink", "sink_basin", "stove", "stove_knob", "faucet"}
"""Objects under or in a slab that show where its run is."""

FIXTURE_PARTS: dict[str, tuple[str, ...]] = {
    "Faucet": ("sink", "bathtub", "counter_top"),
    "StoveBurner": ("counter_top",),
    "StoveKnob": ("counter_top",),
    "ShowerHead": ("bathtub", "shower"),
    "ShowerCurtain": ("bathtub",),
    "ShowerDoor": ("bathtub",),
    "ShowerGlass": ("bathtub",),
}
"""Source label -> the fixture categories it can be part of, in order of preference."""
STANDALONE_SHOWER = frozenset({"ShowerDoor", "ShowerGlass"})
"""Labels kept as a ``shower`` of their own when standing on the floor with no bathtub."""
WALL_MOUNTED = frozenset({"towel_holder", "toilet_paper_hanger"})
"""Categories mounted on a wall: no support (they still carry towels and rolls)."""
PART_REACH_M = 0.25
"""A fixture part belongs to a fixture whose footprint, grown by this, holds its centre..."""
PART_ABOVE_M = 0.6
"""... and whose top is at most this far below the part's bottom (a faucet on a sink's
deck; a shower head is measured against the tub's footprint only)."""
ON_FLOOR_M = 0.1
RANGE_PARTS = frozenset({"StoveBurner", "StoveKnob"})
RANGE_GROUP_M = 0.3
"""Burners this close (xy) belong to one range."""
RANGE_MARGIN_M = 0.05
RANGE_MIN_SIZE_M = 0.55
"""A range's body: its burners' bounds grown by the margin, at least this wide and deep."""


def is_slab(o: SceneObject) -> bool:
    """A counter top that is only a slab over cabinets (AI2-THOR)."""
    return (
        o.category == "counter_top"
        and o.box.size[2] < SLAB_MAX_HEIGHT_M
        and o.box.bottom > SLAB_MIN_BOTTOM_M
    )


def _local_rect(box: OrientedBox, slab: OrientedBox) -> tuple[np.ndarray, np.ndarray]:
    """xy bounds (lo, hi) of ``box``'s corners in ``slab``'s frame."""
    pts = slab.to_local(box.corners())[:, :2]
    return pts.min(0), pts.max(0)


def _strips(
    half: np.ndarray, rects: list[tuple[np.ndarray, np.ndarray]]
) -> list[tuple[np.ndarray, np.ndarray]]:
    """Runs of an L/U slab (half sizes ``half``) from evidence rectangles (slab frame)."""
    strips = []
    for axis in (0, 1):
        along = 1 - axis
        for sign in (-1.0, 1.0):
            edge = sign * half[axis]
            near = [
                (lo, hi)
                for lo, hi in rects
                if min(abs(edge - lo[axis]), abs(edge - hi[axis])) <= EDGE_BAND_M
            ]
            if not near:
                continue
            reach = max(max(abs(edge - lo[axis]), abs(edge - hi[axis])) for lo, hi in near)
            depth = float(np.clip(reach, *RUN_DEPTH_M))
            a0 = min(lo[along] for lo, _ in near)
            a1 = max(hi[along] for _, hi in near)
            if a0 - (-half[along]) <= RUN_END_SNAP_M:
                a0 = -half[along]
            if half[along] - a1 <= RUN_END_SNAP_M:
                a1 = half[along]
            if a1 - a0 < MIN_RUN_LENGTH_M:
                continue
            lo, hi = np.zeros(2), np.zeros(2)
            lo[along], hi[along] = a0, a1
            lo[axis], hi[axis] = (edge, edge + depth) if sign < 0 else (edge - depth, edge)
            strips.append((lo, hi))
    # Longest first; later strips give up the corners the earlier ones hold.
    strips.sort(key=lambda s: -float(np.max(s[1] - s[0])))
    kept: list[tuple[np.ndarray, np.ndarray]] = []
    for lo, hi in strips:
        lo, hi = lo.copy(), hi.copy()
        along = int(np.argmax(hi - lo))
        for klo, khi in kept:
            if np.all(np.minimum(hi, khi) - np.maximum(lo, klo) > 1e-6):
                if (klo[along] + khi[along]) / 2 < (lo[along] + hi[along]) / 2:
                    lo[along] = max(lo[along], khi[along])
                else:
                    hi[along] = min(hi[along], klo[along])
        if hi[along] - lo[along] >= MIN_RUN_LENGTH_M:
            kept.append((lo, hi))
    return kept


def _inside(p: np.ndarray, rect: tuple[np.ndarray, np.ndarray], margin: float) -> bool:
    return bool(np.all((p >= rect[0] - margin) & (p <= rect[1] + margin)))


def _island(
    half: np.ndarray,
    rects: list[tuple[np.ndarray, np.ndarray]],
    runs: list[tuple[np.ndarray, np.ndarray]],
) -> tuple[np.ndarray, np.ndarray] | None:
    """A run for the evidence no edge run holds (an island within the slab's bounds):
    its bounds, at least RUN_DEPTH_M[0] each way, cut back where it meets the edge runs."""
    loose = [r for r in rects if not any(_inside((r[0] + r[1]) / 2, k, 0.0) for k in runs)]
    if not loose:
        return None
    lo = np.min([r[0] for r in loose], axis=0)
    hi = np.max([r[1] for r in loose], axis=0)
    mid, ext = (lo + hi) / 2, np.maximum(hi - lo, RUN_DEPTH_M[0])
    lo, hi = np.maximum(mid - ext / 2, -half), np.minimum(mid + ext / 2, half)
    for klo, khi in runs:
        if not np.all(np.minimum(hi, khi) - np.maximum(lo, klo) > 1e-6):
            continue
        cuts = []  # the four ways to leave the run, keeping the largest remainder
        for a in (0, 1):
            for new_lo, new_hi in ((lo.copy(), hi.copy()), (lo.copy(), hi.copy())):
                cuts.append((new_lo, new_hi))
            cuts[-2][0][a] = max(lo[a], khi[a])
            cuts[-1][1][a] = min(hi[a], klo[a])
        lo, hi = max(cuts, key=lambda c: float(np.prod(np.maximum(c[1] - c[0], 0.0))))
    if np.any(hi - lo < MIN_RUN_LENGTH_M):
        return None
    return lo, hi


def _narrow_aisle(runs: list[tuple[np.ndarray, np.ndarray]]) -> bool:
    """Whether two runs face each other across a gap narrower than MIN_AISLE_M."""
    for i, (alo, ahi) in enumerate(runs):
        for blo, bhi in runs[i + 1 :]:
            for axis in (0, 1):
                other = 1 - axis
                shared = min(ahi[other], bhi[other]) - max(alo[other], blo[other])
                gap = max(blo[axis] - ahi[axis], alo[axis] - bhi[axis])
                facing = axis == np.argmin(ahi - alo) == np.argmin(bhi - blo)
                if facing and shared > MIN_RUN_LENGTH_M and 0 < gap < MIN_AISLE_M:
                    return True
    return False


def _run_box(
    slab: OrientedBox, lo: np.ndarray, hi: np.ndarray, room_center: np.ndarray
) -> OrientedBox:
    """A run from the floor to the slab's top over slab-frame rectangle [lo, hi], its long
    side along its local x and its front (+y) toward ``room_center`` (xy)."""
    centre = slab.to_world(np.array([[(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, 0.0]]))[0]
    top = slab.top
    ext = hi - lo
    yaw0 = slab.yaw if ext[0] >= ext[1] else slab.yaw + np.pi / 2
    size = np.array([max(ext), min(ext), top])
    front = np.array([-np.sin(yaw0), np.cos(yaw0)])
    if float(np.dot(room_center - centre[:2], front)) < 0:
        yaw0 += np.pi
    yaw = float(np.arctan2(np.sin(yaw0), np.cos(yaw0)))
    return OrientedBox(np.array([centre[0], centre[1], top / 2]), size, yaw_to_matrix(yaw))


def counter_runs(
    objects: list[SceneObject], room_center: np.ndarray, report: SourceReport
) -> list[SceneObject]:
    """Counter-top slabs -> cabinet runs from the floor (see the module docstring)."""
    slabs = [o for o in objects if is_slab(o)]
    if not slabs:
        return objects
    redirect: dict[str, list[SceneObject]] = {}
    for slab in slabs:
        sb = slab.box
        half = sb.half_size[:2]
        rects = []
        for o in objects:
            on_slab = o.support == slab.id or o.source_support == slab.id
            if not on_slab and not (
                o.category in EVIDENCE_CATEGORIES
                and o.box.bottom < sb.top
                and o.box.top < sb.top + 0.15
            ):
                continue
            if o.category in BASE_UNITS and o.box.bottom > sb.bottom - 0.1:
                continue  # a wall cabinet's door level with the top, not under it
            c = sb.to_local(o.box.center[None])[0, :2]
            if np.any(np.abs(c) > half + UNDER_RUN_MARGIN_M):
                continue
            lo, hi = _local_rect(o.box, sb)
            rects.append((np.maximum(lo, -half), np.minimum(hi, half)))
        if min(sb.size[0], sb.size[1]) <= SINGLE_RUN_MAX_DEPTH_M or not rects:
            if min(sb.size[0], sb.size[1]) > SINGLE_RUN_MAX_DEPTH_M:
                report.warnings["large counter slab with nothing under it: one run"] += 1
            runs = [(-half, half)]
        else:
            runs = _strips(half, rects)
            if not runs:
                report.warnings["large counter slab with no run along its edges: one run"] += 1
                runs = [(-half, half)]
            elif _narrow_aisle(runs):
                # runs facing each other across a gap no one can stand in: one solid block
                report.warnings["large counter slab, no aisle between its runs: one run"] += 1
                runs = [(-half, half)]
            else:
                report.warnings["counter slab cut into runs along its edges"] += 1
                island = _island(half, rects, runs)
                if island is not None:
                    report.warnings["counter slab: an island run inside its edge runs"] += 1
                    runs.append(island)
        made = []
        for k, (lo, hi) in enumerate(runs):
            rid = slab.id if k == 0 else f"{slab.id}_run{k}"
            box = _run_box(sb, lo, hi, room_center)
            # support: it stands on the floor; source_support stays what the source said
            made.append(replace(slab, id=rid, box=box, support=FLOOR))
        report.warnings["counter slab made a cabinet run from the floor"] += len(made)
        redirect[slab.id] = made

    def nearest_run(slab_id: str, point: np.ndarray) -> SceneObject:
        """The run of a slab nearest ``point`` (by how far it lies outside each)."""
        runs = redirect[slab_id]
        outside = [
            float(np.max(np.abs(r.box.to_local(point[None])[0, :2]) - r.box.half_size[:2]))
            for r in runs
        ]
        return runs[int(np.argmin(outside))]

    runs_all = [r for made in redirect.values() for r in made]
    out: list[SceneObject] = []
    for o in objects:
        if o.id in redirect:
            out.extend(redirect[o.id])
            continue
        if o.category in BASE_UNITS:
            host = _host_run(o, runs_all)
            if host is not None:
                report.warnings["cabinet part under a counter: part of its run"] += 1
                o = replace(o, part_of=host.id, support=host.id)
                out.append(o)
                continue
        for field in ("support", "source_support", "part_of"):
            ref = getattr(o, field)
            if ref in redirect:
                o = replace(o, **{field: nearest_run(ref, o.box.center).id})
        out.append(o)
    return out


def _host_run(o: SceneObject, runs: list[SceneObject]) -> SceneObject | None:
    """The run whose box (grown a little) holds ``o``'s centre, if any."""
    for r in runs:
        if r.box.contains(o.box.center, margin=UNDER_RUN_MARGIN_M)[0]:
            return r
    return None


def _fixture_for(o: SceneObject, hosts: list[SceneObject], kinds: tuple[str, ...]):
    """The fixture of a kind in ``kinds`` (in that order of preference) ``o`` is built
    into: its footprint, grown by PART_REACH_M, holds ``o``'s centre, and its top is not
    far below ``o``'s bottom (shower parts: the footprint alone)."""
    shower_part = (o.source_label or "").startswith("Shower")
    # After the first kind, the fixture the source has it on comes first (a faucet on a
    # counter beside a bathtub), then the other kinds in order.
    annotated = next((h for h in hosts if h.id in (o.support, o.source_support)), None)
    order = list(kinds[:1])
    if annotated is not None and annotated.category in kinds[1:]:
        order.append(annotated.category)
    order += [k for k in kinds[1:] if k not in order]
    for kind in order:
        best, best_d = None, np.inf
        for h in hosts:
            if h.category != kind or h.id == o.id:
                continue
            local = h.box.to_local(o.box.center[None])[0]
            over = np.all(np.abs(local[:2]) <= h.box.half_size[:2] + PART_REACH_M)
            if not over:
                continue
            gap = o.box.bottom - h.box.top
            if not shower_part and not (-h.box.size[2] - 0.05 <= gap <= PART_ABOVE_M):
                continue
            d = float(np.linalg.norm(local[:2]))
            if d < best_d:
                best, best_d = h, d
        if best is not None:
            return best
    return None


def fold_fixture_parts(
    objects: list[SceneObject], room_center: np.ndarray, report: SourceReport
) -> list[SceneObject]:
    """Fixture parts become parts of their fixtures (or are dropped); wall-mounted
    holders lose any support. Counted in ``report.warnings``."""
    hosts = [o for o in objects if o.category in ("sink", "bathtub", "counter_top", "shower")]
    hosts = [o for o in hosts if o.source_label not in FIXTURE_PARTS]
    owner: dict[str, str] = {}
    dropped: set[str] = set()
    for o in objects:
        kinds = FIXTURE_PARTS.get(o.source_label or "")
        if kinds is None:
            continue
        host = _fixture_for(o, hosts, kinds)
        if host is not None:
            owner[o.id] = host.id
            report.warnings[f"{o.source_label}: part of its {host.category}"] += 1
        elif o.source_label in RANGE_PARTS:
            dropped.add(o.id)  # until _ranges gives it a stove to belong to
        elif o.source_label in STANDALONE_SHOWER and o.box.bottom < ON_FLOOR_M:
            report.warnings[f"{o.source_label}: a shower standing on the floor (kept)"] += 1
        elif o.source_label == "ShowerHead":
            # A head over a stand-alone shower screen belongs to it.
            screens = [
                s
                for s in objects
                if s.source_label in STANDALONE_SHOWER and s.box.bottom < ON_FLOOR_M
            ]
            host = _fixture_for(o, screens, ("shower",))
            if host is not None:
                owner[o.id] = host.id
                report.warnings["ShowerHead: part of its shower"] += 1
            else:
                dropped.add(o.id)
                report.warnings["ShowerHead: no fixture to belong to (dropped)"] += 1
        else:
            dropped.add(o.id)
            report.warnings[f"{o.source_label}: no fixture to belong to (dropped)"] += 1
    objects, _ = _ranges(objects, dropped, owner, room_center, report)
    out = []
    for o in objects:
        if o.id in dropped:
            continue
        if o.id in owner:
            o = replace(o, part_of=owner[o.id], support=owner[o.id])
        elif o.category in WALL_MOUNTED and o.support is not None:
            report.warnings[f"{o.category}: wall-mounted, support cleared"] += 1
            o = replace(o, support=None)
        # What rested on a part rests on the part's fixture (a pan on a burner); a part
        # the adapter gave to a folded part (a basin inside a faucet's box) goes with it.
        for field in ("support", "source_support", "part_of"):
            ref = getattr(o, field)
            if ref in owner:
                o = replace(o, **{field: owner[ref]})
            elif ref in dropped:
                o = replace(o, **{field: None})
        out.append(o)
    return out


def _ranges(
    objects: list[SceneObject],
    dropped: set[str],
    owner: dict[str, str],
    room_center: np.ndarray,
    report: SourceReport,
) -> tuple[list[SceneObject], int]:
    """Burners on no counter are the cooktop of a free-standing range whose body the
    source leaves out: each group of them (with the knobs near it) becomes a ``stove``
    from the floor to the burners' bottom, and they its parts. Knobs with no range stay
    dropped. Updates ``dropped`` and ``owner``; returns the objects and the ranges made."""
    burners = [o for o in objects if o.id in dropped and o.source_label == "StoveBurner"]
    groups: list[list[SceneObject]] = []
    for b in burners:
        near = [g for g in groups if any(_xy_gap(b, o) <= RANGE_GROUP_M for o in g)]
        merged = [b] + [o for g in near for o in g]
        groups = [g for g in groups if g not in near] + [merged]
    made = []
    for k, group in enumerate(groups):
        pts = np.concatenate([o.box.corners()[:, :2] for o in group])
        lo, hi = pts.min(0), pts.max(0)
        ext = np.maximum(hi - lo + 2 * RANGE_MARGIN_M, RANGE_MIN_SIZE_M)
        centre = (lo + hi) / 2
        top = min(o.box.bottom for o in group)
        # Long side along x; the front (+y) toward the room's centre.
        yaw = 0.0 if ext[0] >= ext[1] else np.pi / 2
        size = np.array([max(ext), min(ext), top])
        front = np.array([-np.sin(yaw), np.cos(yaw)])
        if float(np.dot(room_center - centre, front)) < 0:
            yaw += np.pi
        yaw = float(np.arctan2(np.sin(yaw), np.cos(yaw)))
        box = OrientedBox(np.array([*centre, top / 2]), size, yaw_to_matrix(yaw))
        stove = SceneObject(
            f"stove_range_{k}",
            "stove",
            box,
            group[0].asset,
            support=FLOOR,
            source_label=None,  # made here, not in the source (so never folded again)
        )
        made.append(stove)
        for o in group:
            dropped.discard(o.id)
            owner[o.id] = stove.id
        report.warnings["StoveBurner: part of a free-standing range (made)"] += len(group)
        report.warnings["free-standing range made from its burners"] += 1
    for o in objects:
        if o.id in dropped and o.source_label == "StoveKnob":
            host = _fixture_for(o, made, ("stove",))
            if host is not None:
                dropped.discard(o.id)
                owner[o.id] = host.id
                report.warnings["StoveKnob: part of a free-standing range"] += 1
    n_lost = sum(1 for o in objects if o.id in dropped and o.source_label in RANGE_PARTS)
    if n_lost:
        report.warnings["StoveKnob: no fixture to belong to (dropped)"] += n_lost
    return objects + made, len(made)


def _xy_gap(a: SceneObject, b: SceneObject) -> float:
    """Distance between the xy bounds of two boxes (0 when they overlap)."""
    pa, pb = a.box.corners()[:, :2], b.box.corners()[:, :2]
    gap = np.maximum(pa.min(0) - pb.max(0), pb.min(0) - pa.max(0))
    return float(np.linalg.norm(np.maximum(gap, 0.0)))


def build_kitchens_and_bathrooms(
    objects: list[SceneObject], room_center: np.ndarray, report: SourceReport
) -> list[SceneObject]:
    """Both steps, in order: counter runs first (fixture parts may belong to them)."""
    return fold_fixture_parts(counter_runs(objects, room_center, report), room_center, report)
