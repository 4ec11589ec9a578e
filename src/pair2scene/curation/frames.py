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


def footprint_frame(anchor: OrientedBox, room_height: float) -> OrientedBox:
    """The frame of a floor object placed relative to ``anchor``: the anchor's footprint
    (centre, yaw, width and depth) from the floor to the ceiling."""
    x = anchor.rotation[:, 0]
    yaw = float(np.arctan2(x[1], x[0])) if np.hypot(x[0], x[1]) > 1e-6 else 0.0
    center = [anchor.center[0], anchor.center[1], room_height / 2]
    return OrientedBox.from_yaw(center, [*anchor.size[:2], room_height], yaw)


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
