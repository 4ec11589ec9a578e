"""A room's walls as anchors: segments of the floor polygon, their frames, and which wall
an object stands against.

Every edge of the floor polygon (counter-clockwise, so the room lies to each edge's left)
is a :class:`Wall`: its end points, its length, the unit vector along it and its inward
normal. L-shaped and other non-convex rooms need nothing special: each edge is a wall, and
the inward normal of a counter-clockwise polygon's edge is the edge's direction turned a
quarter to the left.

A wall's *frame* (:meth:`Wall.frame`) is the box a tuple anchored to it is predicted in:
x along the wall, y its inward normal, z up; centred on the wall's midpoint at floor level
+ half the room's height, :data:`WALL_FRAME_DEPTH_M` deep each side of the wall, so a
canonical y of 1 is a metre into the room and the floor is canonical z = -1, as in the
room's own frame.

:func:`wall_contact` decides whether an object stands against a wall, the way the figures
of issue 18 count it: one of its vertical faces (its back, by preference) lies within
``max_gap`` of the wall, parallel to it within ``max_angle`` degrees, with the face's
extent overlapping the wall segment by at least half of the face.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from pair2scene.scene.geometry import OrientedBox

WALL_FRAME_DEPTH_M = 1.0
"""Half-depth of a wall's frame box: canonical y is metres from the wall."""
AGAINST_GAP_M = 0.15
"""A face this close to a wall (or closer) stands against it."""
AGAINST_ANGLE_DEG = 15.0
"""... when parallel to it within this many degrees."""
MIN_OVERLAP = 0.5
"""... and when at least this share of the face's width lies along the segment."""
EMBEDDED_M = 0.5
"""A back face this far beyond its wall's plane (or less) stands against the wall too: the
box reaches into the wall, as one AI2-THOR bathroom counter's does (FloorPlan411, 0.30 m;
its sides against the two side walls, it had counted as standing sideways)."""
FACES = ("back", "left", "right", "front")
"""An object's vertical faces by their outward normal in its local frame: back -y,
left -x, right +x, front +y. ``back`` against a wall means facing into the room."""
FACE_AXES = {"back": (1, -1.0), "left": (0, -1.0), "right": (0, 1.0), "front": (1, 1.0)}
"""Each of :data:`FACES`: (local axis it is normal to, sign of its outward normal along
that axis)."""
_FACE_NORMALS = {face: np.eye(2)[axis] * sign + 0.0 for face, (axis, sign) in FACE_AXES.items()}


@dataclass(frozen=True)
class Wall:
    """One straight wall of a room, as seen from above."""

    index: int
    """Its edge's index in the floor polygon (edge i runs from vertex i to i + 1)."""
    p0: np.ndarray
    p1: np.ndarray

    # Worked out once a wall (placement asks each of a candidate's checks for them).
    @cached_property
    def length(self) -> float:
        return float(np.linalg.norm(self.p1 - self.p0))

    @cached_property
    def direction(self) -> np.ndarray:
        """Unit vector from p0 to p1."""
        d = self.p1 - self.p0
        return d / max(float(np.linalg.norm(d)), 1e-12)

    @cached_property
    def normal(self) -> np.ndarray:
        """Unit inward normal (into the room)."""
        d = self.direction
        return np.array([-d[1], d[0]])

    @cached_property
    def midpoint(self) -> np.ndarray:
        return (self.p0 + self.p1) / 2

    @property
    def yaw(self) -> float:
        """Heading of the wall's x axis (its direction)."""
        d = self.direction
        return float(np.arctan2(d[1], d[0]))

    def frame(self, height: float) -> OrientedBox:
        """The wall's frame box (see the module docstring)."""
        center = [*self.midpoint, height / 2]
        size = [max(self.length, 1e-3), 2 * WALL_FRAME_DEPTH_M, height]
        return OrientedBox.from_yaw(center, size, self.yaw)

    def local(self, points: np.ndarray) -> np.ndarray:
        """World xy (..., 2) -> (along, inward) coordinates: along from the midpoint,
        inward from the wall's line."""
        rel = np.asarray(points, float) - self.midpoint
        out = np.empty((*rel.shape[:-1], 2))
        out[..., 0] = rel @ self.direction
        out[..., 1] = rel @ self.normal
        return out

    def extent(self, box: OrientedBox) -> tuple[float, float]:
        """(lo, hi) along the wall, from its midpoint, that ``box``'s footprint covers."""
        along = self.local(box.corners()[:, :2])[:, 0]
        return float(along.min()), float(along.max())

    def span(self, p0, p1, tol: float = 0.05) -> tuple[float, float] | None:
        """(lo, hi) along the wall, from its midpoint, that the segment ``p0``-``p1`` (a
        door, a window) covers when it lies on the wall (both ends within ``tol`` m of
        its line); None when it does not."""
        ends = self.local(np.array([p0, p1], float))
        if np.abs(ends[:, 1]).max() > tol:
            return None
        return float(ends[:, 0].min()), float(ends[:, 0].max())

    def to_dict(self) -> dict:
        return {"index": self.index, "p0": self.p0.tolist(), "p1": self.p1.tolist()}


def walls_of(polygon: np.ndarray, min_length: float = 1e-3) -> list[Wall]:
    """The walls of a floor polygon (N, 2), counter-clockwise (as :class:`Room` keeps it);
    edges shorter than ``min_length`` (repeated vertices) are left out."""
    poly = np.asarray(polygon, float)
    out = []
    for i in range(len(poly)):
        p0, p1 = poly[i], poly[(i + 1) % len(poly)]
        if np.linalg.norm(p1 - p0) >= min_length:
            out.append(Wall(i, p0.copy(), p1.copy()))
    return out


@dataclass(frozen=True)
class WallContact:
    """How an object stands against a wall."""

    wall: int
    """The wall's index (:attr:`Wall.index`)."""
    face: str
    """Which face is against it (:data:`FACES`)."""
    gap: float
    """Distance from that face to the wall (m; negative: through it)."""
    angle: float
    """Degrees between the face and the wall."""
    offset: float
    """Position of the object's centre along the wall, from its midpoint (m)."""

    def to_dict(self) -> dict:
        return {"wall": self.wall, "face": self.face, "gap": round(self.gap, 4),
                "angle": round(self.angle, 2), "offset": round(self.offset, 4)}  # fmt: skip


def face_contacts(
    box: OrientedBox,
    walls: list[Wall],
    max_gap: float = AGAINST_GAP_M,
    max_angle: float = AGAINST_ANGLE_DEG,
    min_overlap: float = MIN_OVERLAP,
    faces: tuple[str, ...] = FACES,
) -> list[WallContact]:
    """Every (face, wall) pair of ``box`` that stands against each other, closest first;
    only the ``faces`` asked."""
    rot = box.rotation[:2, :2]
    half = box.half_size
    center = box.center[:2]
    # Below this cosine the angle is over max_angle for certain (arccos is monotone and
    # exact to an ulp): the exact test below runs only on faces near the limit or inside.
    cos_floor = math.cos(math.radians(max_angle)) - 1e-9 if max_angle < 180 else -math.inf
    out = []
    for face, local_normal in _FACE_NORMALS.items():
        if face not in faces:
            continue
        n = rot @ local_normal  # outward normal of the face, world xy
        n_len = float(np.linalg.norm(n))
        if n_len < 0.5:  # not upright enough to have vertical faces
            continue
        n = n / n_len
        across = FACE_AXES[face][0]  # local axis the face is normal to
        along_axis = 1 - across
        face_center = center + n * half[across]
        face_dir = rot[:, along_axis] / max(float(np.linalg.norm(rot[:, along_axis])), 1e-12)
        face_half = half[along_axis]
        for wall in walls:
            # the face looks at the wall: its outward normal opposes the inward normal
            cos = float(-n @ wall.normal)
            if cos < cos_floor:
                continue
            angle = float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
            if angle > max_angle:
                continue
            along, inward = wall.local(face_center)
            if inward > max_gap or inward < -max_gap:
                continue
            extent = abs(float(face_dir @ wall.direction)) * face_half
            lo, hi = along - extent, along + extent
            overlap = min(hi, wall.length / 2) - max(lo, -wall.length / 2)
            if overlap < min_overlap * max(hi - lo, 1e-6):
                continue
            offset = float(wall.local(center)[0])
            out.append(WallContact(wall.index, face, float(inward), angle, offset))
    out.sort(key=lambda c: (abs(c.gap), FACES.index(c.face)))
    return out


def walls_near(box: OrientedBox, walls: list[Wall], max_gap: float = AGAINST_GAP_M) -> set[int]:
    """Indices of the walls ``box``'s footprint comes within ``max_gap`` of (or reaches
    into by up to :data:`EMBEDDED_M`), over their length, whatever the angle between
    them: where an object whose turn means nothing (a round pot) stands by a wall."""
    corners = box.corners()[:, :2]
    out = set()
    for wall in walls:
        along, inward = wall.local(corners).T
        half = wall.length / 2
        if -EMBEDDED_M <= inward.min() <= max_gap and along.max() > -half and along.min() < half:
            out.add(wall.index)
    return out


def in_corner(box: OrientedBox, walls: list[Wall], max_gap: float = AGAINST_GAP_M) -> bool:
    """Whether ``box`` stands in a corner: faces of it against two different walls."""
    return len({c.wall for c in face_contacts(box, walls, max_gap)}) >= 2


def convex_ends(walls: list[Wall]) -> dict[int, tuple[bool, bool]]:
    """Wall index -> whether its start and its end are convex corners of the room (the
    neighbouring wall turns into the room there, as in every corner of a rectangle; the
    inner corner of an L-shaped room is not one): where an object can stand against
    both walls. Walls meet where one's end is the next one's start."""
    out = {}
    for w in walls:
        start = end = False
        for other in walls:
            if other is w:
                continue
            if np.allclose(other.p1, w.p0, atol=1e-6):
                start = float(other.normal @ -w.direction) < -1e-6
            if np.allclose(other.p0, w.p1, atol=1e-6):
                end = float(other.normal @ w.direction) < -1e-6
        out[w.index] = (start, end)
    return out


def wall_contact(
    box: OrientedBox,
    walls: list[Wall],
    max_gap: float = AGAINST_GAP_M,
    max_angle: float = AGAINST_ANGLE_DEG,
) -> WallContact | None:
    """The wall ``box`` stands against, preferring its back (facing into the room), else
    the closest face; None when no face is against a wall."""
    contacts = face_contacts(box, walls, max_gap, max_angle)
    if not contacts:
        return None
    backs = [c for c in contacts if c.face == "back"]
    return backs[0] if backs else contacts[0]


def against_wall(
    box: OrientedBox,
    walls: list[Wall],
    max_gap: float = AGAINST_GAP_M,
    max_angle: float = AGAINST_ANGLE_DEG,
) -> bool:
    """Whether ``box``'s back face stands against a wall, facing into the room: within
    ``max_gap`` of it, or beyond its plane by up to :data:`EMBEDDED_M` (a box that reaches
    into the wall)."""
    reach = max(max_gap, EMBEDDED_M)
    backs = face_contacts(box, walls, reach, max_angle, faces=("back",))
    return any(c.gap <= max_gap for c in backs)
