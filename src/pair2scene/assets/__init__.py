"""Procedural assets: meshes for every category, their parts, surfaces and point clouds.

``generate(category, size, rng)`` builds a procedural asset; ``AssetLibrary``
retrieves from the generators, a user folder of meshes or 3D-FUTURE; ``asset_seed``
picks an object's stand-in asset (the same in every stage); ``surfaces_of`` finds
where things can rest; ``asset_point_cloud`` samples (and caches) the surface points
the layout model reads.
"""

from pair2scene.assets.identity import asset_seed
from pair2scene.assets.library import AssetLibrary
from pair2scene.assets.mesh import Asset, Mesh, Part
from pair2scene.assets.pointcloud import asset_point_cloud
from pair2scene.assets.registry import generate
from pair2scene.assets.surfaces import SupportSurface, support_surfaces, surfaces_of

__all__ = [
    "Asset",
    "AssetLibrary",
    "Mesh",
    "Part",
    "SupportSurface",
    "asset_point_cloud",
    "asset_seed",
    "generate",
    "support_surfaces",
    "surfaces_of",
]
