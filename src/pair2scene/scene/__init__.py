"""The scene model: oriented boxes, objects, rooms, scenes, relation tuples."""

from pair2scene.scene.geometry import (
    OrientedBox,
    matrix_to_6d,
    matrix_to_yaw,
    sixd_to_matrix,
    yaw_to_matrix,
)
from pair2scene.scene.model import (
    FLOOR,
    AssetRef,
    Opening,
    RelationTuple,
    Room,
    Scene,
    SceneObject,
)

__all__ = [
    "FLOOR",
    "AssetRef",
    "Opening",
    "OrientedBox",
    "RelationTuple",
    "Room",
    "Scene",
    "SceneObject",
    "matrix_to_6d",
    "matrix_to_yaw",
    "sixd_to_matrix",
    "yaw_to_matrix",
]
