"""Physical plausibility of a scene at mesh level, independent of how it was made.

- :func:`intersecting` names the objects whose meshes intersect another object's by more
  than ``depth`` (fcl over every convex part; boxes only prefilter the pairs);
  the **collision rate** is their share of the scene's objects.
- :func:`floating` names the objects that do not rest on anything: lowered by ``gap``
  (1 cm), an object on the floor must reach z = 0 and one on a support must touch the
  support's mesh. The **floating rate** is their share.

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


def _shapes(scene: Scene, assets: dict[str, Asset], lift: float = 0.0) -> dict[str, Shape]:
    out = {}
    for o in scene.objects:
        shape = Shape(assets[o.id])
        shape.set_pose(o.box.rotation, o.box.center + [0.0, 0.0, lift])
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
    lowered = _shapes(scene, assets, lift=-gap)
    still = _shapes(scene, assets)
    world = MeshWorld(Tolerances(touch=0.0))
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
        if world.penetration(lowered[o.id], still[o.support]) <= 0.0:
            out[o.id] = f"not touching {o.support} within {gap * 100:.0f} cm"
    return out


def physical_report(scene: Scene, assets: dict[str, Asset]) -> dict:
    """``{"objects", "collision_rate", "floating_rate", "intersecting", "floating"}``."""
    n = len(scene.objects)
    inter = intersecting(scene, assets)
    flo = floating(scene, assets)
    return {
        "objects": n,
        "collision_rate": len(inter) / n if n else 0.0,
        "floating_rate": len(flo) / n if n else 0.0,
        "intersecting": {k: [v[0], round(v[1], 4)] for k, v in inter.items()},
        "floating": flo,
    }
