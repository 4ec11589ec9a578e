"""Reading and writing files: scene.json and atomic writes."""

from pair2scene.io.atomic import atomic_open, atomic_write_bytes, atomic_write_text
from pair2scene.io.scene_json import dumps_scene, read_scene, scene_from_dict, write_scene

__all__ = [
    "atomic_open",
    "atomic_write_bytes",
    "atomic_write_text",
    "dumps_scene",
    "read_scene",
    "scene_from_dict",
    "write_scene",
]
