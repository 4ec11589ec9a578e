"""Procedural assets: meshes for every category, their parts, surfaces and point clouds."""

from pair2scene.assets.mesh import Asset, Mesh, Part
from pair2scene.assets.registry import generate, generators

__all__ = ["Asset", "Mesh", "Part", "generate", "generators"]
