"""A placed scene as one OpenUSD file with UsdPhysics: something Isaac Sim / Isaac Lab,
Omniverse, Newton or any other UsdPhysics reader can open and simulate as it is.

Why USD: the physics simulators built on it read rigid bodies, colliders, masses and
friction from the standard ``UsdPhysics`` schemas, so one file carries what
:mod:`pair2scene.io.physical` decided (which objects move, their mass, centre of mass,
inertia, friction and convex collision parts) and what the scene looks like.

One self-contained file: every mesh is inline (no references, no textures), so the file
can be moved, mailed or opened alone. Its format follows the path's suffix, which is
how USD picks a file format: ``.usda`` (text: readable and diffable) or ``.usdc`` /
``.usd`` (binary "crate"), the better default for simulation: for a 20-object bedroom
0.12 MB against 0.71 MB of text, opened about 3x faster. Either is written into a
temporary folder beside the target and renamed onto it: a reader never sees half a file.
(USD caches the layers a process has open: a process that holds a stage of the file
sees the new content only after ``Reload``.)

Layout (z up, metres, kilograms; ``/World`` is the default prim)::

    /World                      Xform, kind assembly
      PhysicsScene              UsdPhysics.Scene, gravity (0, 0, -1) x 9.81
      PhysicsMaterials/<name>   UsdShade.Material + UsdPhysics.MaterialAPI (friction)
      Room/<piece>              floor, walls, lintels, window panes: static colliders
      Objects/<object>          Xform posed by the object's box (translate + orient)
        visual                  Mesh, displayColor = semantic colour
        collision/part_<i>      Mesh, purpose guide, CollisionAPI + MeshCollisionAPI
                                (convexHull), physics material bound (purpose physics)

A dynamic object's Xform has ``RigidBodyAPI`` and ``MassAPI`` (mass, centre of mass,
principal moments and the rotation to their axes); a fixed one has colliders only, which
UsdPhysics treats as static. Prim names must be identifiers, object ids need not be:
each object's Xform keeps its id in the ``pair2scene:id`` attribute (and its support in
``pair2scene:support``). The category is a ``UsdSemantics.LabelsAPI`` label of taxonomy
``class`` (attribute ``semantics:labels:class``): usd-core's own semantics schema, the
one Isaac Sim reads since 5.0 (the older ``Semantics.SemanticsAPI`` is not in usd-core).

``pxr`` comes from the optional ``usd-core`` package (``pip install 'pair2scene[usd]'``);
it is imported only when a file is written.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from pair2scene.assets.mesh import Asset, Mesh
from pair2scene.errors import UserError
from pair2scene.io.atomic import current_umask
from pair2scene.io.physical import MATERIAL_FRICTION, scene_physics
from pair2scene.io.scene_meshes import room_color, room_meshes, semantic_color
from pair2scene.scene.geometry import orthonormalize
from pair2scene.scene.model import Scene

NEEDS_USD = "USD export needs usd-core: pip install 'pair2scene[usd]'"
"""The error a write without ``pxr`` raises."""
SUFFIXES = (".usda", ".usdc", ".usd")
"""File suffixes :func:`write_usd` writes; the suffix picks the format (``.usd``: crate)."""
GRAVITY_M_S2 = 9.81
"""Magnitude of the physics scene's gravity, along -z."""
ROOM_MATERIAL = "wood"
"""Physics material of the floor and walls (a wooden floor): its friction is
:data:`pair2scene.io.physical.MATERIAL_FRICTION`'s, the coefficient every object's
friction is given against, and it shares the material prim of wooden objects."""
RESTITUTION = 0.0
"""Bounce of every physics material: furniture and household objects do not bounce."""
WORLD, ROOM, OBJECTS, MATERIALS = "World", "Room", "Objects", "PhysicsMaterials"
"""Names of the root prim and of its groups."""
ID_ATTR, SUPPORT_ATTR = "pair2scene:id", "pair2scene:support"
"""String attributes on each object's Xform: its scene id and its support."""
PHYSICS_PURPOSE = "physics"
"""Material purpose of the friction materials' binding (``material:binding:physics``),
the one UsdPhysics readers look up; renderers ignore it."""
SEMANTIC_TAXONOMY = "class"
"""``UsdSemantics.LabelsAPI`` instance holding the category: ``semantics:labels:class``."""


def write_usd(
    scene: Scene, assets: dict[str, Asset], path: str | os.PathLike, dynamic: str = "small"
) -> Path:
    """Write ``scene`` (posed ``assets``, by object id) as one self-contained USD file at
    ``path`` (``.usda`` text, ``.usdc`` / ``.usd`` binary) with UsdPhysics rigid bodies,
    colliders and materials; ``dynamic`` picks the free bodies
    (:data:`pair2scene.io.physical.DYNAMIC_CHOICES`). Objects without an asset are left
    out. Returns the path written."""
    try:
        from pxr import Usd  # noqa: F401  (only to know usd-core is there)
    except ImportError as exc:
        raise UserError(NEEDS_USD) from exc
    path = Path(path)
    if path.suffix.lower() not in SUFFIXES:
        raise UserError(f"USD file name must end with one of {', '.join(SUFFIXES)}: {path}")
    bodies = scene_physics(scene, assets, dynamic=dynamic)
    stage = _build_stage(scene, assets, bodies)
    path.parent.mkdir(parents=True, exist_ok=True)
    # The format comes from the file name's suffix, so the temporary file keeps the name
    # and lives in a temporary folder beside the target instead.
    tmp = Path(tempfile.mkdtemp(dir=path.parent, prefix=f".{path.name}."))
    try:
        written = tmp / path.name
        if not stage.GetRootLayer().Export(str(written)):
            raise OSError(f"USD could not write {path}")
        os.chmod(written, 0o666 & ~current_umask())
        os.replace(written, path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return path


def _build_stage(scene: Scene, assets: dict[str, Asset], bodies: dict):
    """The scene's stage, in memory."""
    from pxr import Kind, Sdf, Usd, UsdGeom, UsdPhysics

    stage = Usd.Stage.CreateInMemory()
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
    stage.GetRootLayer().documentation = f"pair2scene scene {scene.id}"
    world = UsdGeom.Xform.Define(stage, f"/{WORLD}").GetPrim()
    stage.SetDefaultPrim(world)
    Usd.ModelAPI(world).SetKind(Kind.Tokens.assembly)
    world.SetCustomDataByKey("pair2scene:sceneId", scene.id)

    physics = UsdPhysics.Scene.Define(stage, f"/{WORLD}/PhysicsScene")
    physics.CreateGravityDirectionAttr().Set((0.0, 0.0, -1.0))
    physics.CreateGravityMagnitudeAttr().Set(GRAVITY_M_S2)

    materials = _Materials(stage, Sdf.Path(f"/{WORLD}/{MATERIALS}"))
    room = UsdGeom.Xform.Define(stage, f"/{WORLD}/{ROOM}").GetPrim()
    Usd.ModelAPI(room).SetKind(Kind.Tokens.component)
    room_material = materials.get(ROOM_MATERIAL, MATERIAL_FRICTION[ROOM_MATERIAL])
    for name, mesh in room_meshes(scene.room):
        prim = _mesh(stage, room.GetPath().AppendChild(name), mesh, room_color(name))
        _collider(prim, room_material)

    group = UsdGeom.Scope.Define(stage, f"/{WORLD}/{OBJECTS}").GetPrim()
    Usd.ModelAPI(group).SetKind(Kind.Tokens.group)
    names = _PrimNames()
    for obj in scene.objects:
        body = bodies.get(obj.id)
        asset = assets.get(obj.id)
        if body is None or asset is None:
            continue
        path = group.GetPath().AppendChild(names.take(obj.id))
        _object(stage, path, obj, asset, body, materials)
    return stage


def _object(stage, path, obj, asset: Asset, body, materials: _Materials) -> None:
    """One object's Xform: pose, ids, label, visual mesh, colliders, rigid body."""
    from pxr import Gf, Kind, Sdf, Usd, UsdGeom, UsdPhysics, UsdSemantics

    xform = UsdGeom.Xform.Define(stage, path)
    prim = xform.GetPrim()
    Usd.ModelAPI(prim).SetKind(Kind.Tokens.component)
    xform.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble).Set(
        Gf.Vec3d(*np.asarray(obj.box.center, dtype=float).tolist())
    )
    xform.AddOrientOp(UsdGeom.XformOp.PrecisionDouble).Set(_quat(obj.box.rotation))
    for name, value in ((ID_ATTR, obj.id), (SUPPORT_ATTR, obj.support or "")):
        attr = prim.CreateAttribute(name, Sdf.ValueTypeNames.String, True, Sdf.VariabilityUniform)
        attr.Set(value)
    labels = UsdSemantics.LabelsAPI.Apply(prim, SEMANTIC_TAXONOMY)
    labels.CreateLabelsAttr().Set([obj.category])

    _mesh(stage, path.AppendChild("visual"), asset.mesh, semantic_color(obj.category))
    scope = UsdGeom.Scope.Define(stage, path.AppendChild("collision"))
    scope.CreatePurposeAttr().Set(UsdGeom.Tokens.guide)
    material = materials.get(body.material, body.friction)
    for i, part in enumerate(body.parts):
        mesh = _mesh(stage, scope.GetPath().AppendChild(f"part_{i:03d}"), part, None)
        UsdGeom.Imageable(mesh).CreatePurposeAttr().Set(UsdGeom.Tokens.guide)
        _collider(mesh, material)

    if not body.dynamic:
        return  # colliders without a rigid body: static
    UsdPhysics.RigidBodyAPI.Apply(prim)
    mass = UsdPhysics.MassAPI.Apply(prim)
    moments, axes = principal_inertia(body.inertia)
    mass.CreateMassAttr().Set(float(body.mass))
    mass.CreateCenterOfMassAttr().Set(Gf.Vec3f(*np.asarray(body.com, dtype=float).tolist()))
    mass.CreateDiagonalInertiaAttr().Set(Gf.Vec3f(*moments.tolist()))
    mass.CreatePrincipalAxesAttr().Set(Gf.Quatf(_quat(axes)))


def principal_inertia(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The principal moments (3,) and axes (3, 3), a rotation whose columns are the axes
    in the local frame, of an inertia tensor: ``inertia = axes @ diag(moments) @ axes.T``."""
    tensor = np.asarray(inertia, dtype=float)
    moments, axes = np.linalg.eigh((tensor + tensor.T) / 2)
    if np.linalg.det(axes) < 0:
        axes[:, 2] = -axes[:, 2]
    return moments, axes


def _quat(rotation: np.ndarray):
    """The ``Gf.Quatd`` of a rotation matrix (columns: local axes in the parent frame)."""
    from pxr import Gf

    r = orthonormalize(rotation)
    # Gf matrices act on row vectors: the matrix of ``v -> r @ v`` is r transposed.
    # (Matrix4d's quaternion is exact for small angles; Gf.Rotation's axis-angle is not.)
    m = Gf.Matrix3d(*r.T.reshape(-1).tolist())
    return Gf.Matrix4d(m, Gf.Vec3d(0.0)).ExtractRotationQuat()


def _mesh(stage, path, mesh: Mesh, rgb: tuple[int, int, int] | None):
    """A ``UsdGeom.Mesh`` of triangles at ``path`` (flat polygons, no subdivision), with a
    constant displayColor (sRGB 0-255 given, stored linear as USD colours are)."""
    from pxr import UsdGeom, Vt

    prim = UsdGeom.Mesh.Define(stage, path)
    points = Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(mesh.vertices, dtype=np.float32))
    prim.CreatePointsAttr().Set(points)
    counts = np.full(len(mesh.faces), 3, dtype=np.int32)
    prim.CreateFaceVertexCountsAttr().Set(Vt.IntArray.FromNumpy(counts))
    indices = np.ascontiguousarray(mesh.faces.reshape(-1), dtype=np.int32)
    prim.CreateFaceVertexIndicesAttr().Set(Vt.IntArray.FromNumpy(indices))
    prim.CreateSubdivisionSchemeAttr().Set(UsdGeom.Tokens.none)
    prim.CreateExtentAttr().Set(UsdGeom.PointBased.ComputeExtent(points))
    if rgb is not None:
        prim.CreateDisplayColorPrimvar(UsdGeom.Tokens.constant).Set([_linear(rgb)])
    return prim.GetPrim()


def _linear(rgb: tuple[int, int, int]) -> tuple[float, float, float]:
    """sRGB 0-255 -> linear 0-1."""
    c = np.asarray(rgb, dtype=float) / 255.0
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return tuple(float(x) for x in lin)


def _collider(prim, material) -> None:
    """Make a mesh prim a convex-hull collider with ``material`` bound for physics."""
    from pxr import UsdPhysics, UsdShade

    UsdPhysics.CollisionAPI.Apply(prim)
    UsdPhysics.MeshCollisionAPI.Apply(prim).CreateApproximationAttr().Set(
        UsdPhysics.Tokens.convexHull
    )
    UsdShade.MaterialBindingAPI.Apply(prim).Bind(
        material, UsdShade.Tokens.weakerThanDescendants, PHYSICS_PURPOSE
    )


class _Materials:
    """One physics material per distinct (material name, friction), made on first use."""

    def __init__(self, stage, root) -> None:
        from pxr import UsdGeom

        self.stage, self.root = stage, root
        UsdGeom.Scope.Define(stage, root)
        self.made: dict[tuple[str, float], object] = {}
        self.names = _PrimNames()

    def get(self, name: str, friction: float):
        from pxr import UsdPhysics, UsdShade

        key = (name, round(float(friction), 6))
        if key not in self.made:
            material = UsdShade.Material.Define(
                self.stage, self.root.AppendChild(self.names.take(name or "material"))
            )
            api = UsdPhysics.MaterialAPI.Apply(material.GetPrim())
            api.CreateStaticFrictionAttr().Set(float(friction))
            api.CreateDynamicFrictionAttr().Set(float(friction))
            api.CreateRestitutionAttr().Set(RESTITUTION)
            self.made[key] = material
        return self.made[key]


class _PrimNames:
    """Valid, unique prim names for arbitrary strings (ids, material names)."""

    def __init__(self) -> None:
        self.used: set[str] = set()

    def take(self, text: str) -> str:
        from pxr import Tf

        base = Tf.MakeValidIdentifier(text) or "_"
        name, n = base, 1
        while name in self.used:
            name, n = f"{base}_{n}", n + 1
        self.used.add(name)
        return name
