"""Physical plausibility of a scene at mesh level, independent of how it was made.

- :func:`intersecting` names the objects whose meshes intersect another object's by more
  than ``depth`` (fcl over every convex part; boxes only prefilter the pairs);
  the **collision rate** is their share of the scene's objects.
- :func:`floating` names the objects that do not rest on anything: lowered by ``gap``
  (1 cm), an object on the floor must reach z = 0 and one on a support must touch the
  support's mesh. An object hung on a wall (support ``wall:<i>``, no gravity) rests on it
  when one of its vertical faces (the back, preferably) is parallel to wall i within 15
  degrees, 1 cm or less from its line, overlapping the wall segment, and no corner of the
  object is more than 5 mm through the wall (:func:`wall_rest`). The **floating rate**
  is their share. Objects with an unknown support (None) are not judged.
- :func:`stability` simulates the scene as it is for 2 s under gravity (MuJoCo, the
  curation's physics with no depenetration phase and no fitting: nothing is helped) and
  measures how far each object's box corners moved; **stability** is the share of the
  simulated objects that moved less than 2 cm.

Room walls are not collision partners here (only objects are): a wall object touching
its wall is no collision, and one pushed into its wall is reported by :func:`floating`,
not counted in the collision rate.

Both take the scene and the assets its objects were built from (a generated scene's own
assets; for a scene.json read back, :func:`pair2scene.curation.physics.scene_assets`).
"""

from __future__ import annotations

import itertools

import numpy as np

from pair2scene.assembly.collision import MeshWorld, Shape, Tolerances, obb_overlaps
from pair2scene.assets.mesh import Asset
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, WALL, Scene, wall_index
from pair2scene.scene.walls import (
    AGAINST_ANGLE_DEG,
    FACE_AXES,
    FACES,
    MIN_OVERLAP,
    Wall,
    walls_of,
)

COLLISION_DEPTH_M = 0.005
"""Penetration that counts as an intersection: half a centimetre, above the 2 mm contact
placement allows and the numerical noise of fcl's convex tests."""
FLOAT_GAP_M = 0.01
"""An object farther than this above what carries it is floating."""
FLOAT_STEP_M = 0.001
"""Step of the lowering that looks for the support (thinner than any support part)."""
WALL_GAP_M = 0.01
"""A wall object whose nearest parallel face is farther than this from its wall floats."""
WALL_DEPTH_M = COLLISION_DEPTH_M
"""A wall object reaching deeper than this behind its wall's line does not rest on it."""
WALL_ANGLE_DEG = AGAINST_ANGLE_DEG
"""A face rests flat on a wall when parallel to it within this many degrees (15)."""
STABLE_MOTION_M = 0.02
"""An object whose box corners all move less than this in the simulation is stable."""
STABILITY_SECONDS = 2.0
"""Simulated time under gravity for :func:`stability`."""


def _shapes(scene: Scene, assets: dict[str, Asset]) -> dict[str, Shape]:
    out = {}
    for o in scene.objects:
        shape = Shape(assets[o.id])
        shape.set_pose(o.box.rotation, o.box.center)
        out[o.id] = shape
    return out


def intersecting(
    scene: Scene, assets: dict[str, Asset], depth: float = COLLISION_DEPTH_M
) -> dict[str, tuple[str, float]]:
    """object id -> (the object it intersects most, depth m), for every intersecting one."""
    objs = scene.objects
    if len(objs) < 2:
        return {}
    c = np.stack([o.box.center for o in objs])
    h = np.stack([o.box.half_size for o in objs])
    r = np.stack([o.box.rotation for o in objs])
    near = obb_overlaps(c, h, r, c, h, r, 0.0)
    world = MeshWorld(Tolerances(touch=depth))
    shapes = _shapes(scene, assets)
    out: dict[str, tuple[str, float]] = {}
    for i, j in itertools.combinations(range(len(objs)), 2):
        if not near[i, j]:
            continue
        d = world.penetration(shapes[objs[i].id], shapes[objs[j].id], tight=True)
        if d > depth:
            for a, b in ((objs[i].id, objs[j].id), (objs[j].id, objs[i].id)):
                if d > out.get(a, ("", 0.0))[1]:
                    out[a] = (b, d)
    return out


def wall_rest(
    box: OrientedBox,
    wall: Wall,
    height: float,
    max_gap: float = WALL_GAP_M,
    max_depth: float = WALL_DEPTH_M,
    max_angle: float = WALL_ANGLE_DEG,
) -> str | None:
    """None when ``box`` hangs on ``wall`` (of a room ``height`` high), else why not.

    It hangs there when one vertical face, the back tried first, looks at the wall within
    ``max_angle`` degrees (tilted or turned), the face's nearest point is at most
    ``max_gap`` from the wall's line, at least :data:`~pair2scene.scene.walls.MIN_OVERLAP`
    of the face's width lies along the segment, the box overlaps the wall's height, and no
    corner of the box over the segment lies more than ``max_depth`` behind the line."""
    corners = box.corners()  # (8, 3)
    local = wall.local(corners[:, :2])  # (8, 2): along from the midpoint, inward
    half_len = wall.length / 2
    over = np.abs(local[:, 0]) <= half_len + 1e-9
    depth = float(-local[over, 1].min()) if over.any() else 0.0
    if depth > max_depth:
        return f"{depth:.3f} m through wall {wall.index}"
    if box.bottom >= height or box.top <= 0.0:
        return f"outside wall {wall.index}'s height (0 to {height:.2f} m)"
    inward = np.array([*wall.normal, 0.0])
    # which corners lie on which face: their local coordinates' signs
    signs = np.sign((corners - box.center) @ box.rotation)  # (8, 3)
    why = f"no face parallel to wall {wall.index} within {max_angle:.0f} degrees"
    for face in FACES:
        axis, sign = FACE_AXES[face]
        normal = box.rotation[:, axis] * sign  # outward, world
        cos = float(-normal @ inward)
        if cos < np.cos(np.radians(max_angle)):
            continue
        on_face = signs[:, axis] == sign
        gap = float(local[on_face, 1].min())
        lo, hi = float(local[on_face, 0].min()), float(local[on_face, 0].max())
        overlap = min(hi, half_len) - max(lo, -half_len)
        if overlap < MIN_OVERLAP * max(hi - lo, 1e-6):
            why = f"its {face} is beside wall {wall.index}, not on it"
            continue
        if gap > max_gap:
            why = f"its {face} is {gap:.3f} m off wall {wall.index}"
            continue
        return None
    return why


def _wall_floating(scene: Scene, support: str, box: OrientedBox) -> str | None:
    """None when an object with the wall support ``support`` hangs on it, else why not."""
    i = wall_index(support)
    walls = {w.index: w for w in walls_of(scene.room.floor_polygon)}
    if i is None:  # "wall" (not chosen: hierarchies only) or a malformed "wall:..."
        return f"its support {support!r} names no wall (wall:<i>)"
    if i not in walls:
        return f"its support {support} is not a wall of the room ({len(walls)} walls)"
    return wall_rest(box, walls[i], scene.room.height)


def floating(scene: Scene, assets: dict[str, Asset], gap: float = FLOAT_GAP_M) -> dict[str, str]:
    """object id -> why it floats, for every object not resting on its support within
    ``gap``; an object on a wall (``wall:<i>``) by :func:`wall_rest`. Objects with an
    unknown support (``None``) are not judged."""
    by_id = scene.by_id()
    still = _shapes(scene, assets)
    world = MeshWorld(Tolerances(touch=0.0))
    # Lowered in 1 mm steps, not in one jump: a 4 mm card resting on a bowl's 6 mm bottom
    # would pass clean through it if teleported 1 cm down.
    steps = np.arange(1, int(np.ceil(gap / FLOAT_STEP_M)) + 1) * FLOAT_STEP_M
    steps = np.minimum(steps, gap)
    out = {}
    for o in scene.objects:
        if o.support is None:
            continue
        if o.support == FLOOR:
            if o.box.bottom > gap:
                out[o.id] = f"{o.box.bottom:.3f} m above the floor"
            continue
        if o.support.partition(":")[0] == WALL:  # "wall:<i>" (or a malformed "wall...")
            why = _wall_floating(scene, o.support, o.box)
            if why is not None:
                out[o.id] = why
            continue
        if o.support not in by_id:
            out[o.id] = f"its support {o.support} is missing"
            continue
        moving = Shape(assets[o.id])
        for drop in steps:
            moving.set_pose(o.box.rotation, o.box.center - [0.0, 0.0, drop])
            if world.penetration(moving, still[o.support]) > 0.0:
                break
        else:
            out[o.id] = f"not touching {o.support} within {gap * 100:.0f} cm"
    return out


def stability(
    scene: Scene, assets: dict[str, Asset], seconds: float = STABILITY_SECONDS
) -> tuple[dict[str, float], list[str]]:
    """(object id -> largest box-corner displacement (m) after ``seconds`` under gravity,
    for every simulated object; notes). Objects the physics fixes to the world (mounted
    ones) are not in the result. An unstable simulation gives no motions and a note."""
    from pair2scene.curation.physics import PhysicsConfig, validate_physics

    config = PhysicsConfig(fit_heights=False, depenetration_seconds=0.0, settle_seconds=seconds)
    outcome = validate_physics(scene, config=config, assets=assets)
    by_id = scene.by_id()
    motion = {}
    for oid, box in outcome.settled.items():
        moved = np.linalg.norm(box.corners() - by_id[oid].box.corners(), axis=-1)
        motion[oid] = float(moved.max())
    return motion, list(outcome.notes)


def physical_report(scene: Scene, assets: dict[str, Asset], simulate: bool = True) -> dict:
    """``{"objects", "collision_rate", "floating_rate", "intersecting", "floating"}``, and
    with ``simulate`` also ``"stability"`` (None when the simulation failed),
    ``"simulated"``, ``"unstable"`` (id -> metres moved) and ``"notes"``."""
    n = len(scene.objects)
    inter = intersecting(scene, assets)
    flo = floating(scene, assets)
    out = {
        "objects": n,
        "collision_rate": len(inter) / n if n else 0.0,
        "floating_rate": len(flo) / n if n else 0.0,
        "intersecting": {k: [v[0], round(v[1], 4)] for k, v in inter.items()},
        "floating": flo,
    }
    if simulate:
        motion, notes = stability(scene, assets)
        moved = {k: round(v, 4) for k, v in motion.items() if v >= STABLE_MOTION_M}
        failed = any(t.startswith(("could not build", "simulation unstable")) for t in notes)
        share = 1.0 - len(moved) / len(motion) if motion else 1.0
        out["stability"] = None if failed else share
        out["simulated"] = len(motion)
        out["unstable"] = moved
        out["notes"] = notes
    return out
