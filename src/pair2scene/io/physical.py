"""Physical properties of a placed scene's objects, shared by every simulator export.

MJCF, USD and URDF exports all need the same facts about each object: is it a free
body or fixed to the world, its mass, centre of mass and inertia tensor, its friction
and its convex collision parts. They are decided here once (:func:`body_physics`,
:func:`scene_physics`), so that the same scene behaves the same in every simulator.

**Mass.** Each category has a rule (:data:`CATEGORY_PHYSICS`):

- a *density* (kg/m^3) where the procedural asset is a solid of one material whose
  parts match the real object's volume (a book, a potato, a pencil, a soap bar): the mass
  is the sum over the convex parts of density x volume (:func:`convex_mass_properties`,
  exact for a closed polyhedron);
- a *typical mass* (kg) at the category's typical size
  (:func:`pair2scene.assets.typical_sizes.typical_size`) where a density makes no sense:
  hollow or mixed objects (a fridge, a wardrobe, a television, a sofa, a mug) whose
  procedural parts are solid stand-ins. The mass scales with the box volume relative to
  the typical box (clamped to :data:`TYPICAL_SCALE_RANGE`), and the parts' unit-density
  inertia is scaled to that mass, so the centre of mass and the shape of the tensor still
  come from the parts.

Parts may overlap (a tomato's stem in its body); the overlap is counted twice, a small
error next to the spread of real masses.

**Friction** comes from the category's material class (:data:`MATERIAL_FRICTION`).
Simulators combine two coefficients differently (MuJoCo takes the larger, PhysX the
average by default); the values are each material's dry sliding coefficient against
wood, the most common counterpart (tables, shelves, floors). Simulators with rolling
friction also get :func:`rolling_friction`: the contact patch a soft object (a pillow, a
lettuce, a filled bag) rests on, which keeps its rigid, round-bottomed stand-in from
rocking away.

**Who moves** (``dynamic``, :data:`DYNAMIC_CHOICES`):

- ``"small"`` (default): small objects (super-category SMALL_OBJECT) are free bodies;
  large furniture, fixtures and anything on a wall are fixed. A mug on a fixed table
  stays free: it can be picked up. A towel hung on a towel holder is fixed as its holder
  is (:func:`~pair2scene.assembly.hanging.hung_on_holder`), under every policy but
  ``"all"``.
- ``"all"``: every object is free except fixtures (counters, sinks, toilets...), wall
  objects and anything mounted on a wall (support ``wall:<i>``), parts of furniture, and
  an object with no known support whose bottom is above the floor (a mounted TV).
- ``"none"``: everything is fixed (a static collision scene).

Shapes: positions (3,), rotations and tensors (3, 3); every quantity of a
:class:`BodyPhysics` is in the object's local frame (its box frame, which is the
asset's frame: centred on the box, +z up, +y front).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pair2scene.assets.mesh import Asset, Mesh
from pair2scene.categories import SuperCategory, super_category
from pair2scene.errors import UserError
from pair2scene.scene.model import Scene, SceneObject, on_wall

__all__ = [
    "CATEGORY_PHYSICS",
    "DYNAMIC_CHOICES",
    "MATERIAL_FRICTION",
    "BodyPhysics",
    "MassRule",
    "body_physics",
    "convex_mass_properties",
    "is_dynamic",
    "rolling_friction",
    "scene_physics",
]

DYNAMIC_CHOICES = ("all", "small", "none")
"""Values of ``dynamic``: which objects are free bodies (see the module docstring)."""


@dataclass(frozen=True)
class BodyPhysics:
    """What a simulator needs to build one object as a rigid body."""

    object_id: str
    category: str
    dynamic: bool
    """True: a free body; False: fixed (welded to the world / a static collider)."""
    mass: float
    """kg (> 0)."""
    com: np.ndarray
    """(3,) centre of mass in the object's local (box) frame."""
    inertia: np.ndarray
    """(3, 3) inertia tensor about ``com``, local axes; symmetric positive definite."""
    friction: float
    """Sliding friction coefficient."""
    material: str
    """The material class the friction came from (a key of :data:`MATERIAL_FRICTION`)."""
    parts: tuple[Mesh, ...]
    """Convex collision parts in the local frame (the asset's parts)."""


# -- materials -----------------------------------------------------------------------
MATERIAL_FRICTION: dict[str, float] = {
    "wood": 0.5,  # wood on wood, dry: 0.25-0.5 (Engineering ToolBox friction table)
    "fabric": 0.8,  # upholstery, cloth, foam on wood: 0.6-1 (no standard figure)
    "rubber": 1.0,  # rubber soles, feet and balls on wood or floors: 0.7-1.2
    "metal": 0.4,  # steel or aluminium on wood: 0.2-0.6
    "ceramic": 0.4,  # glazed ceramic or porcelain on wood: 0.3-0.5
    "glass": 0.4,  # glass on wood: 0.25-0.5
    "plastic": 0.4,  # ABS / PVC / polycarbonate on wood: 0.3-0.5
    "paper": 0.5,  # paper and cardboard on wood: 0.4-0.6
    "stone": 0.6,  # stone, granite, marble on wood: 0.4-0.7
    "food": 0.6,  # fruit skin, bread crust on wood: moist, 0.5-0.7
}
"""Sliding friction per material class: a dry static coefficient against wood, the
middle of the ranges of the usual engineering tables (rounded to 0.1). Objects at rest on
level surfaces do not slide at any of them, so their spread matters only for pushing."""

RIGID_ROLLING_FRICTION_M = 2e-4
"""m; rolling friction length (the lever arm of the resisting torque, per newton of
normal force) of a rigid object: hard plastic or steel on wood has a contact patch of a
fraction of a millimetre (rolling-resistance coefficients of 0.001-0.003 for wheels of
10 cm). Simulators without rolling friction ignore it."""
SOFT_PATCH_FRACTION: dict[str, float] = {
    "fabric": 0.25,  # a pillow or a teddy bear sits on a quarter of its width and more
    "food": 0.1,  # a lettuce, a loaf or a tomato flattens a little under its weight
}
"""Materials of soft objects -> the half-width of the patch they rest on, as a fraction
of their smaller horizontal half-extent: a deformable object resting on a table can
resist a toppling torque up to its weight times that half-width, which is what rolling
friction models. The procedural stand-ins are rigid convex hulls that touch the table at
one point of a rounded bottom (a lettuce, a filled bag); without this they rock and roll
away where the real object slumps and stays."""
SOFT_CATEGORIES: dict[str, float] = {
    "garbage_bag": 0.25,  # a filled plastic sack slumps like a cushion
}
"""Soft categories whose material is not a soft one -> their patch fraction (as in
:data:`SOFT_PATCH_FRACTION`)."""

DEFAULT_MATERIAL = "wood"
"""Material of a category missing from :data:`CATEGORY_PHYSICS` (one added later, or
``unknown``): furniture is mostly wood."""
DEFAULT_DENSITY_KG_M3 = 500.0
"""Density of a category missing from :data:`CATEGORY_PHYSICS`: a softwood / particle
board figure (pine 350-550, chipboard 600-700), the density
:mod:`pair2scene.curation.physics` simulates every object with."""

WOOD_KG_M3 = 600.0
"""Wood, for solid wooden parts (a pencil's lead is negligible): beech 700, pine 500."""
PAPER_KG_M3 = 700.0
"""A book or paper stack with the air between pages: printed paper is 700-1150."""
PVC_KG_M3 = 1380.0
"""Rigid PVC, the body of a credit card."""
PLASTIC_KG_M3 = 1100.0
"""A pen's plastic barrel with its metal refill and the air in it."""
SOAP_KG_M3 = 1100.0
"""Bar soap: 1.05-1.15 g/cm^3 (it sinks, barely)."""
APPLE_KG_M3 = 850.0
"""Apples float: about 0.85 g/cm^3."""
POTATO_KG_M3 = 1080.0
"""Potatoes sink: 1.06-1.10 g/cm^3 (the starch test)."""
EGG_KG_M3 = 1030.0
"""A fresh egg: 1.03 g/cm^3 (it sinks in fresh water)."""
BREAD_KG_M3 = 250.0
"""A loaf of bread: 0.2-0.3 g/cm^3."""
PILLOW_KG_M3 = 50.0
"""A pillow's filling and cover: a 50 x 70 cm pillow of ~12 L weighs ~0.6 kg."""
STONE_KG_M3 = 2500.0
"""Quartz / granite worktops: 2400-2700 kg/m^3."""


@dataclass(frozen=True)
class MassRule:
    """How a category's mass is found: by ``density`` (kg/m^3) over the parts' volume,
    or as a ``typical_mass`` (kg) at the category's typical size; exactly one is set."""

    material: str
    density: float | None = None
    typical_mass: float | None = None

    def __post_init__(self) -> None:
        if (self.density is None) == (self.typical_mass is None):
            raise ValueError("a MassRule has exactly one of density and typical_mass")
        if self.material not in MATERIAL_FRICTION:
            raise ValueError(f"unknown material {self.material!r}")


def _d(material: str, density: float) -> MassRule:
    return MassRule(material, density=density)


def _m(material: str, kg: float) -> MassRule:
    return MassRule(material, typical_mass=kg)


# Typical masses are retail and catalogue figures of common items (IKEA, appliance
# makers' data sheets, sports federations' rules), rounded; ranges in the comments.
# fmt: off
CATEGORY_PHYSICS: dict[str, MassRule] = {
    # large furniture: hollow carcasses, frames and upholstery -> typical masses
    "bed": _m("fabric", 80.0),  # double frame 40-55 + mattress 25-35
    "sofa": _m("fabric", 60.0),  # three-seat sofa 45-80
    "armchair": _m("fabric", 25.0),  # 15-35
    "chair": _m("wood", 6.0),  # dining chair 4-8
    "stool": _m("wood", 4.0),  # bar stool 3-6
    "ottoman": _m("fabric", 10.0),  # 6-15
    "dining_table": _m("wood", 35.0),  # four to six seats 25-50
    "coffee_table": _m("wood", 20.0),  # 12-30
    "side_table": _m("wood", 8.0),  # nightstand 6-15
    "desk": _m("wood", 30.0),  # 20-40
    "dressing_table": _m("wood", 30.0),  # 20-40
    "dresser": _m("wood", 50.0),  # chest of drawers 40-70
    "wardrobe": _m("wood", 90.0),  # 100 x 60 x 200 cm: 80-110
    "cabinet": _m("wood", 45.0),  # sideboard 35-60
    "tv_stand": _m("wood", 25.0),  # 15-35
    "shelving_unit": _m("wood", 30.0),  # 80 x 28 x 200 cm bookcase ~30
    "floor_lamp": _m("metal", 5.0),  # 3-8
    "garbage_can": _m("plastic", 3.0),  # 20-30 L bin, empty
    "fridge": _m("metal", 70.0),  # fridge-freezer 60-90
    "laundry_hamper": _m("fabric", 2.0),  # 1-3, empty
    "safe": _m("metal", 40.0),  # home safe 20-60
    "dog_bed": _m("fabric", 3.0),  # 2-5
    "house_plant": _m("ceramic", 8.0),  # pot, soil and plant 5-15
    "vacuum_cleaner": _m("plastic", 6.0),  # upright 4-8
    "cart": _m("metal", 12.0),  # service trolley 8-15
    # fixtures (fixed under every policy; masses for completeness)
    "counter_top": _d("stone", STONE_KG_M3),  # a solid slab
    "sink": _m("ceramic", 15.0),  # ceramic basin 10-20
    "toilet": _m("ceramic", 40.0),  # two-piece 30-50
    "bathtub": _m("ceramic", 50.0),  # acrylic 30-50 (cast iron 100+)
    "shower": _m("glass", 30.0),  # glass screen and tray
    "towel_holder": _m("metal", 1.0),
    "toilet_paper_hanger": _m("metal", 0.5),
    "faucet": _m("metal", 1.5),  # brass mixer tap 1-2
    "stove": _m("metal", 2.0),  # one burner of a hob
    "ceiling_lamp": _m("metal", 2.0),  # pendant 1-4
    # parts
    "drawer": _m("wood", 3.0),
    "cabinet_door": _m("wood", 4.0),
    "shelf": _m("wood", 3.0),
    "stove_knob": _m("plastic", 0.02),
    "sink_basin": _m("metal", 5.0),  # stainless basin
    "bathtub_basin": _m("ceramic", 30.0),
    # wall objects
    "painting": _m("wood", 3.0),  # framed canvas 1-5
    "mirror": _m("glass", 8.0),  # 50 x 80 cm framed mirror 6-10
    "curtains": _m("fabric", 3.0),  # a pair 2-4
    "blinds": _m("plastic", 2.0),
    "wall_lamp": _m("metal", 1.0),
    # small objects: hollow, filled or multi-material -> typical masses
    "television": _m("plastic", 15.0),  # 50-55" LED TV with stand 13-20
    "laptop": _m("plastic", 2.0),  # 1.2-2.5
    "desktop_computer": _m("metal", 8.0),  # tower 6-10
    "monitor": _m("plastic", 5.0),  # 24-27" with stand 4-7
    "keyboard": _m("plastic", 0.8),  # 0.5-1.2
    "table_lamp": _m("ceramic", 2.0),  # 1-3
    "book": _d("paper", PAPER_KG_M3),  # solid block
    "pillow": _d("fabric", PILLOW_KG_M3),  # solid cushion
    "vase": _m("ceramic", 1.0),  # 0.5-2, empty
    "bowl": _m("ceramic", 0.4),  # cereal bowl 0.3-0.5
    "mug": _m("ceramic", 0.35),  # 0.3-0.4
    "cup": _m("glass", 0.25),  # tumbler 0.2-0.3
    "plate": _m("ceramic", 0.5),  # dinner plate 0.4-0.7
    "pot": _m("metal", 1.5),  # saucepan 1-2
    "pan": _m("metal", 1.2),  # frying pan 0.9-1.8
    "kettle": _m("metal", 1.2),  # empty 1-1.5
    "box": _m("paper", 2.0),  # carton with some contents
    "statue": _m("ceramic", 2.0),  # figurine 0.5-4
    "remote_control": _m("plastic", 0.15),  # with batteries
    "alarm_clock": _m("plastic", 0.3),
    "cell_phone": _m("glass", 0.18),  # 0.15-0.22
    "bottle": _m("plastic", 1.0),  # a filled 1 L bottle
    "wine_bottle": _m("glass", 1.3),  # full 75 cl: 1.2-1.5
    "spray_bottle": _m("plastic", 0.5),  # 0.5 L, filled
    "soap_bottle": _m("plastic", 0.4),  # 0.3 L, filled
    "candle": _m("plastic", 0.2),  # pillar candle in a holder (wax: plastic-like)
    "tissue_box": _m("paper", 0.2),
    "teddy_bear": _m("fabric", 0.4),
    "watch": _m("metal", 0.1),
    "key_chain": _m("metal", 0.05),
    "credit_card": _d("plastic", PVC_KG_M3),  # solid card
    "pen": _d("plastic", PLASTIC_KG_M3),
    "pencil": _d("wood", WOOD_KG_M3),
    "cd": _m("plastic", 0.016),  # a disc is 15-16 g (the procedural one is thicker)
    "newspaper": _m("paper", 0.3),  # magazine 0.2-0.4
    "cloth": _m("fabric", 0.1),
    "towel": _m("fabric", 0.5),  # bath towel 0.4-0.7
    "hand_towel": _m("fabric", 0.15),
    "toilet_paper": _m("paper", 0.1),  # one roll 0.09-0.12
    "paper_towel_roll": _m("paper", 0.25),
    "soap_bar": _d("plastic", SOAP_KG_M3),  # solid bar (plastic-like friction)
    "scrub_brush": _m("plastic", 0.2),
    "plunger": _m("rubber", 0.5),  # rubber cup on a wooden handle
    "dish_sponge": _m("fabric", 0.02),  # foam
    "salt_shaker": _m("glass", 0.15),
    "pepper_shaker": _m("glass", 0.15),
    "fork": _m("metal", 0.05),  # table fork 40-60 g
    "knife": _m("metal", 0.15),  # kitchen knife 0.1-0.25
    "butter_knife": _m("metal", 0.05),
    "spoon": _m("metal", 0.05),
    "spatula": _m("plastic", 0.1),
    "ladle": _m("metal", 0.15),
    "microwave": _m("metal", 15.0),  # 10-18
    "toaster": _m("metal", 2.5),  # 2-3
    "coffee_machine": _m("plastic", 5.0),  # 3-8
    "apple": _d("food", APPLE_KG_M3),
    "bread": _d("food", BREAD_KG_M3),
    "potato": _d("food", POTATO_KG_M3),
    "tomato": _m("food", 0.15),  # 0.1-0.2 (procedural parts overlap)
    "egg": _d("food", EGG_KG_M3),
    "lettuce": _m("food", 0.5),  # a head 0.4-0.7
    "aluminum_foil": _m("metal", 0.4),  # a roll in its box
    "watering_can": _m("plastic", 0.5),  # empty
    "baseball_bat": _m("wood", 0.9),  # 0.8-1
    "basketball": _m("rubber", 0.62),  # FIBA size 7: 567-650 g
    "tennis_racket": _m("plastic", 0.3),  # composite frame 0.25-0.35
    "dumbbell": _m("metal", 5.0),  # 2-10
    "boots": _m("rubber", 1.5),  # a pair, rubber soles
    "garbage_bag": _m("plastic", 3.0),  # a filled bag 2-5
    "decor": _m("ceramic", 1.0),  # table-top ornament
}
"""Category -> material and mass rule; a missing category gets :data:`DEFAULT_MATERIAL`
at :data:`DEFAULT_DENSITY_KG_M3`. The test suite checks that every object category is
listed."""
# fmt: on

TYPICAL_SCALE_RANGE = (0.125, 8.0)
"""A typical mass scales with the box volume over the typical box volume, clamped to
this range: a single bed is lighter than a king-size one, but a box eight times the
typical volume is a mis-sized asset, not a heavier kind of object."""
MIN_THICKNESS_M = 2e-4
"""A part thinner than this (a flat card, a degenerate hull) is taken as a box of its
extents with this thickness: a zero-volume polyhedron has no inertia, and one this thin
weighs next to nothing (0.2 mm: thinner than any procedural part)."""
MIN_MASS_KG = 1e-3
"""Floor on a body's mass (1 g): a simulator divides by it."""
INERTIA_REGULARISATION = 1e-4
"""Each principal moment gets this fraction of the largest one added: keeps a flat
body's tensor (where C = A + B exactly) strictly within the triangle inequality that
simulators check, after the rounding of a file format (MJCF is written with 6
significant digits). Negligible otherwise (0.01 %)."""
MIN_INERTIA = 1e-10
"""kg m^2; absolute floor on each principal moment (a simulator divides by it)."""
MOUNTED_MIN_HEIGHT_M = 0.05
"""An object with no known support whose bottom is above this is mounted (a wall TV),
as in :mod:`pair2scene.curation.physics`, and is fixed."""


# -- mass properties -------------------------------------------------------------------
def convex_mass_properties(mesh: Mesh, density: float) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass (kg), centre of mass (3,) and inertia tensor (3, 3) about it, of a closed,
    outward-oriented mesh of uniform ``density`` (kg/m^3), exact for the polyhedron.

    The solid is split into signed tetrahedra from a point near the mesh (its vertex
    mean, for rounding), one per face; their volumes and second moments sum to the
    polyhedron's (the divergence theorem). The second moment of a tetrahedron
    (0, a, b, c) is det(A) A C A^T with A = [a b c] and C = (I + ones(3, 3)) / 120, the
    canonical tetrahedron's (F. Tonon, "Explicit exact formulas for the 3-D tetrahedron
    inertia tensor in terms of its vertex coordinates"). A part thinner than
    :data:`MIN_THICKNESS_M`, or one with no positive volume (a flat or open mesh), is taken
    as the box of its extents along its principal directions, the thinnest one floored at
    that thickness, so the tensor stays positive definite."""
    v = np.asarray(mesh.vertices, dtype=float)
    if len(v) == 0:
        raise ValueError("a mesh without vertices has no mass")
    ref = v.mean(0)
    axes, lo, hi = _principal_extents(v - ref)
    if len(mesh.faces) and np.min(hi - lo) >= MIN_THICKNESS_M:
        t = mesh.triangles - ref  # (F, 3, 3): rows a, b, c of each face
        det = np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2]))  # (F,) 6 x volumes
        volume = float(det.sum()) / 6.0
        if volume > 0.0:
            centroid = (det[:, None] * t.sum(1)).sum(0) / (4.0 * det.sum())  # (3,)
            # sum over faces of det * A C A^T, A = t^T (t's rows are the vertices); with
            # C = (I + ones) / 120 that is (sum_k v_k v_k^T + s s^T) / 120, s = sum_k v_k
            s = t.sum(1)  # (F, 3)
            cov = np.einsum("f,fki,fkj->ij", det, t, t) + np.einsum("f,fi,fj->ij", det, s, s)
            cov /= 120.0
            cov_c = cov - volume * np.outer(centroid, centroid)  # about the centroid
            inertia = np.trace(cov_c) * np.eye(3) - cov_c
            inertia = density * (inertia + inertia.T) / 2
            if np.linalg.eigvalsh(inertia)[0] > 0.0:
                return density * volume, ref + centroid, inertia
    # thin or degenerate: the box of its principal extents, floored in thickness
    size = np.maximum(hi - lo, MIN_THICKNESS_M)
    mass = density * float(np.prod(size))
    moments = mass / 12.0 * ((size**2).sum() - size**2)
    centre = ref + axes @ ((lo + hi) / 2)
    return mass, centre, axes @ np.diag(moments) @ axes.T


def _principal_extents(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Principal axes (3, 3) (columns) of points (N, 3) and their min (3,) and max (3,)
    coordinates along them."""
    cov = points.T @ points / max(len(points), 1)
    _, axes = np.linalg.eigh(cov)
    local = points @ axes
    return axes, local.min(0), local.max(0)


def _combine(props: list[tuple[float, np.ndarray, np.ndarray]]):
    """Mass, centre of mass (3,) and inertia (3, 3) about it of rigidly joined parts,
    each given as (mass, com, inertia about its com) (parallel-axis theorem)."""
    masses = np.array([m for m, _, _ in props])
    coms = np.array([c for _, c, _ in props]).reshape(-1, 3)
    total = float(masses.sum())
    com = (masses[:, None] * coms).sum(0) / total
    inertia = np.zeros((3, 3))
    for m, c, tensor in props:
        d = c - com
        inertia += tensor + m * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return total, com, inertia


def _regularised(inertia: np.ndarray) -> np.ndarray:
    """``inertia`` made exactly symmetric, with every principal moment raised by
    :data:`INERTIA_REGULARISATION` of the largest and floored at :data:`MIN_INERTIA`."""
    sym = (inertia + inertia.T) / 2
    w, axes = np.linalg.eigh(sym)
    w = np.maximum(w + INERTIA_REGULARISATION * max(w[-1], 0.0), MIN_INERTIA)
    return (axes * w) @ axes.T


def mass_rule(category: str) -> MassRule:
    """The :class:`MassRule` of ``category`` (the default one if it is not listed)."""
    rule = CATEGORY_PHYSICS.get(category)
    return rule if rule is not None else MassRule(DEFAULT_MATERIAL, DEFAULT_DENSITY_KG_M3)


def _typical_volume(category: str) -> float:
    from pair2scene.assets.typical_sizes import typical_size

    return float(np.prod(typical_size(category).size))


def asset_mass_properties(
    category: str, parts: tuple[Mesh, ...], size: np.ndarray
) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass (kg), centre of mass (3,) and inertia tensor (3, 3) about it of an asset of
    ``category`` with convex ``parts`` filling a box of ``size`` (3,)."""
    rule = mass_rule(category)
    density = rule.density if rule.density is not None else 1.0
    mass, com, inertia = _combine([convex_mass_properties(p, density) for p in parts])
    if rule.typical_mass is not None:
        ratio = float(np.prod(np.asarray(size, dtype=float))) / max(
            _typical_volume(category), 1e-12
        )
        target = rule.typical_mass * float(np.clip(ratio, *TYPICAL_SCALE_RANGE))
        inertia = inertia * (target / mass)
        mass = target
    if mass < MIN_MASS_KG:
        inertia = inertia * (MIN_MASS_KG / mass)
        mass = MIN_MASS_KG
    return mass, com, _regularised(inertia)


def rolling_friction(category: str, size: np.ndarray) -> float:
    """Rolling friction length (m) of an object of ``category`` filling a box of ``size``
    (3,): the half-width of the patch a soft object rests on
    (:data:`SOFT_PATCH_FRACTION`), or :data:`RIGID_ROLLING_FRICTION_M`. Shared by the
    exports of simulators with rolling friction (MuJoCo: condim 6)."""
    fraction = SOFT_CATEGORIES.get(category, SOFT_PATCH_FRACTION.get(mass_rule(category).material))
    if fraction is None:
        return RIGID_ROLLING_FRICTION_M
    half = float(np.min(np.asarray(size, dtype=float)[:2])) / 2
    return max(fraction * half, RIGID_ROLLING_FRICTION_M)


# -- who moves ---------------------------------------------------------------------------
def _check_dynamic(dynamic: str) -> None:
    if dynamic not in DYNAMIC_CHOICES:
        raise UserError(f"dynamic must be one of {', '.join(DYNAMIC_CHOICES)}; got {dynamic!r}")


def _anchored(obj: SceneObject) -> bool:
    """Whether ``obj`` is part of the building under every policy: a fixture, room
    structure, a wall object or anything on a wall, a part of furniture, or an object with
    no known support whose bottom is above the floor (mounted)."""
    sup = super_category(obj.category)
    if sup in (
        SuperCategory.FIXTURE,
        SuperCategory.WALL_OBJECT,
        SuperCategory.PART,
        SuperCategory.STRUCTURE,
    ):
        return True
    if on_wall(obj.support):
        return True
    known = obj.support if obj.support is not None else obj.source_support
    return known is None and obj.box.bottom > MOUNTED_MIN_HEIGHT_M


def is_dynamic(obj: SceneObject, dynamic: str = "small") -> bool:
    """Whether ``obj`` is a free body under the ``dynamic`` policy (module docstring)."""
    _check_dynamic(dynamic)
    if dynamic == "none" or _anchored(obj):
        return False
    if dynamic == "all":
        return True
    return super_category(obj.category) is SuperCategory.SMALL_OBJECT


# -- bodies ------------------------------------------------------------------------------
def body_physics(
    obj: SceneObject, asset: Asset, dynamic: str = "small", hung: bool = False
) -> BodyPhysics:
    """The rigid body of ``obj`` built from ``asset`` (its parts in the box frame);
    ``hung``: a cloth on a towel holder, fixed unless every object is to move."""
    free = is_dynamic(obj, dynamic) and (dynamic == "all" or not hung)
    parts = tuple(p.mesh for p in asset.parts)
    if not parts:
        raise ValueError(f"{obj.id}: asset without parts")
    mass, com, inertia = asset_mass_properties(obj.category, parts, obj.box.size)
    rule = mass_rule(obj.category)
    return BodyPhysics(
        object_id=obj.id,
        category=obj.category,
        dynamic=free,
        mass=float(mass),
        com=com,
        inertia=inertia,
        friction=MATERIAL_FRICTION[rule.material],
        material=rule.material,
        parts=parts,
    )


def scene_physics(
    scene: Scene, assets: dict[str, Asset], dynamic: str = "small"
) -> dict[str, BodyPhysics]:
    """object id -> :class:`BodyPhysics`, in scene order, for every object that has an
    asset in ``assets`` (room structure and objects without an asset are left out)."""
    from pair2scene.assembly.hanging import hung_on_holder

    _check_dynamic(dynamic)
    by_id = scene.by_id()
    out: dict[str, BodyPhysics] = {}
    for o in scene.objects:
        asset = assets.get(o.id)
        if asset is None or super_category(o.category) is SuperCategory.STRUCTURE:
            continue
        out[o.id] = body_physics(o, asset, dynamic, hung_on_holder(o, by_id))
    return out
