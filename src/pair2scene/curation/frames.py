"""Which anchor's frame a relation tuple is predicted in (issue 18): one rule for the
learned model (:mod:`pair2scene.model.features`), the Gaussian baseline
(:mod:`pair2scene.model.baseline`) and placement, free of torch.

- a floor object standing against a wall (the tuple's stored wall): the wall's frame
  (:meth:`~pair2scene.scene.walls.Wall.frame`: x along the wall, y into the room);
- else a floor object with a functional anchor: the anchor's footprint frame
  (:func:`footprint_frame`);
- else its support's canonical frame.
"""

from __future__ import annotations

import numpy as np

from pair2scene.curation.dataset import PairsDataset
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR

FRAME_SUPPORT, FRAME_WALL, FRAME_FUNCTIONAL = 0, 1, 2
"""The frame a tuple is predicted in: its support's, the wall it stands against, or its
functional anchor's footprint."""
FRAME_NAMES: tuple[str, ...] = ("support", "wall", "functional")
FRAME_EPS = 1e-9
"""The floor :meth:`OrientedBox.in_frame_of` puts under a frame's half-size."""


def footprint_frame(anchor: OrientedBox, room_height: float) -> OrientedBox:
    """The frame of a floor object placed relative to ``anchor``: the anchor's footprint
    (centre, yaw, width and depth) from the floor to the ceiling."""
    center = [anchor.center[0], anchor.center[1], room_height / 2]
    return OrientedBox.from_yaw(center, [*anchor.size[:2], room_height], anchor.yaw)


def frame_choice(
    support: OrientedBox,
    on_floor: bool,
    wall: OrientedBox | None,
    functional: OrientedBox | None,
) -> tuple[int, OrientedBox]:
    """(frame kind, frame box) of one tuple (see the module docstring)."""
    if on_floor and wall is not None:
        return FRAME_WALL, wall
    if on_floor and functional is not None:
        return FRAME_FUNCTIONAL, footprint_frame(functional, float(support.size[2]))
    return FRAME_SUPPORT, support


def tuple_frames(data: PairsDataset) -> tuple[np.ndarray, np.ndarray]:
    """(N,) frame kinds and (N, 12) frame boxes of every tuple (:func:`frame_choice` on
    its support, stored wall and functional anchor)."""
    kinds = np.full(len(data), FRAME_SUPPORT, np.int64)
    boxes = data.support.box.astype(np.float64)
    has_wall, has_func = data.wall_index >= 0, data.functional.present
    for i in np.flatnonzero((data.support.id == FLOOR) & (has_wall | has_func)):
        kind, frame = frame_choice(
            OrientedBox.from_vector(boxes[i]),
            True,
            OrientedBox.from_vector(data.wall_box[i]) if has_wall[i] else None,
            OrientedBox.from_vector(data.functional.box[i]) if has_func[i] else None,
        )
        kinds[i], boxes[i] = kind, frame.to_vector()
    return kinds, boxes


def canonical_to_frame(
    canonical: np.ndarray, support: np.ndarray, frame: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Stored canonical vectors (N, 12) in the frames of ``support`` (N, 12 box vectors)
    -> the same boxes in the frames of ``frame`` (N, 12), and (N,) the log-Jacobian
    ``sum log h_support - sum log h_frame`` of each of the two scaled parts (the centre,
    the size): an affine map, so ``log p(canonical) = log p(out) + 2 * that``. The 6D
    part is rotated as stored (not orthonormalised)."""
    x = np.asarray(canonical, dtype=np.float64).reshape(-1, 12)
    sup = np.asarray(support, dtype=np.float64).reshape(-1, 12)
    frm = np.asarray(frame, dtype=np.float64).reshape(-1, 12)
    out = np.empty_like(x)
    log_jac = np.zeros(len(x))
    for i in range(len(x)):
        s, f = OrientedBox.from_vector(sup[i]), OrientedBox.from_vector(frm[i])
        hs, hf = np.maximum(s.half_size, FRAME_EPS), np.maximum(f.half_size, FRAME_EPS)
        rel = f.rotation.T @ s.rotation  # support axes in the frame's
        out[i, 0:3] = (rel @ (x[i, 0:3] * hs) + f.rotation.T @ (s.center - f.center)) / hf
        out[i, 3:6] = x[i, 3:6] * hs / hf
        out[i, 6:9], out[i, 9:12] = rel @ x[i, 6:9], rel @ x[i, 9:12]
        log_jac[i] = np.log(hs).sum() - np.log(hf).sum()
    return out, log_jac
