"""Physical plausibility of a scene at mesh level, independent of how it was made.

- :func:`intersecting` names the objects whose meshes intersect another object's by more
  than ``depth`` (fcl over every convex part; boxes only prefilter the pairs);
  the **collision rate** is their share of the scene's objects.
- :func:`floating` names the objects that do not rest on anything: lowered by ``gap``
  (1 cm), an object on the floor must reach z = 0 and one on a support must touch the
  support's mesh. The **floating rate** is their share.
- :func:`stability` simulates the scene as it is for 2 s under gravity (MuJoCo, the
  curation's physics with no depenetration phase and no fitting: nothing is helped) and
  measures how far each object's box corners moved; **stability** is the share of the
  simulated objects that moved less than 2 cm.

Both take the scene and the assets its objects were built from (a generated scene's own
assets; for a scene.json read back, :func:`pair2scene.curation.physics.scene_assets`).
"""

from __future__ import annotations

import itertools

import numpy as np

from pair2scene.assembly.collision import MeshWorld, Shape, Tolerances, obb_overlaps
from pair2scene.assets.mesh import Asset
from pair2scene.scene.model import FLOOR, Scene

COLLISION_DEPTH_M = 0.005
"""Penetration that counts as an intersection: half a centimetre, above the 2 mm contact
placement allows and the numerical noise of fcl's convex tests."""
FLOAT_GAP_M = 0.01
"""An object farther than this above what carries it is floating."""
FLOAT_STEP_M = 0.001
"""Step of the lowering that looks for the support (thinner than any support part)."""
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
        d = world.penetration(shapes[objs[i].id], shapes[objs[j].id])
        if d > depth:
            for a, b in ((objs[i].id, objs[j].id), (objs[j].id, objs[i].id)):
                if d > out.get(a, ("", 0.0))[1]:
                    out[a] = (b, d)
    return out


def floating(scene: Scene, assets: dict[str, Asset], gap: float = FLOAT_GAP_M) -> dict[str, str]:
    """object id -> why it floats, for every object not resting on its support within
    ``gap``. Objects with an unknown support (``None``, e.g. wall-hung) are not judged."""
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
