"""Rotations and oriented boxes in the world frame (z up, right-handed, metres).

Rotations are 3x3 matrices whose columns are the object's local axes in world
coordinates: column 0 is local +x (right), column 1 local +y (front), column 2
local +z (up). The learned model uses the continuous 6D representation of
Zhou et al. (2019): the first two columns, flattened column-major, mapped back
by Gram-Schmidt. All functions are vectorised over leading dimensions.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

ArrayLike = np.typing.ArrayLike

ROTATION_ATOL = 1e-5
"""Tolerance for accepting a matrix as a rotation: float32 files round-trip at ~1e-7."""


def yaw_to_matrix(yaw: ArrayLike) -> np.ndarray:
    """Rotation about world +z by ``yaw`` radians (counter-clockwise seen from above).

    yaw : (...,) float  ->  (..., 3, 3) float
    """
    if isinstance(yaw, float):  # one yaw, as placement asks thousands of times a scene
        c, s = float(np.cos(yaw)), float(np.sin(yaw))  # (the same numbers as below)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    yaw = np.asarray(yaw, dtype=float)
    c, s = np.cos(yaw), np.sin(yaw)
    zero, one = np.zeros_like(yaw), np.ones_like(yaw)
    rows = [
        np.stack([c, -s, zero], axis=-1),
        np.stack([s, c, zero], axis=-1),
        np.stack([zero, zero, one], axis=-1),
    ]
    return np.stack(rows, axis=-2)


def matrix_to_yaw(rotation: ArrayLike) -> np.ndarray:
    """Heading of local +x in the world xy plane, in [-pi, pi].

    Exact inverse of :func:`yaw_to_matrix` for rotations about z; for tilted
    objects it is the heading of their projected x axis.
    rotation : (..., 3, 3)  ->  (...,)
    """
    r = np.asarray(rotation, dtype=float)
    return np.arctan2(r[..., 1, 0], r[..., 0, 0])


def matrix_to_6d(rotation: ArrayLike) -> np.ndarray:
    """First two columns of the rotation, concatenated: (..., 3, 3) -> (..., 6)."""
    r = np.asarray(rotation, dtype=float)
    return np.concatenate([r[..., :, 0], r[..., :, 1]], axis=-1)


def sixd_to_matrix(sixd: ArrayLike, eps: float = 1e-9) -> np.ndarray:
    """Gram-Schmidt a 6D vector back to a rotation: (..., 6) -> (..., 3, 3).

    The two 3-vectors need not be unit length or orthogonal (network outputs
    are not); they must not be parallel.
    """
    x = np.asarray(sixd, dtype=float)
    b = x[..., 3:]
    c0 = sixd_x_axis(x, eps)
    b = b - np.sum(c0 * b, axis=-1, keepdims=True) * c0
    c1 = b / np.maximum(np.linalg.norm(b, axis=-1, keepdims=True), eps)
    (ax, ay, az), (bx, by, bz) = np.moveaxis(c0, -1, 0), np.moveaxis(c1, -1, 0)
    c2 = np.stack((ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx), axis=-1)
    return np.stack([c0, c1, c2], axis=-1)  # (c2: np.cross's products, in its order)


def sixd_x_axis(sixd: np.ndarray, eps: float = 1e-9) -> np.ndarray:
    """The first column of :func:`sixd_to_matrix` (the local +x axis), alone: (..., 6)
    float -> (..., 3)."""
    a = sixd[..., :3]
    return a / np.maximum(np.linalg.norm(a, axis=-1, keepdims=True), eps)


def euler_to_matrix(angles: ArrayLike, order: str) -> np.ndarray:
    """Compose elementary rotations (radians) applied in ``order``, e.g. "zxy".

    The first letter is applied first (extrinsic convention): for "zxy" the
    result is Ry @ Rx @ Rz. angles : (3,) in x, y, z order.
    """
    ax, ay, az = np.asarray(angles, dtype=float)
    elementary = {"x": rot_x(ax), "y": rot_y(ay), "z": rot_z(az)}
    out = np.eye(3)
    for axis in order:
        out = elementary[axis] @ out
    return out


def rot_x(a: float) -> np.ndarray:
    """(3, 3) rotation by ``a`` radians about +x."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(a: float) -> np.ndarray:
    """(3, 3) rotation by ``a`` radians about +y."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(a: float) -> np.ndarray:
    """(3, 3) rotation by ``a`` radians about +z."""
    return yaw_to_matrix(float(a))


def is_rotation(rotation: ArrayLike, atol: float = ROTATION_ATOL) -> bool:
    """True when ``rotation`` (3, 3) is orthonormal with determinant +1."""
    r = np.asarray(rotation, dtype=float)
    if r.shape != (3, 3) or not np.all(np.isfinite(r)):
        return False
    return bool(np.allclose(r.T @ r, np.eye(3), atol=atol) and abs(np.linalg.det(r) - 1) < atol)


def orthonormalize(rotation: ArrayLike) -> np.ndarray:
    """Nearest rotation (SVD projection) to a nearly orthonormal (3, 3) matrix."""
    u, _, vt = np.linalg.svd(np.asarray(rotation, dtype=float))
    d = np.sign(np.linalg.det(u @ vt))
    return u @ np.diag([1.0, 1.0, d]) @ vt


# The 8 corners of the unit cube [-1, 1]^3, in a fixed order: bottom face
# (z = -1) counter-clockwise from (-1, -1), then the top face in the same order.
UNIT_CORNERS = np.array(
    [
        [-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1],
    ],
    dtype=float,
)  # fmt: skip


def _frozen(value, shape: tuple[int, ...]) -> bool:
    """Whether ``value`` is an array a box may keep as it is: float64 of ``shape``, owning
    its data and read-only (what :class:`OrientedBox` makes of its inputs)."""
    return (
        isinstance(value, np.ndarray)
        and value.base is None
        and not value.flags.writeable
        and value.dtype == np.float64
        and value.shape == shape
    )


@dataclass(frozen=True, eq=False)
class OrientedBox:
    """A box in the world: centre (3,), full size along local x/y/z (3,), rotation (3, 3).

    Local frame: +z up, +y the object's front, +x its right.
    """

    center: np.ndarray
    size: np.ndarray
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))

    def __post_init__(self) -> None:
        for name, shape in (("center", (3,)), ("size", (3,)), ("rotation", (3, 3))):
            value = getattr(self, name)
            if _frozen(value, shape):
                continue  # another box's array (placement makes thousands a second)
            arr = np.array(value, dtype=float)
            if arr.shape != shape:
                raise ValueError(f"OrientedBox.{name} must have shape {shape}, got {arr.shape}")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    # -- constructors -------------------------------------------------------
    @classmethod
    def from_yaw(cls, center: ArrayLike, size: ArrayLike, yaw: float = 0.0) -> OrientedBox:
        return cls(np.asarray(center), np.asarray(size), yaw_to_matrix(yaw))

    @classmethod
    def from_vector(cls, vec: ArrayLike) -> OrientedBox:
        """From the model's 12-d layout (centre 3, size 3, 6D rotation 6)."""
        v = np.asarray(vec, dtype=float)
        return cls(v[:3], v[3:6], sixd_to_matrix(v[6:12]))

    @classmethod
    def from_transform(cls, transform: ArrayLike, size: ArrayLike) -> OrientedBox:
        """From a rigid (4, 4) local-to-world transform and the full size (3,)."""
        t = np.asarray(transform, dtype=float)
        return cls(t[:3, 3], np.asarray(size), t[:3, :3])

    # -- views --------------------------------------------------------------
    @property
    def yaw(self) -> float:
        return float(matrix_to_yaw(self.rotation))

    @cached_property
    def half_size(self) -> np.ndarray:
        """Half the size (3,), read-only (worked out once a box: placement asks a box for
        it thousands of times a scene)."""
        half = self.size / 2.0
        half.setflags(write=False)
        return half

    @property
    def transform(self) -> np.ndarray:
        """Local-to-world (4, 4) rigid transform (size not included)."""
        t = np.eye(4)
        t[:3, :3] = self.rotation
        t[:3, 3] = self.center
        return t

    def to_vector(self) -> np.ndarray:
        """(12,) centre, size, 6D rotation."""
        return np.concatenate([self.center, self.size, matrix_to_6d(self.rotation)])

    def corners(self) -> np.ndarray:
        """(8, 3) world corners in :data:`UNIT_CORNERS` order."""
        return self.to_world(UNIT_CORNERS * self.half_size)

    def to_world(self, points: ArrayLike) -> np.ndarray:
        """Local points (N, 3) -> world points (N, 3)."""
        return np.asarray(points, dtype=float) @ self.rotation.T + self.center

    def to_local(self, points: ArrayLike) -> np.ndarray:
        """World points (N, 3) -> local points (N, 3)."""
        return (np.asarray(points, dtype=float) - self.center) @ self.rotation

    def aabb(self) -> tuple[np.ndarray, np.ndarray]:
        """World axis-aligned bounds: (min (3,), max (3,)), read-only."""
        return self._bounds

    @cached_property
    def _bounds(self) -> tuple[np.ndarray, np.ndarray]:
        extent = np.abs(self.rotation) @ self.half_size
        low, high = self.center - extent, self.center + extent
        low.setflags(write=False)
        high.setflags(write=False)
        return low, high

    @property
    def bottom(self) -> float:
        return float(self.aabb()[0][2])

    @property
    def top(self) -> float:
        return float(self.aabb()[1][2])

    def contains(self, points: ArrayLike, margin: float = 0.0) -> np.ndarray:
        """(N,) bool: world points inside the box grown by ``margin`` on each side."""
        local = self.to_local(np.atleast_2d(points))
        return np.all(np.abs(local) <= self.half_size + margin, axis=-1)

    # -- canonical frame (architecture.md) ------------------------------------
    def in_frame_of(self, anchor: OrientedBox, eps: float = 1e-9) -> OrientedBox:
        """This box in ``anchor``'s canonical frame: anchor's rotation removed,
        centred on it and divided by its half-size, so the anchor is [-1, 1]^3."""
        scale = np.maximum(anchor.half_size, eps)
        center = anchor.rotation.T @ (self.center - anchor.center) / scale
        return OrientedBox(center, self.size / scale, anchor.rotation.T @ self.rotation)

    def from_frame_of(self, anchor: OrientedBox, eps: float = 1e-9) -> OrientedBox:
        """Inverse of :meth:`in_frame_of`: a canonical-frame box back to the world."""
        scale = np.maximum(anchor.half_size, eps)
        center = anchor.rotation @ (self.center * scale) + anchor.center
        return OrientedBox(center, self.size * scale, anchor.rotation @ self.rotation)

    def allclose(self, other: OrientedBox, atol: float = 1e-6) -> bool:
        return bool(
            np.allclose(self.center, other.center, atol=atol)
            and np.allclose(self.size, other.size, atol=atol)
            and np.allclose(self.rotation, other.rotation, atol=atol)
        )

    def __repr__(self) -> str:
        c = ", ".join(f"{v:.3f}" for v in self.center)
        s = ", ".join(f"{v:.3f}" for v in self.size)
        return f"OrientedBox(center=[{c}], size=[{s}], yaw={np.degrees(self.yaw):.1f}deg)"


def corner_distance(a: ArrayLike, b: ArrayLike) -> float:
    """Largest distance from a corner of ``a`` (8, 3) to the nearest corner of ``b`` (8, 3).

    Order-free: sources list OBB corners in their own order.
    """
    d = np.linalg.norm(np.asarray(a)[:, None, :] - np.asarray(b)[None, :, :], axis=-1)
    return float(max(d.min(axis=1).max(), d.min(axis=0).max()))


def convex_overlap_area(a: ArrayLike, b: ArrayLike) -> float:
    """Area of the intersection of two convex counter-clockwise polygons (K, 2) and
    (M, 2): ``a`` clipped by each edge of ``b`` in turn (Sutherland-Hodgman), then the
    shoelace formula. In Python's floats: two footprints of four corners each, tested
    for every floor candidate, where numpy's per-call cost would be most of the time."""
    out = [(float(x), float(y)) for x, y in np.asarray(a, dtype=float).tolist()]
    clip = np.asarray(b, dtype=float).tolist()
    for (x0, y0), (x1, y1) in zip(clip, clip[1:] + clip[:1]):
        if len(out) < 3:
            return 0.0
        ex, ey = x1 - x0, y1 - y0
        kept = []
        prev = out[-1]
        s_prev = ex * (prev[1] - y0) - ey * (prev[0] - x0)  # >= 0: left of the edge, inside
        for cur in out:
            s_cur = ex * (cur[1] - y0) - ey * (cur[0] - x0)
            if (s_cur >= 0) != (s_prev >= 0):  # the edge's line crosses prev -> cur
                t = s_prev / (s_prev - s_cur)
                kept.append((prev[0] + t * (cur[0] - prev[0]), prev[1] + t * (cur[1] - prev[1])))
            if s_cur >= 0:
                kept.append(cur)
            prev, s_prev = cur, s_cur
        out = kept
    if len(out) < 3:
        return 0.0
    twice = sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(out, out[1:] + out[:1]))
    return max(0.5 * twice, 0.0)


def polygon_area(polygon: ArrayLike) -> float:
    """Signed area of a 2D polygon (N, 2); positive when counter-clockwise."""
    p = np.asarray(polygon, dtype=float)
    x, y = p[:, 0], p[:, 1]
    return float(0.5 * (np.dot(x, following(y)) - np.dot(y, following(x))))


def following(values: np.ndarray) -> np.ndarray:
    """Each row's next one along the first axis, the last's being the first:
    ``np.roll(values, -1, axis=0)``, the same values, without its general machinery (a
    polygon's edges end there; placement asks for thousands a scene)."""
    return np.concatenate((values[1:], values[:1]))


def points_in_polygon(points: ArrayLike, polygon: ArrayLike) -> np.ndarray:
    """(N,) bool: 2D points (N, 2) inside polygon (M, 2) by the even-odd rule."""
    pts = np.atleast_2d(np.asarray(points, dtype=float))
    poly = np.asarray(polygon, dtype=float)
    if len(pts) * len(poly) <= _FEW:
        return _few_in_polygon(pts.tolist(), poly.tolist())
    x, y = pts[:, 0:1], pts[:, 1:2]
    x0, y0 = poly[:, 0], poly[:, 1]
    x1, y1 = np.concatenate((x0[1:], x0[:1])), np.concatenate((y0[1:], y0[:1]))
    crosses = (y0 > y) != (y1 > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_at = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
    inside = crosses & (x < x_at)
    return np.count_nonzero(inside, axis=1) % 2 == 1


_FEW = 64
"""Up to this many point-edge tests, :func:`points_in_polygon` loops in Python: a box's
footprint against a room's floor (5 points, 4-8 edges) is tested for every candidate,
where numpy's per-call cost is most of the time."""


def _few_in_polygon(pts: list, poly: list) -> np.ndarray:
    """:func:`points_in_polygon`, the same arithmetic, a point and an edge at a time."""
    edges = [(*poly[i], *poly[(i + 1) % len(poly)]) for i in range(len(poly))]
    out = []
    for x, y in pts:
        inside = False
        for x0, y0, x1, y1 in edges:
            if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
                inside = not inside
        out.append(inside)
    return np.array(out, dtype=bool)


def convex_hull_2d(points: np.ndarray) -> list[tuple[float, float]]:
    """Convex hull (counter-clockwise) of 2D points: a tilted box's footprint.

    Monotone chain; duplicate and collinear points are dropped, so an upright box's
    eight corners give its four footprint corners.
    """
    pts = sorted({(float(x), float(y)) for x, y in points})
    if len(pts) <= 2:
        return pts

    def cross(o, a, b) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[tuple[float, float]] = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[tuple[float, float]] = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]
