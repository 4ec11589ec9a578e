"""Physical validation with MuJoCo: keep only what stays put under gravity.

Each object becomes a rigid body built from its asset's convex parts (MuJoCo collides
a mesh by its convex hull, so concave furniture must arrive as parts: legs, top,
tiers), placed at the object's box pose (asset local frame = box frame), above an
infinite floor plane at z = 0. Then:

0. **Height fitting** (:func:`fit_heights`): each object is set onto its support's
   procedural surface when that is within a few centimetres of where the source rests
   it (the stand-in's mattress or desk top is not exactly where the source's is), and
   an object the source holds higher above its support (where it was spawned) falls
   straight down onto it, as it would have in the source's simulator.
1. **Depenetration** (``depenetration_seconds``, gravity off, strong velocity
   damping): contacts push overlapping bodies apart. A body pushed further than
   ``max_depenetration_m`` was deeply inside something (two chairs merged, a table
   sunk into the floor) and is dropped.
2. **Settling** (``settle_seconds``, gravity on, no damping), measured from the pose
   at the end of phase 1, so that separating by a few millimetres does not count: a
   body that moves more than ``max_translation_m`` or turns more than
   ``max_rotation_deg`` is dropped (floating, tipping over an edge, sliding).

Motion is measured relative to the free body an object rests on: a mug riding on a
table that is pushed or falls has done nothing wrong itself, and the table's failure
reaches it below.

Dropped objects take their dependents with them: everything whose support chain
(``support``, or ``source_support`` where ``support`` is not known) reaches a dropped
object, and every part (``part_of``) of one.

Who moves (see :func:`plan_bodies`):

- ``free``: large furniture, small objects and unknowns: a free joint each.
- ``static``: fixtures (built in: counters, sinks, toilets), wall objects (they hang
  on walls the simulation does not have), towels on a towel holder (they hang on it:
  our rigid stand-in of a cloth, balanced on a round bar, slid off; 12 of the source
  towels on holders were dropped so), and objects whose support is not known at
  all (neither ``support`` nor ``source_support``) whose bottom is above
  :data:`MOUNTED_MIN_HEIGHT_M` (a wall-mounted TV, a microwave in an over-stove
  cabinet that the source does not list). They collide but never move and are
  never dropped.
- ``owned``: a part (drawer, shelf) of a piece of furniture is not simulated: the
  owner's asset already has its shape, and the sources' part boxes often stick out of
  their owner's. It is dropped with its owner. Parts with no furniture owner (AI2-THOR
  kitchen cabinets, which are only doors and drawers) are static.
- ``excluded``: room structure (walls, doors): not simulated, kept as is.

Walls are not built: objects in the sources often poke a few centimetres through the
room polygon, and a wall would push them out and count it as motion.

Shapes: positions (3,), rotations (3, 3) as in :mod:`pair2scene.scene.geometry`,
quaternions (4,) in MuJoCo's (w, x, y, z) order.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from enum import Enum

import numpy as np

from pair2scene.assets.identity import asset_seed
from pair2scene.assets.mesh import Asset, Mesh, axis_aligned_box
from pair2scene.categories import SuperCategory
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Scene, SceneObject, on_wall


@dataclass(frozen=True)
class PhysicsConfig:
    max_translation_m: float = 0.05
    """An object that moves more than this under gravity is dropped: several times the
    few millimetres a resting body sinks into MuJoCo's soft contacts, well under the
    size of anything that fell or slid."""
    max_rotation_deg: float = 10.0
    """... or turns more than this: a tipping object passes it within a fraction of a
    second, a wobbling one on uneven procedural legs stays below it."""
    settle_seconds: float = 1.0
    """Simulated time under gravity: an object starting 0.3 m above its support lands
    in 0.25 s; one balanced on an edge is well past 10 degrees after 1 s."""
    depenetration_seconds: float = 0.12
    """Simulated time of phase 1 (gravity off): long enough for contacts to push
    shallow overlaps (a few cm) fully apart under the damping below."""
    max_depenetration_m: float = 0.05
    """An object pushed further than this out of an overlap (relative to what it rests
    on) is dropped: the same bound as under gravity, since no object may be displaced
    more than that by anything. The sources' boxes and the procedural shapes disagree
    by a centimetre or three (a chair tucked under a table, a book against a shelf's
    side); two pieces of furniture merged by 10 cm, or a table sunk into the floor, do
    not pass."""
    depenetration_damping: float = 30.0
    """1/s; velocity damping rate of phase 1 (per unit mass or inertia): overdamped, so
    bodies separate without flying apart."""
    timestep: float = 0.004
    """s; twice it must stay under the contact time constant (MuJoCo's default 0.02 s)."""
    density_kg_m3: float = 500.0
    """Mass from the asset's volume: a wood-like density. Only ratios and the centre of
    mass matter for whether something stays put."""
    friction: float = 0.8
    """Sliding friction of every geom (wood on wood ~0.5, rubber feet ~1): objects on
    level surfaces do not slide, so its exact value matters little."""
    fit_heights: bool = True
    """Set objects onto their support's procedural surface first (:func:`fit_heights`)."""
    max_fall_m: float = 1.0
    """:func:`fit_heights` also lets an object that the source holds above its supporting
    object's surface, further than :data:`FIT_TOL_M`, fall straight down onto the highest surface
    under its centre, from at most this high: ProcTHOR's files hold small objects where
    they were spawned, before the simulator settled them (61 % of the training pillows
    float 0.2-0.7 m over the mattress of a bed whose box ends at its headboard), and they
    would have landed there. 0 keeps only :data:`FIT_TOL_M`'s fitting."""
    walls: bool = True
    """Build the room's walls (from the floor polygon) as static slabs."""
    min_rotation_shift_m: float = 0.02
    """A rotation counts only when it also moves some corner of the object's box by more
    than this: a 7 cm potato rolling onto a facet of its procedural hull, or a pen
    rolling a quarter turn, turns past 10 degrees while nothing visibly moved."""
    seed: int = 0
    """Mixed into each object's asset seed (:func:`~pair2scene.assets.identity.asset_seed`)."""


class Role(str, Enum):
    FREE = "free"
    """A free body: simulated, and dropped if it moves."""
    STATIC = "static"
    """Fixed to the world: collides, never moves, never dropped by the simulation."""
    OWNED = "owned"
    """A part of a piece of furniture (a shelf of a bookcase): the owner's asset already
    has its shape (tiers fitted to what rests on them), and the sources' part boxes
    often poke out of their owner's (below the floor, above the top), so the part is
    not simulated; it is dropped with its owner."""
    EXCLUDED = "excluded"
    """Not simulated, never dropped (room structure)."""


MOUNTED_MIN_HEIGHT_M = 0.05
"""An object with no support annotation whose bottom is higher than this is mounted
(wall TVs, built-in microwaves); lower, it stands on the floor and is simulated."""
FIT_TOL_M = 0.1
"""Largest gap between where the source rests an object and its support's procedural
surface that :func:`fit_heights` closes: the procedural beds, desks and sofas put their
surfaces up to ~9 cm from the sources' (measured on AI2-THOR); a gap larger than this is
the scene's own error (an object floating, or sunk into its support)."""
UPRIGHT_COS = 0.999
"""A support whose up axis is within ~2.5 degrees of vertical is upright; the surfaces
of a tilted one are not level, and nothing is fitted onto them."""
MIN_MASS_KG = 0.01
"""Floor on a body's mass: a credit card's 1 mm procedural slab would be ~2 g, and very
light bodies next to 100 kg furniture slow the contact solver down."""
MIN_INERTIA = 1e-6
"""kg m^2; floor on each principal moment, for the same reason."""
SOLVER_ITERATIONS = 30
"""Newton iterations per step: resting contact converges in a few; MuJoCo's default
(100) only costs time here."""
WALL_THICKNESS_M = 0.2
"""Wall slabs are this thick: no object can be pushed through one within a step."""
BOX_TOL = 1e-9
"""m; a part whose 8 vertices sit on its bounds (within this) is an axis-aligned box,
simulated as a MuJoCo box primitive (faster than a mesh)."""


@dataclass(frozen=True)
class BodyPlan:
    """How one object enters the simulation."""

    role: Role
    owner: str | None = None
    """For OWNED parts: the piece of furniture they belong to."""
    why: str = ""
    """A few words on the choice (reports, tests)."""


@dataclass
class PhysicsOutcome:
    scene: Scene
    """The scene without the dropped objects (and their dependents)."""
    dropped: dict[str, str] = field(default_factory=dict)
    """object id -> reason ("moved 0.12 m", "rotated 34 deg", "rests on dropped sofa_0")."""
    motion: dict[str, tuple[float, float]] = field(default_factory=dict)
    """object id -> (translation m, rotation deg) measured in the simulation (phase 2,
    from the pose after depenetration; translation relative to the free body it rests
    on), for every free body."""
    seconds: float = 0.0
    depenetration: dict[str, float] = field(default_factory=dict)
    """object id -> translation (m) in phase 1 (relative to the free body it rests on),
    for every free body."""
    roles: dict[str, Role] = field(default_factory=dict)
    """object id -> how it was simulated."""
    fitted: dict[str, float] = field(default_factory=dict)
    """object id -> vertical shift (m) of its start pose onto its support's procedural
    surface (:func:`fit_heights`); the output scene keeps the source's boxes."""
    notes: list[str] = field(default_factory=list)
    """Why the result is partial, if it is (a failed build, an unstable simulation)."""
    settled: dict[str, OrientedBox] = field(default_factory=dict)
    """object id -> its box at the end of the simulation, for every free body (empty
    when the simulation was unstable)."""


# -- planning --------------------------------------------------------------------------
def _resting_on(o: SceneObject) -> str | None:
    """The object ``o`` rests on, as far as the scene knows."""
    return o.support if o.support is not None else o.source_support


def plan_bodies(scene: Scene) -> dict[str, BodyPlan]:
    """object id -> :class:`BodyPlan` (the rules are in the module docstring)."""
    from pair2scene.assembly.hanging import hung_on_holder

    by_id = scene.by_id()
    plans: dict[str, BodyPlan] = {}
    for o in scene.objects:
        sup = o.super
        if sup is SuperCategory.STRUCTURE:
            plans[o.id] = BodyPlan(Role.EXCLUDED, why="room structure")
        elif sup is SuperCategory.FIXTURE:
            plans[o.id] = BodyPlan(Role.STATIC, why="built-in fixture")
        elif sup is SuperCategory.WALL_OBJECT or on_wall(o.support):
            plans[o.id] = BodyPlan(Role.STATIC, why="hangs on a wall")
        elif hung_on_holder(o, by_id):
            plans[o.id] = BodyPlan(Role.STATIC, why="hangs on a holder")
        elif sup is SuperCategory.PART:
            plans[o.id] = BodyPlan(Role.STATIC, why="part without free furniture owner")
        elif _resting_on(o) is None and o.box.bottom > MOUNTED_MIN_HEIGHT_M:
            plans[o.id] = BodyPlan(Role.STATIC, why="no support known, above the floor")
        else:
            plans[o.id] = BodyPlan(Role.FREE)
    for o in scene.objects:
        if o.super is not SuperCategory.PART or o.part_of is None:
            continue
        owner = by_id.get(o.part_of)
        # Only furniture carries parts: the adapters' nearest-host guess can name a small
        # object (a spoon inside a drawer), and a part does not follow a spoon.
        if owner is not None and owner.super is SuperCategory.LARGE_FURNITURE:
            plans[o.id] = BodyPlan(Role.OWNED, owner=owner.id, why="part of furniture")
    return plans


def support_heights(scene: Scene) -> dict[str, list[float]]:
    """object id -> heights above its box bottom (m) where objects resting on it have
    their bottoms: the tiers procedural shelves and cabinets are fitted to."""
    by_id = scene.by_id()
    out: dict[str, list[float]] = {}
    for o in scene.objects:
        host_id = _resting_on(o)
        host = by_id.get(host_id) if host_id not in (None, FLOOR) else None
        if host is None:
            continue
        out.setdefault(host.id, []).append(o.box.bottom - host.box.bottom)
    return out


def scene_assets(scene: Scene, library=None, seed: int = 0) -> dict[str, Asset]:
    """object id -> asset filling its box, for every object not excluded.

    Categories served by the procedural generators are fitted to the heights where the
    scene's objects rest on them (:func:`support_heights`), so that a book on a
    bookcase's second tier finds a board there, and in their solid form (a counter as a
    block: the source's objects stood on its top, whatever its shape). ``library``: an
    :class:`~pair2scene.assets.AssetLibrary` (default: procedural only).
    """
    from pair2scene.assets import AssetLibrary
    from pair2scene.assets.registry import generate

    library = AssetLibrary() if library is None else library
    heights = support_heights(scene)
    out: dict[str, Asset] = {}
    for o in scene.objects:
        if o.super is SuperCategory.STRUCTURE:
            continue
        rng = np.random.default_rng(asset_seed(o.id, seed))
        fit = heights.get(o.id)
        if (
            fit
            and library.procedural
            and library.generator is generate
            and not library.entries(o.category)
        ):
            out[o.id] = generate(o.category, o.box.size, rng, support_heights=fit, solid=True)
        else:
            out[o.id] = library.retrieve(o.category, o.box.size, rng=rng)
    return out


def fit_heights(
    scene: Scene,
    plans: Mapping[str, BodyPlan],
    assets: Mapping[str, Asset],
    max_fall_m: float = 0.0,
) -> dict[str, float]:
    """object id -> vertical offset (m) that sets each free object onto the surface of
    its support's asset (or the floor) nearest to its bottom, when that surface is
    within :data:`FIT_TOL_M`, or else, for an object resting on another, onto the
    highest surface below its bottom when that is at most ``max_fall_m`` down (it falls
    there; furniture off the floor is the scene's error); objects resting on it move
    with it.

    The source placed the object on its own asset, whose surfaces the procedural
    stand-in reproduces only roughly (a mattress's thickness, a desk top's height); the
    offset removes that modelling error before simulation, not the scene's own errors
    (an object floating or sunk further than the tolerance).
    """
    by_id = scene.by_id()
    offset: dict[str, float] = {}

    def resolve(o: SceneObject, seen: frozenset[str]) -> float:
        if o.id in offset:
            return offset[o.id]
        host_id = _resting_on(o)
        host = by_id.get(host_id) if host_id not in (None, FLOOR) else None
        if host is not None and host.id in seen:  # a support cycle: leave it be
            return 0.0
        base = resolve(host, seen | {o.id}) if host is not None else 0.0
        own = 0.0
        if plans[o.id].role is Role.FREE:
            bottom = o.box.bottom + base
            levels = _surface_levels(o, host, assets, base)
            if levels.size:
                nearest = levels[np.argmin(np.abs(levels - bottom))]
                below = levels[levels <= bottom]
                if abs(nearest - bottom) <= FIT_TOL_M:
                    own = float(nearest - bottom)
                elif host is not None and below.size and bottom - below.max() <= max_fall_m:
                    own = float(below.max() - bottom)
        offset[o.id] = base + own
        return offset[o.id]

    for o in scene.objects:
        resolve(o, frozenset())
    return {k: v for k, v in offset.items() if v != 0.0}


def _surface_levels(
    o: SceneObject, host: SceneObject | None, assets: Mapping[str, Asset], host_offset: float
) -> np.ndarray:
    """World heights (K,) of the host's support surfaces under ``o``'s centre (the floor:
    0); empty if none, or if the host is tilted."""
    from pair2scene.assets import surfaces_of

    if host is None:
        return np.zeros(1) if _resting_on(o) == FLOOR else np.zeros(0)
    if host.id not in assets or abs(host.box.rotation[2, 2]) < UPRIGHT_COS:
        return np.zeros(0)
    xy = host.box.to_local(o.box.center[None])[0, :2]
    levels = [
        host.box.center[2] + host_offset + s.z
        for s in surfaces_of(assets[host.id])
        if s.contains(xy[None])[0]
    ]
    return np.array(levels)


# -- mass properties -------------------------------------------------------------------
def mesh_mass_properties(mesh: Mesh) -> tuple[float, np.ndarray]:
    """Volume (m^3) and centroid (3,) of a closed outward mesh, by signed tetrahedra
    from the origin. Degenerate meshes give their vertex mean and zero volume."""
    t = mesh.triangles  # (F, 3, 3)
    vol6 = np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2]))  # (F,) 6x volumes
    total = float(vol6.sum()) / 6.0
    if total <= 1e-12:
        return 0.0, mesh.vertices.mean(0) if len(mesh.vertices) else np.zeros(3)
    centroid = (vol6[:, None] * t.sum(1)).sum(0) / (4.0 * vol6.sum())
    return total, centroid


def body_inertial(asset: Asset, density: float) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass (kg), centre of mass (3,) and principal moments (3,) in the asset's frame.

    Mass and centre from the parts' volumes (what decides tipping); moments from the
    asset's full box with that mass (a coarse stand-in: they only set how fast a body
    turns, not whether it does).
    """
    props = [mesh_mass_properties(p.mesh) for p in asset.parts]
    vols = np.array([v for v, _ in props])
    cents = np.array([c for _, c in props]).reshape(-1, 3)
    volume = float(vols.sum())
    com = (vols[:, None] * cents).sum(0) / volume if volume > 0 else np.zeros(3)
    mass = max(density * volume, MIN_MASS_KG)
    sx, sy, sz = np.asarray(asset.size, dtype=float)
    moments = mass / 12.0 * np.array([sy**2 + sz**2, sx**2 + sz**2, sx**2 + sy**2])
    return mass, com, np.maximum(moments, MIN_INERTIA)


def _as_box(mesh: Mesh) -> tuple[np.ndarray, np.ndarray] | None:
    """(centre (3,), half-size (3,), at least 0.5 mm) if ``mesh`` is an axis-aligned box,
    else None."""
    box = axis_aligned_box(mesh, BOX_TOL)
    return None if box is None else (box[0], np.maximum(box[1], 5e-4))


def quat_wxyz(rotation: np.ndarray) -> np.ndarray:
    """(3, 3) rotation -> (4,) unit quaternion (w, x, y, z)."""
    import mujoco

    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(rotation, dtype=float).reshape(9))
    return q


def _quat_angle_deg(q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Rotation angle (deg) between unit quaternions (N, 4) and (N, 4): (N,)."""
    dot = np.clip(np.abs(np.einsum("ij,ij->i", q0, q1)), 0.0, 1.0)
    return np.degrees(2.0 * np.arccos(dot))


# -- building the model ----------------------------------------------------------------
def _add_geoms(spec, body, asset: Asset, rotation, translation, config, tag: str) -> None:
    """Add ``asset``'s parts to ``body`` as geoms, the asset frame placed at (rotation
    (3, 3), translation (3,)) in the body frame."""
    import mujoco

    for k, part in enumerate(asset.parts):
        mesh = part.mesh
        as_box = _as_box(mesh)
        if as_box is not None:
            centre, half = as_box
            body.add_geom(
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=half,
                pos=rotation @ centre + translation,
                quat=quat_wxyz(rotation),
                friction=[config.friction, 0.005, 0.0001],
            )
            continue
        v = mesh.vertices @ np.asarray(rotation).T + translation
        lo, hi = v.min(0), v.max(0)
        if np.any(hi - lo < 1e-3):
            # too flat for a convex hull (qhull needs a volume): collide as its bounds
            body.add_geom(
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=np.maximum((hi - lo) / 2, 5e-4),
                pos=(lo + hi) / 2,
                friction=[config.friction, 0.005, 0.0001],
            )
            continue
        name = f"{tag}/{k}"
        spec.add_mesh(
            name=name,
            uservert=v.astype(np.float32).reshape(-1).tolist(),
            userface=mesh.faces.astype(np.int32).reshape(-1).tolist(),
            inertia=mujoco.mjtMeshInertia.mjMESH_INERTIA_CONVEX,
        )
        body.add_geom(
            type=mujoco.mjtGeom.mjGEOM_MESH,
            meshname=name,
            friction=[config.friction, 0.005, 0.0001],
        )


def _build(
    scene: Scene,
    plans: Mapping[str, BodyPlan],
    assets: Mapping[str, Asset],
    config: PhysicsConfig,
    offsets: Mapping[str, float] | None = None,
):
    """The compiled MjModel and the free objects' ids in body order; ``offsets``: object
    id -> vertical shift of its start pose (:func:`fit_heights`)."""
    import mujoco

    spec = mujoco.MjSpec()
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.option.timestep = config.timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.iterations = SOLVER_ITERATIONS
    spec.option.gravity = [0.0, 0.0, -9.81]
    spec.worldbody.add_geom(
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[0.0, 0.0, 1.0],
        friction=[config.friction, 0.005, 0.0001],
    )
    free_ids: list[str] = []
    for o in scene.objects:
        plan = plans[o.id]
        if plan.role is Role.FREE:
            pos = o.box.center + [0.0, 0.0, (offsets or {}).get(o.id, 0.0)]
            body = spec.worldbody.add_body(name=o.id, pos=pos, quat=quat_wxyz(o.box.rotation))
            body.add_freejoint()
            mass, com, moments = body_inertial(assets[o.id], config.density_kg_m3)
            body.mass, body.ipos, body.inertia = mass, com, moments
            _add_geoms(spec, body, assets[o.id], np.eye(3), np.zeros(3), config, o.id)
            free_ids.append(o.id)
        elif plan.role is Role.STATIC:
            _add_geoms(
                spec, spec.worldbody, assets[o.id], o.box.rotation, o.box.center, config, o.id
            )
    if config.walls:
        _add_walls(spec, scene, config)
    return spec.compile(), free_ids


def _add_walls(spec, scene: Scene, config: PhysicsConfig) -> None:
    """A static slab behind every edge of the floor polygon, its inner face on the edge
    (things lean on walls: bats, rackets, mattresses)."""
    import mujoco

    poly = np.asarray(scene.room.floor_polygon, dtype=float)  # (N, 2), counter-clockwise
    height = float(scene.room.height)
    t = WALL_THICKNESS_M
    for p0, p1 in zip(poly, np.roll(poly, -1, axis=0)):
        edge = p1 - p0
        length = float(np.hypot(*edge))
        if length < 1e-6:
            continue
        direction = edge / length
        outward = np.array([direction[1], -direction[0]])  # right of a CCW edge: outside
        centre = (p0 + p1) / 2 + outward * t / 2
        yaw = np.arctan2(direction[1], direction[0])
        rot = np.array([[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]])
        # no overhang past the edge's ends: at a reflex corner it would reach into the room
        spec.worldbody.add_geom(
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[length / 2, t / 2, height / 2],
            pos=[centre[0], centre[1], height / 2],
            quat=quat_wxyz(rot),
            friction=[config.friction, 0.005, 0.0001],
        )


# -- simulation ------------------------------------------------------------------------
def _free_poses(data, qadr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positions (n, 3) and quaternions (n, 4) of the free bodies whose free joints
    start at qpos addresses ``qadr`` (n,)."""
    q = data.qpos[qadr[:, None] + np.arange(7)]  # (n, 7)
    return q[:, :3].copy(), q[:, 3:].copy()


@dataclass(frozen=True)
class _Poses:
    """Free-body poses: start, after depenetration, after settling; (n, 3) positions
    and (n, 4) quaternions."""

    p0: np.ndarray
    p1: np.ndarray
    q1: np.ndarray
    p2: np.ndarray
    q2: np.ndarray


def _simulate(model, free_ids: list[str], config: PhysicsConfig) -> tuple[_Poses, list[str]]:
    """Run both phases on the free bodies ``free_ids``; poses and notes."""
    import mujoco

    body = np.array([model.body(oid).id for oid in free_ids])  # (n,)
    jnt = model.body_jntadr[body]
    qadr = model.jnt_qposadr[jnt]
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    p0, _ = _free_poses(data, qadr)
    notes: list[str] = []

    # phase 1: no gravity, damping proportional to each body's mass and inertia
    gravity = model.opt.gravity.copy()
    model.opt.gravity[:] = 0.0
    for i, b in enumerate(body):
        d0 = model.jnt_dofadr[jnt[i]]
        sub_mass = model.body_subtreemass[b]
        model.dof_damping[d0 : d0 + 3] = config.depenetration_damping * sub_mass
        model.dof_damping[d0 + 3 : d0 + 6] = config.depenetration_damping * np.maximum(
            model.body_inertia[b], MIN_INERTIA
        )
    for _ in range(int(round(config.depenetration_seconds / config.timestep))):
        mujoco.mj_step(model, data)
    p1, q1 = _free_poses(data, qadr)

    # phase 2: gravity, no damping, from rest
    model.opt.gravity[:] = gravity
    model.dof_damping[:] = 0.0
    data.qvel[:] = 0.0
    for _ in range(int(round(config.settle_seconds / config.timestep))):
        mujoco.mj_step(model, data)
    p2, q2 = _free_poses(data, qadr)
    bad = int(data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number)
    if bad or not np.all(np.isfinite(data.qpos)):
        notes.append(f"simulation unstable ({bad} bad accelerations): no object dropped")
    if data.warning[mujoco.mjtWarning.mjWARN_CONTACTFULL].number:
        notes.append("contact buffer full: some contacts were ignored")
    return _Poses(p0, p1, q1, p2, q2), notes


def _relative_motion(scene: Scene, free_ids: list[str], poses: _Poses):
    """Each free body's motion relative to the free body it rests on (n,) x 4: phase-1
    translation, phase-2 translation, phase-2 rotation (deg) and the distance that
    rotation moves a box corner.

    Relative, because an object riding along on a support that is itself pushed or
    falls has done nothing wrong; the support's own failure reaches it through
    :func:`dependents_closure`. Rotation is the body's own (a tipping support is
    dropped itself).
    """
    by_id = scene.by_id()
    index = {oid: i for i, oid in enumerate(free_ids)}
    host = np.array([index.get(_resting_on(by_id[oid]), -1) for oid in free_ids])  # (n,)
    step1 = poses.p1 - poses.p0  # (n, 3)
    step2 = poses.p2 - poses.p1
    has = host >= 0
    step1[has] -= (poses.p1 - poses.p0)[host[has]]
    step2[has] -= (poses.p2 - poses.p1)[host[has]]
    half = np.array([by_id[oid].box.half_size for oid in free_ids]).reshape(-1, 3)
    return (
        np.linalg.norm(step1, axis=1),
        np.linalg.norm(step2, axis=1),
        _quat_angle_deg(poses.q1, poses.q2),
        rotation_shift(poses.q1, poses.q2, half),
    )


def _quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """Unit quaternions (n, 4) (w, x, y, z) -> rotations (n, 3, 3)."""
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=-2,
    )


def rotation_shift(q1: np.ndarray, q2: np.ndarray, half_sizes: np.ndarray) -> np.ndarray:
    """(n,) largest distance a box corner moves when a body turns from q1 (n, 4) to
    q2 (n, 4) about its centre; half_sizes (n, 3)."""
    from pair2scene.scene.geometry import UNIT_CORNERS

    corners = UNIT_CORNERS[None] * half_sizes[:, None, :]  # (n, 8, 3) local
    r1, r2 = _quat_to_matrix(q1), _quat_to_matrix(q2)  # (n, 3, 3)
    delta = np.einsum("nij,nkj->nki", r2 - r1, corners)  # (n, 8, 3)
    return np.linalg.norm(delta, axis=-1).max(axis=1)


def dependents_closure(
    scene: Scene, dropped: Mapping[str, str], plans: Mapping[str, BodyPlan] | None = None
) -> dict[str, str]:
    """``dropped`` plus every object resting (directly or through a chain) on a dropped
    one, or part of one; id -> reason.

    plans : when given, a part follows only the owner its plan names (an OWNED part of
    furniture), not whatever ``part_of`` says (the adapters' host guess can be a small
    object standing inside the part).
    """
    out = dict(dropped)
    changed = True
    while changed:
        changed = False
        for o in scene.objects:
            if o.id in out:
                continue
            host = _resting_on(o)
            owner = o.part_of if plans is None else plans[o.id].owner
            if owner in out:
                out[o.id] = f"part of dropped {owner}"
            elif host in out:
                out[o.id] = f"rests on dropped {host}"
            else:
                continue
            changed = True
    return out


def validate_physics(
    scene: Scene,
    library=None,
    config: PhysicsConfig = PhysicsConfig(),
    assets: Mapping[str, Asset] | None = None,
) -> PhysicsOutcome:
    """Simulate ``scene`` under gravity and drop what does not stay put (with dependents).

    library : an :class:`~pair2scene.assets.AssetLibrary` (default: procedural assets).
    assets : object id -> asset, when the scene's assets are at hand (a generated
    scene); otherwise they are built from the library.
    A scene that cannot be built or simulated comes back whole, with the reason in
    ``notes``. ``outcome.settled`` has every kept free body's box at the end.
    """
    t0 = time.perf_counter()
    plans = plan_bodies(scene)
    roles = {k: p.role for k, p in plans.items()}
    outcome = PhysicsOutcome(scene=scene, roles=roles)
    try:
        if assets is None:
            assets = scene_assets(scene, library, seed=config.seed)
        outcome.fitted = (
            fit_heights(scene, plans, assets, config.max_fall_m) if config.fit_heights else {}
        )
        model, free_ids = _build(scene, plans, assets, config, outcome.fitted)
    except Exception as exc:  # noqa: BLE001  (a partial result beats a lost corpus)
        outcome.notes.append(f"could not build the simulation: {type(exc).__name__}: {exc}")
        outcome.seconds = time.perf_counter() - t0
        return outcome
    if not free_ids:
        outcome.seconds = time.perf_counter() - t0
        return outcome

    poses, notes = _simulate(model, free_ids, config)
    outcome.notes += notes
    d1, d2, rot, shift = _relative_motion(scene, free_ids, poses)
    unstable = any(n.startswith("simulation unstable") for n in notes)
    drop: dict[str, str] = {}
    for i, oid in enumerate(free_ids):
        outcome.depenetration[oid] = float(d1[i])
        outcome.motion[oid] = (float(d2[i]), float(rot[i]))
        if unstable:
            continue
        if d1[i] > config.max_depenetration_m:
            drop[oid] = f"overlapped: pushed {d1[i]:.2f} m apart"
        elif d2[i] > config.max_translation_m:
            drop[oid] = f"moved {d2[i]:.2f} m"
        elif rot[i] > config.max_rotation_deg and shift[i] > config.min_rotation_shift_m:
            drop[oid] = f"rotated {rot[i]:.0f} deg"
    outcome.dropped = dependents_closure(scene, drop, plans)
    if not unstable:
        by_id = scene.by_id()
        rotations = _quat_to_matrix(poses.q2)
        for i, oid in enumerate(free_ids):
            outcome.settled[oid] = OrientedBox(poses.p2[i], by_id[oid].box.size, rotations[i])
    keep = [o for o in scene.objects if o.id not in outcome.dropped]
    keep = [
        replace(o, functional_anchor=None) if o.functional_anchor in outcome.dropped else o
        for o in keep
    ]
    outcome.scene = replace(scene, objects=keep, stats=dict(scene.stats))
    outcome.seconds = time.perf_counter() - t0
    return outcome
