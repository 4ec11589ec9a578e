"""Navigable rooms: can an agent walk in by a door and reach the free floor and the
objects' fronts?

The floor is rasterised into square cells of :attr:`NavigationConfig.resolution_m`
(row ``j`` along world y, column ``i`` along world x; a cell is judged by its centre).
An *obstacle* is every object standing on the floor (support ``floor``, or a box bottom
below :attr:`NavigationConfig.clearance_m`); its whole footprint (the convex hull of its
box seen from above) blocks, even a table's an agent could crawl under: conservative, and
what a wheeled robot sees. Objects resting on others lie inside their support's footprint.

The agent is a disc of :attr:`NavigationConfig.agent_radius_m`. A cell is *free* for the
agent's centre when its centre is over the floor polygon, farther than the radius from
every wall (edge of the polygon) and from every obstacle's footprint. Distances are exact
(point to segment, point to convex polygon), not a grid erosion, so the free space is the
agent's configuration space sampled at the cell centres.

Free cells are joined 4-connected (a step to a side neighbour): a diagonal step between
two cells whose shared side neighbours are both blocked could squeeze through a sliver
that a disc cannot pass, so 8-connectivity would overstate reachability.

The agent enters through the doors: the *start* cells of a door are the free cells over
its width and at most ``agent radius + 2 cells`` inward from the wall line (the door's
midpoint moved inward by the radius plus a cell, widened to the door's width so a chair
leg off the door's centre line does not shut the door). Reachable cells are the free
components holding a start cell; a room without a door starts from its largest free
component.

Measures (:class:`Navigability`):

- ``reachable_fraction``: reachable free cells / free cells (the agent's centre);
- ``swept_fraction``: the share of the uncovered floor (floor cells under no obstacle)
  the agent's body sweeps from a reachable centre (reachable cells dilated by the radius):
  the "raw floor" figure, which counts the strip along the walls a centre cannot enter;
- ``reachable_objects``: the share of floor objects (supported by the floor, parts left
  out) whose front can be reached: a reachable cell in front of the front face (+y side)
  and within ``agent radius + front_reach_m`` of it (rounded at the face's ends). When
  another obstacle's footprint covers at least half of the thin strip
  (:data:`AGAINST_STRIP_M`) just in front of the face, the front is against something
  (a chair pushed under its table or desk, a stool under a counter): then either side
  face counts as well. A wall in front does not (a bed facing a wall 0.1 m away cannot be
  used from its front, and nothing else stands there for it). Small objects (footprint's
  longer side at most :attr:`NavigationConfig.any_side_below_m`: plants, lamps, bins,
  chairs) count from any face: their front is arbitrary or they are pulled out;
- ``door_clear``: every door's swing (a square of the door's width on the inward side,
  or :attr:`NavigationConfig.door_swing_m` deep) holds no obstacle (footprints
  overlapping it by more than :data:`OVERLAP_TOL_M`).

:class:`FloorGuard` is the same test kept up to date while a scene is placed, for the
placer: ``add`` an accepted floor object, ask ``blocks`` of a candidate. Its cost per
candidate is one 4-connected labelling of the grid (``scipy.ndimage.label``, a project
dependency), and only when the candidate's grown footprint touches reachable floor:
0.3 ms median on a 5 x 5 m room at 0.05 m, about 0.6 ms on the generated 10-68 m2 rooms.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from pair2scene.errors import UserError, check_ranges
from pair2scene.scene.geometry import (
    OrientedBox,
    convex_hull_2d,
    following,
    points_in_polygon,
    polygon_area,
)
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject
from pair2scene.scene.walls import walls_of

AGAINST_STRIP_M = 0.1
"""Depth of the strip in front of a face that, half covered by another obstacle, puts
the face against that object (sides then count for the object's reachability)."""
OVERLAP_TOL_M = 0.01
"""A footprint must overlap a door's swing by more than this to block it (a box flush
with the swing's edge does not)."""
WELL_REACHED = 0.97
"""A room counts as navigable in :func:`navigation_report` from this reachable fraction."""
_CROSS = ndimage.generate_binary_structure(2, 1)  # 4-connectivity


MIN_RESOLUTION_M = 0.01
"""Finest floor cell :class:`NavigationConfig` accepts (a 20 x 20 m apartment: 4 million
cells)."""


@dataclass(frozen=True)
class NavigationConfig:
    """How navigability is measured and guarded."""

    agent_radius_m: float = 0.2
    """Radius of the agent's disc, up to 2 m: free floor keeps its centre this far from
    walls and obstacles, so gaps narrower than twice it are closed."""
    resolution_m: float = 0.05
    """Side of a floor cell, 0.01 .. 0.5. Reachability is exact at the cell centres; a gap
    within a cell of twice the radius may go either way."""
    clearance_m: float = 0.05
    """Objects whose box bottom is below this (or whose support is the floor) are
    obstacles; higher ones (on furniture, on walls) are not."""
    front_reach_m: float = 0.3
    """An object's front is reachable from a reachable cell this far beyond the agent's
    radius from its front face (an arm's reach)."""
    door_swing_m: float | None = None
    """Depth of a door's swing, inward from the wall; none: the door's width (a square)."""
    min_cut_area_m2: float = 0.25
    """:class:`FloorGuard`: a candidate may leave at most this much previously reachable
    free floor cut off (pockets in corners and between legs are fine; 0.25 m2 is a square
    half a metre on a side, the least floor an agent can stand and turn in: 2.5 x its
    0.2 m radius)."""
    min_reachable_share: float = WELL_REACHED
    """:class:`FloorGuard`: a candidate that cuts any floor off may not bring the room's
    reachable share of free floor (``reachable_fraction``) below this, nor lower than it
    was when it already was (a room whose shape alone leaves pockets): small pockets add
    up in a small room. A C-shaped counter run in a 9 m2 kitchen closed 0.24 m2, under
    ``min_cut_area_m2`` but 9 % of its free floor (seed 22 of the docs/results.md
    kitchens, 0.913 reachable). 0 turns this off."""
    any_side_below_m: float = 0.6
    """A floor object whose footprint's longer side is at most this (a plant, a lamp, a
    bin, a stool, a chair) is reachable from any face: such things have no front to speak
    of, or are pulled out from where one stands (0: fronts only)."""
    protect_fronts: bool = True
    """:class:`FloorGuard`: a candidate may not cut off the front of an object placed
    before it (a desk shutting a wardrobe)."""

    def __post_init__(self) -> None:
        def flag(name: str) -> str:
            return "--assembly.navigation." + name.replace("_", "-")

        positive = {"agent_radius_m": self.agent_radius_m, "resolution_m": self.resolution_m}
        non_negative = {"clearance_m": self.clearance_m, "front_reach_m": self.front_reach_m,
                        "any_side_below_m": self.any_side_below_m,
                        "min_cut_area_m2": self.min_cut_area_m2}  # fmt: skip
        check_ranges("--assembly.navigation.", positive, non_negative)
        if not 0.0 <= self.min_reachable_share <= 1.0:  # (NaN fails too)
            raise UserError(f"{flag('min_reachable_share')} must be in [0, 1], "
                            f"got {self.min_reachable_share}")  # fmt: skip
        if self.agent_radius_m > 2.0:  # wider than most rooms: no floor would be free
            raise UserError(f"{flag('agent_radius_m')} must be at most 2.0, "
                            f"got {self.agent_radius_m}")  # fmt: skip
        if not MIN_RESOLUTION_M <= self.resolution_m <= 0.5:
            # Below a centimetre the grid of a large room outgrows memory (1e-9 m asked for
            # 60 GiB of cell centres) for nothing an agent of centimetres could tell.
            raise UserError(f"{flag('resolution_m')} must be in {MIN_RESOLUTION_M} .. 0.5, "
                            f"got {self.resolution_m}")  # fmt: skip
        if self.door_swing_m is not None and not (
            np.isfinite(self.door_swing_m) and self.door_swing_m >= 0
        ):
            raise UserError(f"{flag('door_swing_m')} must be >= 0 or none, got {self.door_swing_m}")


# -- geometry on the grid ------------------------------------------------------------


def footprint_polygon(box: OrientedBox) -> np.ndarray:
    """(K, 2) counter-clockwise convex footprint of a box seen from above."""
    rot = box.rotation
    if abs(rot[2, 2]) > 1 - 1e-9:  # upright (or upside down): a rectangle
        hx, hy = box.half_size[:2]
        local = np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])
        pts = local @ rot[:2, :2].T + box.center[:2]
        return pts if polygon_area(pts) >= 0 else pts[::-1].copy()
    return np.array(convex_hull_2d(box.corners()[:, :2]), dtype=float)


def _segment_distance(px: np.ndarray, py: np.ndarray, a: np.ndarray, b: np.ndarray):
    """Distance of points (broadcast px, py) to segment a-b."""
    d = b - a
    dd = max(float(d @ d), 1e-18)
    t = np.clip(((px - a[0]) * d[0] + (py - a[1]) * d[1]) / dd, 0.0, 1.0)
    return np.hypot(px - a[0] - t * d[0], py - a[1] - t * d[1])


def _polygon_distance(px: np.ndarray, py: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance of points to a convex counter-clockwise polygon (0 inside)."""
    inside = np.ones(np.broadcast(px, py).shape, bool)
    dist = np.full(inside.shape, np.inf)
    for k in range(len(poly)):
        a, b = poly[k], poly[(k + 1) % len(poly)]
        inside &= (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]) >= 0
        dist = np.minimum(dist, _segment_distance(px, py, a, b))
    if len(poly) < 3:
        inside[:] = False
    return np.where(inside, 0.0, dist)


def _overlap_depth(p: np.ndarray, q: np.ndarray) -> float:
    """Least penetration of two convex polygons over their edge normals (<= 0: apart)."""
    depth = np.inf
    for poly in (p, q):
        edges = following(poly) - poly
        normals = np.stack([-edges[:, 1], edges[:, 0]], 1)
        norms = np.linalg.norm(normals, axis=1)
        normals = normals[norms > 1e-12] / norms[norms > 1e-12, None]
        if not len(normals):
            continue
        a, b = p @ normals.T, q @ normals.T
        over = np.minimum(a.max(0), b.max(0)) - np.maximum(a.min(0), b.min(0))
        depth = min(depth, float(over.min()))
    return depth


@dataclass
class _Grid:
    origin: np.ndarray
    res: float
    shape: tuple[int, int]
    """(rows along y, columns along x)."""
    xs: np.ndarray
    ys: np.ndarray

    @classmethod
    def of(cls, polygon: np.ndarray, res: float) -> _Grid:
        lo, hi = polygon.min(0), polygon.max(0)
        nx = max(int(np.ceil((hi[0] - lo[0]) / res - 1e-9)), 1)
        ny = max(int(np.ceil((hi[1] - lo[1]) / res - 1e-9)), 1)
        xs = lo[0] + (np.arange(nx) + 0.5) * res
        ys = lo[1] + (np.arange(ny) + 0.5) * res
        return cls(lo, res, (ny, nx), xs, ys)

    def window(self, lo: np.ndarray, hi: np.ndarray) -> tuple[slice, slice] | None:
        """Rows and columns of the cells whose centres lie in [lo, hi] (None: none)."""
        i0 = max(int(np.ceil((lo[0] - self.origin[0]) / self.res - 0.5)), 0)
        i1 = min(int(np.floor((hi[0] - self.origin[0]) / self.res - 0.5)), self.shape[1] - 1)
        j0 = max(int(np.ceil((lo[1] - self.origin[1]) / self.res - 0.5)), 0)
        j1 = min(int(np.floor((hi[1] - self.origin[1]) / self.res - 0.5)), self.shape[0] - 1)
        if i0 > i1 or j0 > j1:
            return None
        return slice(j0, j1 + 1), slice(i0, i1 + 1)

    def centres(self, win: tuple[slice, slice]) -> tuple[np.ndarray, np.ndarray]:
        """Broadcastable (rows, 1) y and (1, cols) x of a window's cell centres."""
        return self.xs[win[1]][None, :], self.ys[win[0]][:, None]

    def near(self, poly: np.ndarray, within: float):
        """(window, bool mask) of the cells within ``within`` of a convex polygon."""
        win = self.window(poly.min(0) - within, poly.max(0) + within)
        if win is None:
            return None, None
        px, py = self.centres(win)
        return win, _polygon_distance(px, py, poly) <= within + 1e-9

    def near_box(self, box: OrientedBox, within: float, poly: np.ndarray | None = None):
        """(window, bool mask) of the cells within ``within`` of a box's footprint; an
        upright box's distances in its own frame (one pass), others' by the hull."""
        poly = footprint_polygon(box) if poly is None else poly
        if abs(box.rotation[2, 2]) <= 1 - 1e-9:
            return self.near(poly, within)
        win = self.window(poly.min(0) - within, poly.max(0) + within)
        if win is None:
            return None, None
        px, py = self.centres(win)
        ax, ay = box.rotation[:2, 0], box.rotation[:2, 1]
        dx, dy = px - box.center[0], py - box.center[1]
        qx = np.maximum(np.abs(dx * ax[0] + dy * ax[1]) - box.half_size[0], 0.0)
        qy = np.maximum(np.abs(dx * ay[0] + dy * ay[1]) - box.half_size[1], 0.0)
        return win, qx * qx + qy * qy <= (within + 1e-9) ** 2

    def all_centres(self) -> tuple[np.ndarray, np.ndarray]:
        return self.xs[None, :], self.ys[:, None]


@dataclass(frozen=True)
class _Door:
    index: int
    id: str | None
    mid: np.ndarray
    along: np.ndarray
    inward: np.ndarray
    width: float
    swing: np.ndarray
    """(4, 2) the swing's square, counter-clockwise."""


def _doors(room: Room, swing_depth: float | None, probe: float) -> list[_Door]:
    """The doors with their inward normal: the nearest wall's, flipped when a point
    ``probe`` inward of the midpoint is not over the floor."""
    walls = walls_of(room.floor_polygon)
    out = []
    for k, door in enumerate(room.doors):
        p0, p1 = np.asarray(door.p0, float), np.asarray(door.p1, float)
        width = float(np.linalg.norm(p1 - p0))
        if width < 1e-6 or not walls:
            continue
        along = (p1 - p0) / width
        mid = (p0 + p1) / 2
        dist = [float(_segment_distance(mid[0], mid[1], w.p0, w.p1)) for w in walls]
        inward = np.array([-along[1], along[0]])
        if inward @ walls[int(np.argmin(dist))].normal < 0:
            inward = -inward
        inside = room.contains_xy(np.array([mid + probe * inward, mid - probe * inward]))
        if not inside[0] and inside[1]:
            inward = -inward
        depth = width if swing_depth is None else swing_depth
        half = along * width / 2
        swing = np.array([mid - half, mid + half, mid + half + depth * inward,
                          mid - half + depth * inward])  # fmt: skip
        e0, e1 = swing[1] - swing[0], swing[2] - swing[1]
        if e0[0] * e1[1] - e0[1] * e1[0] < 0:
            swing = swing[::-1].copy()
        out.append(_Door(k, door.id, mid, along, inward, width, swing))
    return out


def _face_frame(box: OrientedBox):
    """Unit world xy of the box's local x and y, and its half sizes along them."""
    ax, ay = box.rotation[:2, 0], box.rotation[:2, 1]
    nx, ny = max(float(np.linalg.norm(ax)), 1e-12), max(float(np.linalg.norm(ay)), 1e-12)
    return ax / nx, ay / ny, box.half_size[0] * nx, box.half_size[1] * ny


def _face_band(grid: _Grid, box: OrientedBox, face: str, reach: float, strip: float):
    """(window, band mask, strip mask) of one vertical face (``front`` +y, ``back`` -y,
    ``left`` -x, ``right`` +x); window None when off the grid. The band is the cells beyond
    the face within ``reach`` of it (rounded at its ends); the strip the cells beyond it
    within ``strip`` of its plane, across its width."""
    ax, ay, hx, hy = _face_frame(box)
    normal, tangent, h_n, h_t = {
        "front": (ay, ax, hy, hx),
        "back": (-ay, ax, hy, hx),
        "left": (-ax, ay, hx, hy),
        "right": (ax, ay, hx, hy),
    }[face]
    c = box.center[:2]
    f0 = c + normal * h_n - tangent * h_t
    f1 = c + normal * h_n + tangent * h_t
    pts = np.array([f0, f1])
    win = grid.window(pts.min(0) - reach, pts.max(0) + reach)
    if win is None:
        return None, None, None
    px, py = grid.centres(win)
    u = (px - c[0]) * tangent[0] + (py - c[1]) * tangent[1]
    v = (px - c[0]) * normal[0] + (py - c[1]) * normal[1] - h_n
    d = np.hypot(np.maximum(np.abs(u) - h_t, 0.0), v)
    band = (v > 0) & (d <= reach)
    return win, band, (v > 0) & (v <= strip) & (np.abs(u) <= h_t)


class _Faces:
    """An object's face bands on a grid (:func:`_face_band`), computed once when asked."""

    def __init__(self, grid: _Grid, box: OrientedBox, reach: float):
        self.grid, self.box, self.reach = grid, box, reach
        _, _, hx, hy = _face_frame(box)
        self.longest = 2 * max(hx, hy)
        self._bands: dict[str, tuple] = {}

    def __getitem__(self, face: str) -> tuple:
        if face not in self._bands:
            self._bands[face] = _face_band(self.grid, self.box, face, self.reach,
                                           AGAINST_STRIP_M)  # fmt: skip
        return self._bands[face]


def is_obstacle(obj: SceneObject, clearance: float = 0.05) -> bool:
    """Whether an object blocks the floor: supported by it, or its bottom below
    ``clearance``."""
    return obj.support == FLOOR or obj.box.bottom < clearance


# -- the floor state -------------------------------------------------------------------


class _Floor:
    """Rasters of one room: floor, walls, obstacles, start cells."""

    def __init__(self, room: Room, config: NavigationConfig):
        self.room, self.cfg = room, config
        r, res = config.agent_radius_m, config.resolution_m
        poly = room.floor_polygon
        self.grid = _Grid.of(poly, res)
        px, py = self.grid.all_centres()
        pts = np.stack(np.broadcast_arrays(px, py), -1).reshape(-1, 2)
        self.floor = points_in_polygon(pts, poly).reshape(self.grid.shape)
        wall_d = np.full(self.grid.shape, np.inf)
        for w in walls_of(poly):
            wall_d = np.minimum(wall_d, _segment_distance(px, py, w.p0, w.p1))
        self.static_free = self.floor & (wall_d > r)
        self.occupied = np.zeros(self.grid.shape, bool)  # raw footprints
        self.blocked = np.zeros(self.grid.shape, bool)  # footprints grown by the radius
        self.doors = _doors(room, config.door_swing_m, r + res)
        self.start = np.zeros(self.grid.shape, bool)
        for door in self.doors:
            u = (px - door.mid[0]) * door.along[0] + (py - door.mid[1]) * door.along[1]
            v = (px - door.mid[0]) * door.inward[0] + (py - door.mid[1]) * door.inward[1]
            self.start |= (np.abs(u) <= door.width / 2) & (v >= 0) & (v <= r + 2 * res)

    def add(self, box: OrientedBox) -> None:
        poly = footprint_polygon(box)
        win, mask = self.grid.near_box(box, self.cfg.agent_radius_m, poly)
        if win is not None:
            self.blocked[win] |= mask
        win, mask = self.grid.near_box(box, 0.0, poly)
        if win is not None:
            self.occupied[win] |= mask

    @property
    def free(self) -> np.ndarray:
        return self.static_free & ~self.blocked

    def reachable(self, free: np.ndarray, from_doors: bool = True) -> np.ndarray:
        """The free cells 4-connected to a door's start cells (with no door, or
        ``from_doors`` False: the largest free component)."""
        labels, n = ndimage.label(free, _CROSS)
        if n == 0:
            return np.zeros_like(free)
        keep = np.zeros(n + 1, bool)
        if self.doors and from_doors:
            keep[labels[self.start & free]] = True
        else:
            keep[int(np.argmax(np.bincount(labels.ravel())[1:])) + 1] = True
        keep[0] = False
        return keep[labels]

    def faces(self, box: OrientedBox) -> _Faces:
        return _Faces(self.grid, box, self.cfg.agent_radius_m + self.cfg.front_reach_m)

    def face_reachable(self, faces: _Faces, reach: np.ndarray, occupied: np.ndarray):
        """(reachable?, only by a side or the back?): the front, else, when the box is
        small (:attr:`NavigationConfig.any_side_below_m`) or its front is against an
        object, its sides (and a small box's back)."""
        win, band, strip = faces["front"]
        if win is not None and (reach[win] & band).any():
            return True, False
        small = faces.longest <= self.cfg.any_side_below_m
        against = win is not None and strip.any() and occupied[win][strip].mean() >= 0.5
        if not (small or against):
            return False, False
        for face in ("left", "right", "back") if small else ("left", "right"):
            win, band, _ = faces[face]
            if win is not None and (reach[win] & band).any():
                return True, True
        return False, False


# -- measures --------------------------------------------------------------------------


@dataclass(frozen=True)
class Navigability:
    """How navigable one room is (see the module docstring for each measure)."""

    reachable_fraction: float
    """Reachable free cells / free cells for the agent's centre (0 with no free cell)."""
    swept_fraction: float
    """Share of the uncovered floor the agent's body sweeps from reachable centres."""
    free_floor_fraction: float
    """Share of the floor no obstacle covers."""
    reachable_objects: float
    """Share of floor objects whose front (or, against an object, a side) is reachable
    (1 with no floor object)."""
    door_clear: bool
    """Every door's swing holds no obstacle (True with no door)."""
    n_objects: int
    """Floor objects judged: obstacles supported by the floor (or by nothing known), not
    parts."""
    n_doors: int
    free_area_m2: float
    reachable_area_m2: float
    unreachable: tuple[str, ...] = ()
    """Ids of the floor objects whose front cannot be reached."""
    by_side: tuple[str, ...] = ()
    """Ids reached only by another face than the front (front against another object, or
    a small object)."""
    blocked_doors: tuple[int, ...] = ()
    """Indices (in ``room.doors``) of doors whose swing holds an obstacle."""
    door_blockers: tuple[str, ...] = ()
    """Ids of the objects in a door's swing."""
    start: str = "door"
    """``door`` (from the doors) or ``largest`` (no door: the largest free component)."""

    def to_dict(self) -> dict:
        return {
            "reachable_fraction": round(self.reachable_fraction, 4),
            "swept_fraction": round(self.swept_fraction, 4),
            "free_floor_fraction": round(self.free_floor_fraction, 4),
            "reachable_objects": round(self.reachable_objects, 4),
            "door_clear": self.door_clear,
            "n_objects": self.n_objects,
            "n_doors": self.n_doors,
            "free_area_m2": round(self.free_area_m2, 3),
            "reachable_area_m2": round(self.reachable_area_m2, 3),
            "unreachable": list(self.unreachable),
            "by_side": list(self.by_side),
            "blocked_doors": list(self.blocked_doors),
            "door_blockers": list(self.door_blockers),
            "start": self.start,
        }


def _config(config, agent_radius, resolution) -> NavigationConfig:
    cfg = config or NavigationConfig()
    changes = {}
    if agent_radius is not None:
        changes["agent_radius_m"] = float(agent_radius)
    if resolution is not None:
        changes["resolution_m"] = float(resolution)
    if changes:
        cfg = dataclasses.replace(cfg, **changes)
    return cfg


def navigability(
    room: Room,
    objects: Iterable[SceneObject],
    agent_radius: float | None = None,
    resolution: float | None = None,
    config: NavigationConfig | None = None,
) -> Navigability:
    """How navigable ``room`` is with ``objects`` in it. ``agent_radius`` and
    ``resolution`` (m) override ``config``'s (defaults 0.2 and 0.05)."""
    cfg = _config(config, agent_radius, resolution)
    fl = _Floor(room, cfg)
    floor_objs = [o for o in objects if is_obstacle(o, cfg.clearance_m)]
    for o in floor_objs:
        fl.add(o.box)
    free = fl.free
    reach = fl.reachable(free)
    cell = cfg.resolution_m**2
    n_free, n_reach = int(free.sum()), int(reach.sum())
    open_floor = fl.floor & ~fl.occupied
    if n_reach:
        dist = ndimage.distance_transform_edt(~reach, sampling=cfg.resolution_m)
        swept = (dist <= cfg.agent_radius_m + 1e-9) & open_floor
    else:
        swept = np.zeros_like(reach)
    n_open, n_floor = int(open_floor.sum()), int(fl.floor.sum())

    # judged: what stands on the floor itself (a book resting low on a flat support blocks
    # within the support's footprint, but is not a floor object); parts go with their whole
    judged = [o for o in floor_objs if o.support in (FLOOR, None) and o.part_of is None]
    unreachable, by_side = [], []
    for o in judged:
        # (an object's own footprint never meets the strip beyond its faces)
        ok, side = fl.face_reachable(fl.faces(o.box), reach, fl.occupied)
        if not ok:
            unreachable.append(o.id)
        elif side:
            by_side.append(o.id)

    blocked_doors, blockers = [], []
    polys = [(o.id, footprint_polygon(o.box)) for o in floor_objs]
    for door in fl.doors:
        hit = [oid for oid, p in polys if _overlap_depth(p, door.swing) > OVERLAP_TOL_M]
        if hit:
            blocked_doors.append(door.index)
            blockers.extend(h for h in hit if h not in blockers)
    return Navigability(
        reachable_fraction=n_reach / n_free if n_free else 0.0,
        swept_fraction=float(swept.sum()) / n_open if n_open else 0.0,
        free_floor_fraction=n_open / n_floor if n_floor else 0.0,
        reachable_objects=1.0 - len(unreachable) / len(judged) if judged else 1.0,
        door_clear=not blocked_doors,
        n_objects=len(judged),
        n_doors=len(fl.doors),
        free_area_m2=n_free * cell,
        reachable_area_m2=n_reach * cell,
        unreachable=tuple(unreachable),
        by_side=tuple(by_side),
        blocked_doors=tuple(blocked_doors),
        door_blockers=tuple(blockers),
        start="door" if fl.doors else "largest",
    )


def _pool(rows: list[Navigability]) -> dict:
    if not rows:
        return {"rooms": 0}
    frac = np.array([r.reachable_fraction for r in rows])
    n_obj = sum(r.n_objects for r in rows)
    n_bad = sum(len(r.unreachable) for r in rows)
    with_doors = [r for r in rows if r.n_doors]
    return {
        "rooms": len(rows),
        "mean_reachable_fraction": round(float(frac.mean()), 4),
        "median_reachable_fraction": round(float(np.median(frac)), 4),
        "share_rooms_reachable": round(float((frac >= WELL_REACHED).mean()), 4),
        "mean_swept_fraction": round(float(np.mean([r.swept_fraction for r in rows])), 4),
        "mean_free_floor_fraction": round(float(np.mean([r.free_floor_fraction for r in rows])), 4),
        "floor_objects": n_obj,
        "unreachable_objects": n_bad,
        "share_objects_reachable": round(1 - n_bad / n_obj, 4) if n_obj else 1.0,
        "rooms_with_doors": len(with_doors),
        "share_doors_clear": (
            round(float(np.mean([r.door_clear for r in with_doors])), 4) if with_doors else None
        ),
    }


def navigation_report(scenes: Iterable[Scene], config: NavigationConfig | None = None) -> dict:
    """Navigability pooled over scenes: every figure of :func:`_pool` over all rooms
    (``all``) and per room type (``by_room_type``); a room counts as reachable from a
    reachable fraction of :data:`WELL_REACHED`."""
    rows: dict[str, list[Navigability]] = {}
    every = []
    for scene in scenes:
        nav = navigability(scene.room, scene.objects, config=config)
        rows.setdefault(scene.room.type, []).append(nav)
        every.append(nav)
    cfg = config or NavigationConfig()
    return {
        "agent_radius_m": cfg.agent_radius_m,
        "resolution_m": cfg.resolution_m,
        "reachable_threshold": WELL_REACHED,
        "all": _pool(every),
        "by_room_type": {k: _pool(v) for k, v in sorted(rows.items())},
    }


# -- the placement guard -----------------------------------------------------------------


@dataclass
class _Front:
    faces: _Faces
    reachable: bool


@dataclass
class FloorGuard:
    """Keeps the free floor of a room being placed, and tells whether a floor candidate
    would spoil it (:meth:`reason`). Build once per scene, :meth:`add` every accepted floor
    object (and every kept one), ask :meth:`blocks` of each floor candidate that passed
    the other tests."""

    room: Room
    config: NavigationConfig = field(default_factory=NavigationConfig)

    def __post_init__(self) -> None:
        self._floor = _Floor(self.room, self.config)
        self._fronts: list[_Front] = []
        self.door_shut = False
        """True when the doors let no agent in (too narrow a way in, or a kept object in
        it): the guard then keeps the largest free part of the floor connected instead,
        rather than refusing every floor candidate."""
        self._reach = self._reachable(self._floor.free)

    def _reachable(self, free: np.ndarray) -> np.ndarray:
        reach = self._floor.reachable(free, from_doors=not self.door_shut)
        if not reach.any() and self._floor.doors and not self.door_shut:
            self.door_shut = True
            reach = self._floor.reachable(free, from_doors=False)
        return reach

    @classmethod
    def for_room(
        cls,
        room: Room,
        agent_radius: float | None = None,
        resolution: float | None = None,
        door_clearance: float | None = None,
        config: NavigationConfig | None = None,
    ) -> FloorGuard:
        """A guard with ``config``'s settings, ``agent_radius``, ``resolution`` and
        ``door_clearance`` (the swing's depth, m) overriding them when given."""
        cfg = _config(config, agent_radius, resolution)
        if door_clearance is not None:
            cfg = dataclasses.replace(cfg, door_swing_m=float(door_clearance))
        return cls(room, cfg)

    @property
    def reachable_area_m2(self) -> float:
        return float(self._reach.sum()) * self.config.resolution_m**2

    def add(self, box: OrientedBox) -> None:
        """An accepted floor object becomes an obstacle (only its footprint is rastered)."""
        fl = self._floor
        fl.add(box)
        self._reach = self._reachable(fl.free)
        faces = fl.faces(box)
        reachable, _ = fl.face_reachable(faces, self._reach, fl.occupied)
        self._fronts.append(_Front(faces, reachable))

    def blocks(self, box: OrientedBox) -> bool:
        """Whether adding ``box`` would spoil the floor (:meth:`reason` is not None)."""
        return self.reason(box) is not None

    @staticmethod
    def _share(reach: np.ndarray, free: np.ndarray) -> float:
        """Reachable share of the free cells, as ``reachable_fraction`` counts it, but 1
        with no free cell (nothing left to cut off; ``reachable_fraction`` reads 0)."""
        n = np.count_nonzero(free)
        return np.count_nonzero(reach) / n if n else 1.0

    def reason(self, box: OrientedBox) -> str | None:
        """Why ``box`` may not stand on the floor, or None:

        - ``door``: its footprint overlaps a door's swing;
        - ``cut``: it cuts more than ``min_cut_area_m2`` of reachable free floor off the
          doors, or cuts some off and leaves less than ``min_reachable_share`` of the
          free floor reachable;
        - ``front``: its own front (or a side, against an object) would be out of reach;
        - ``front_of_other``: it cuts off the front of an object placed before
          (``protect_fronts``).
        """
        fl, cfg = self._floor, self.config
        poly = footprint_polygon(box)
        for door in fl.doors:
            if _overlap_depth(poly, door.swing) > OVERLAP_TOL_M:
                return "door"
        win, grown = fl.grid.near_box(box, cfg.agent_radius_m, poly)
        reach = after = self._reach
        if win is not None and (reach[win] & grown).any():
            free = fl.free
            free[win] &= ~grown
            after = fl.reachable(free, from_doors=not self.door_shut)
            lost = reach & ~after
            lost[win] &= ~grown  # under the candidate itself: covered, not cut off
            cut = np.count_nonzero(lost)
            if cut * cfg.resolution_m**2 > cfg.min_cut_area_m2:
                return "cut"
            if cut:  # (the room's share as it stands: a kept object may have lowered it)
                floor = min(cfg.min_reachable_share, self._share(reach, fl.free))
                if self._share(after, free) < floor:
                    return "cut"
        if not fl.face_reachable(fl.faces(box), after, fl.occupied)[0]:
            return "front"
        if cfg.protect_fronts and after is not reach:
            occupied = fl.occupied.copy()
            owin, own = fl.grid.near_box(box, 0.0, poly)
            if owin is not None:
                occupied[owin] |= own
            for front in self._fronts:
                if front.reachable and not fl.face_reachable(front.faces, after, occupied)[0]:
                    return "front_of_other"
        return None
