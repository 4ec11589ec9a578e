"""Wall-mounted objects in curation: the wall each one hangs on, and what it hangs over.

Support extraction (:mod:`pair2scene.curation.support`) finds what carries an object from
below; paintings, mirrors, curtains, blinds, mounted televisions and towel rails are
carried by nothing below them. :func:`mount_on_walls` gives each such object whose box
touches a wall that wall as its support, ``wall:<i>`` (:func:`~pair2scene.scene.model.
wall_support`): one vertical face within :data:`MOUNT_GAP_M` of the wall and parallel to
it within :data:`MOUNT_ANGLE_DEG`. In AI2-THOR and ProcTHOR-1k paintings and televisions
hang 5 mm off their wall (95 % within 2 cm), mirrors 2 cm, blinds and curtains up to
25 cm (in the window's recess, on a rod). The box is then expressed with its back
against the wall (+y, its front, into the room): the same region of space, so a mirror
the source stored facing the wall (AI2-THOR: 34 of 62) faces the room like the others.

:func:`wall_anchors` gives a mounted object its functional anchor, a floor object, the
way the method gives a chair its table: the floor object standing against the same wall
right below it (a painting above the bed or the sofa, a mirror above the dresser or the
sink's counter), else the nearest seat facing it within :data:`FACING_REACH_M` (a TV on
the wall across from the sofa), else none.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pair2scene.categories import SuperCategory, hangs_on_walls
from pair2scene.scene.geometry import OrientedBox, yaw_to_matrix
from pair2scene.scene.model import FLOOR, Scene, SceneObject, wall_index, wall_support
from pair2scene.scene.relations import faces
from pair2scene.scene.walls import AGAINST_GAP_M, Wall, face_contacts, wall_contact, walls_of

MOUNT_GAP_M = 0.3
"""A face this close to a wall mounts an object that nothing carries on it."""
MOUNT_ANGLE_DEG = 20.0
"""... when parallel to it within this many degrees."""
BELOW_MARGIN_M = 0.1
"""A floor object is below a wall object when its top is at most this far above the wall
object's bottom (a headboard reaching a painting's frame)."""
FACING_REACH_M = 5.0
"""A seat facing a wall object anchors it within this distance (centre to centre)."""
SEATS = frozenset({"sofa", "armchair", "bed"})
"""Floor objects a mounted object may face from across the room (a TV, a painting)."""
ANCHOR_SUPER_CATEGORIES = frozenset({SuperCategory.LARGE_FURNITURE, SuperCategory.FIXTURE})
"""What a mounted object is placed relative to: furniture and fixtures (a box or a bin
standing below a painting is not what it was hung over)."""

_TURN = {"back": 0.0, "front": np.pi, "left": -np.pi / 2, "right": np.pi / 2}
"""Yaw turn that brings a face (:data:`~pair2scene.scene.walls.FACES`) to the back."""


def mountable(obj: SceneObject) -> bool:
    """Whether ``obj`` may hang on a wall: carried by nothing, of a category that hangs
    (:func:`~pair2scene.categories.hangs_on_walls`), not built into another object. Other
    objects that nothing carries (a sofa, a bowl: errors of the source) are not mounted."""
    return obj.support is None and hangs_on_walls(obj.category) and obj.part_of is None


def hung_on(obj: SceneObject, walls: list[Wall]) -> Wall | None:
    """The wall ``obj`` hangs on: the one its ``wall:<i>`` support names; for an object
    nothing is known to carry (no support, no source support: a real room as its source
    gives it) that :func:`mountable` would mount, the wall a face touches; else None."""
    index = wall_index(obj.support)
    if index is not None:
        return next((w for w in walls if w.index == index), None)
    if obj.source_support is not None or not mountable(obj):
        return None
    contacts = face_contacts(obj.box, walls, MOUNT_GAP_M, MOUNT_ANGLE_DEG)
    return next((w for w in walls if w.index == contacts[0].wall), None) if contacts else None


def _flat(obj: SceneObject) -> bool:
    """Whether ``obj`` hangs flat on its wall, thinnest across it (a painting, a mirror,
    curtains, a TV; not a towel rail or a microwave): 12 paintings of AI2-THOR and
    ProcTHOR-1k touch a wall only edge-on or lying flat beside it, errors of the source."""
    return obj.super is SuperCategory.WALL_OBJECT or obj.category == "television"


def back_to_wall(box: OrientedBox, face: str) -> OrientedBox:
    """``box`` re-expressed so that ``face`` is its back (local -y): the same region, the
    rotation turned about its own z and the x / y sizes swapped for a quarter turn."""
    turn = _TURN[face]
    if turn == 0.0:
        return box
    rotation = box.rotation @ yaw_to_matrix(turn)
    size = box.size.copy()
    if face in ("left", "right"):
        size[[0, 1]] = size[[1, 0]]
    return OrientedBox(box.center, size, rotation)


def mount_on_walls(scene: Scene) -> Scene:
    """A copy of ``scene`` with every :func:`mountable` object that touches a wall mounted
    on it (support ``wall:<i>``, back to the wall); the others are left as they are."""
    walls = walls_of(scene.room.floor_polygon)
    if not walls:
        return scene
    objects = []
    for o in scene.objects:
        if mountable(o):
            for c in face_contacts(o.box, walls, MOUNT_GAP_M, MOUNT_ANGLE_DEG):
                box = back_to_wall(o.box, c.face)
                if _flat(o) and box.size[1] > min(box.size[0], box.size[2]):
                    continue  # edge-on or lying: not hung on the wall it touches
                o = replace(o, box=box, support=wall_support(c.wall))
                break
        objects.append(o)
    return replace(scene, objects=objects)


def _below(obj: SceneObject, wall: Wall, floor: list[SceneObject], walls: list[Wall]):
    """The floor object against ``wall`` right below ``obj`` (its extent along the wall
    covers obj's centre, its top below obj's bottom), the tallest of several; or None."""
    along = float(wall.local(obj.box.center[:2])[0])
    best = None
    for f in floor:
        contact = wall_contact(f.box, walls, AGAINST_GAP_M)
        if contact is None or contact.wall != wall.index:
            continue
        lo, hi = wall.extent(f.box)
        if not lo <= along <= hi:
            continue
        if f.box.top > obj.box.bottom + BELOW_MARGIN_M:
            continue
        if best is None or f.box.top > best.box.top:
            best = f
    return best


def _facing(obj: SceneObject, floor: list[SceneObject]):
    """The nearest seat within :data:`FACING_REACH_M` that faces ``obj``; or None."""
    best, best_d = None, FACING_REACH_M
    for f in floor:
        if f.category not in SEATS or not faces(f.box, obj.box):
            continue
        d = float(np.linalg.norm(f.box.center[:2] - obj.box.center[:2]))
        if d <= best_d:
            best, best_d = f, d
    return best


def wall_anchors(scene: Scene) -> Scene:
    """A copy of ``scene`` where every object mounted on a wall has the functional anchor
    of the module docstring (or none): whatever another step set for it is replaced."""
    walls = {w.index: w for w in walls_of(scene.room.floor_polygon)}
    floor = [
        o for o in scene.objects
        if o.support == FLOOR and o.part_of is None and o.super in ANCHOR_SUPER_CATEGORIES
    ]  # fmt: skip
    objects = []
    for o in scene.objects:
        index = wall_index(o.support)
        if index is not None and index in walls:
            anchor = _below(o, walls[index], floor, list(walls.values())) or _facing(o, floor)
            o = replace(o, functional_anchor=None if anchor is None else anchor.id)
        objects.append(o)
    return replace(scene, objects=objects)
