"""USD export (:mod:`pair2scene.io.usd`): a generated bedroom written with ``write_usd`` and
read back with USD itself (``pxr``, from the optional ``usd-core``): stage metadata, one
posed Xform per object holding its visual mesh and convex-hull colliders, rigid bodies
with USD mass properties on the dynamic objects only, friction materials bound for
physics, semantic labels; then what a simulator's parser (UsdPhysics' own) and USD's
validators make of the file. Without ``usd-core`` only the error message is tested."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from pair2scene.assets.registry import generate
from pair2scene.errors import UserError
from pair2scene.io.physical import scene_physics
from pair2scene.io.scene_meshes import object_meshes, room_meshes
from pair2scene.io.usd import ID_ATTR, NEEDS_USD, SEMANTIC_TAXONOMY, write_usd
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

F32 = dict(rtol=1e-5, atol=1e-6)
"""Tolerance of float (32-bit) USD attributes against float64 values."""


@pytest.fixture(scope="module")
def pxr():
    return pytest.importorskip("pxr")


@pytest.fixture(scope="module")
def bedroom():
    from pair2scene import Pair2Scene

    r = Pair2Scene.from_pretrained().generate(room="bedroom", seed=0)
    return r.scene, r.assets


@pytest.fixture(scope="module")
def written(pxr, bedroom, tmp_path_factory):
    """(scene, assets, stage) of the bedroom written as binary USD."""
    scene, assets = bedroom
    path = write_usd(scene, assets, tmp_path_factory.mktemp("usd") / "scene.usdc")
    return scene, assets, pxr.Usd.Stage.Open(str(path))


def object_prims(stage) -> dict:
    """Scene id -> the object's Xform prim, found by the id attribute."""
    out = {}
    for prim in stage.GetPrimAtPath("/World/Objects").GetChildren():
        out[prim.GetAttribute(ID_ATTR).Get()] = prim
    return out


def test_stage_metadata(written, pxr):
    from pxr import UsdGeom, UsdPhysics

    _, _, stage = written
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert UsdPhysics.GetStageKilogramsPerUnit(stage) == 1.0
    assert stage.GetDefaultPrim().GetPath() == "/World"
    scenes = [p for p in stage.Traverse() if p.IsA(UsdPhysics.Scene)]
    assert len(scenes) == 1
    physics = UsdPhysics.Scene(scenes[0])
    assert tuple(physics.GetGravityDirectionAttr().Get()) == (0.0, 0.0, -1.0)
    assert physics.GetGravityMagnitudeAttr().Get() == pytest.approx(9.81)


def test_one_posed_prim_per_object(written, pxr):
    from pxr import UsdGeom

    scene, assets, stage = written
    prims = object_prims(stage)
    children = stage.GetPrimAtPath("/World/Objects").GetChildren()
    assert len(prims) == len(scene.objects) == len(children)
    world = {oid: mesh for oid, _, mesh in object_meshes(scene, assets)}
    for obj in scene.objects:
        prim = prims[obj.id]
        xform = UsdGeom.Xformable(prim)
        ops = [op.GetOpName() for op in xform.GetOrderedXformOps()]
        assert ops == ["xformOp:translate", "xformOp:orient"]  # no scale
        m = np.array(xform.ComputeLocalToWorldTransform(0.0)).T  # USD: row vectors
        assert np.allclose(m[:3, :3], obj.box.rotation, atol=1e-9)
        assert np.allclose(m[:3, 3], obj.box.center, atol=1e-9)
        visual = UsdGeom.Mesh(prim.GetChild("visual"))
        points = np.array(visual.GetPointsAttr().Get(), dtype=float)
        placed = points @ m[:3, :3].T + m[:3, 3]
        assert np.allclose(placed, world[obj.id].vertices, atol=1e-5)
        color = visual.GetDisplayColorPrimvar()
        assert color.GetInterpolation() == UsdGeom.Tokens.constant
        assert len(color.Get()) == 1
        labels = prim.GetAttribute(f"semantics:labels:{SEMANTIC_TAXONOMY}").Get()
        assert list(labels) == [obj.category]


def test_collision_parts(written, pxr):
    from pxr import UsdGeom, UsdPhysics, UsdShade

    scene, assets, stage = written
    bodies = scene_physics(scene, assets)
    for oid, prim in object_prims(stage).items():
        scope = prim.GetChild("collision")
        assert UsdGeom.Imageable(scope).ComputePurpose() == UsdGeom.Tokens.guide
        parts = scope.GetChildren()
        assert len(parts) == len(bodies[oid].parts) == len(assets[oid].parts)
        for part, mesh in zip(parts, bodies[oid].parts):
            assert part.HasAPI(UsdPhysics.CollisionAPI)
            assert part.HasAPI(UsdPhysics.MeshCollisionAPI)
            approx = UsdPhysics.MeshCollisionAPI(part).GetApproximationAttr().Get()
            assert approx == UsdPhysics.Tokens.convexHull
            assert UsdGeom.Imageable(part).ComputePurpose() == UsdGeom.Tokens.guide
            points = np.array(UsdGeom.Mesh(part).GetPointsAttr().Get(), dtype=float)
            assert np.allclose(points, mesh.vertices, atol=1e-6)
            material, _ = UsdShade.MaterialBindingAPI(part).ComputeBoundMaterial("physics")
            friction = UsdPhysics.MaterialAPI(material.GetPrim()).GetStaticFrictionAttr().Get()
            assert friction == pytest.approx(bodies[oid].friction)
    room = stage.GetPrimAtPath("/World/Room").GetChildren()
    assert [p.GetName() for p in room] == [name for name, _ in room_meshes(scene.room)]
    assert all(p.HasAPI(UsdPhysics.CollisionAPI) for p in room)


def test_rigid_bodies_and_mass(written, pxr):
    from pxr import Gf, UsdPhysics

    scene, assets, stage = written
    bodies = scene_physics(scene, assets)
    assert any(b.dynamic for b in bodies.values()) and not all(b.dynamic for b in bodies.values())
    for oid, prim in object_prims(stage).items():
        body = bodies[oid]
        assert prim.HasAPI(UsdPhysics.RigidBodyAPI) == body.dynamic
        assert prim.HasAPI(UsdPhysics.MassAPI) == body.dynamic
        if not body.dynamic:
            continue
        api = UsdPhysics.MassAPI(prim)
        mass = api.GetMassAttr().Get()
        moments = np.array(api.GetDiagonalInertiaAttr().Get(), dtype=float)
        assert mass > 0 and np.all(moments > 0)
        assert mass == pytest.approx(body.mass, rel=1e-6)
        assert np.allclose(api.GetCenterOfMassAttr().Get(), body.com, **F32)
        q = api.GetPrincipalAxesAttr().Get()
        axes = np.array(Gf.Matrix3d().SetRotate(Gf.Quatd(q)).GetTranspose())  # columns
        tensor = axes @ np.diag(moments) @ axes.T
        assert np.allclose(tensor, body.inertia, rtol=1e-5, atol=1e-6 * moments.max())


def test_what_a_physics_parser_sees(written, pxr):
    """UsdPhysics' own parser (what simulators build on): one rigid body per dynamic
    object owning its parts, every collider a convex hull with a material, the rest
    static."""
    from pxr import UsdPhysics

    scene, assets, stage = written
    bodies = scene_physics(scene, assets)
    parse = getattr(UsdPhysics, "UsdPhysicsLoadStageFromPrimRange", None)
    if parse is None:
        pytest.skip("this usd-core has no UsdPhysicsLoadStageFromPrimRange")
    found = parse(stage, ["/World"])
    rigid_paths, rigid = found[UsdPhysics.ObjectType.RigidBody]
    prims = object_prims(stage)
    dynamic = {str(prims[o].GetPath()): b for o, b in bodies.items() if b.dynamic}
    assert sorted(str(p) for p in rigid_paths) == sorted(dynamic)
    for path, desc in zip(rigid_paths, rigid):
        assert len(desc.collisions) == len(dynamic[str(path)].parts)
    _, shapes = found[UsdPhysics.ObjectType.MeshShape]
    n_parts = sum(len(b.parts) for b in bodies.values())
    assert len(shapes) == n_parts + len(room_meshes(scene.room))
    assert all(s.approximation == UsdPhysics.Tokens.convexHull for s in shapes)
    assert all(len(s.materials) == 1 for s in shapes)
    static = [s for s in shapes if not str(s.rigidBody)]
    n_dynamic_parts = sum(len(b.parts) for b in dynamic.values())
    assert len(static) == len(shapes) - n_dynamic_parts


def test_usd_validators_find_nothing(written, pxr):
    """USD's validation framework (which replaced ``UsdUtils.ComplianceChecker``), every
    registered validator: stage metadata, physics (colliders, rigid bodies), shading,
    geometry, composition."""
    validation = pytest.importorskip("pxr.UsdValidation")
    _, _, stage = written
    validators = validation.ValidationRegistry().GetOrLoadAllValidators()
    errors = validation.ValidationContext(validators).Validate(stage)
    assert [(e.GetName(), e.GetMessage()) for e in errors] == []


def test_text_and_binary_files(pxr, tmp_path):
    scene, assets = tiny_scene()
    for name in ("scene.usda", "scene.usdc", "scene.usd"):
        path = write_usd(scene, assets, tmp_path / name)
        stage = pxr.Usd.Stage.Open(str(path))
        assert len(object_prims(stage)) == len(scene.objects)
    assert (tmp_path / "scene.usda").read_text().startswith("#usda 1.0")
    assert (tmp_path / "scene.usdc").read_bytes().startswith(b"PXR-USDC")
    write_usd(scene, assets, tmp_path / "scene.usda")  # replaces the file
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.usd", "scene.usda", "scene.usdc"]
    with pytest.raises(UserError, match="must end with"):
        write_usd(scene, assets, tmp_path / "scene.glb")


def test_ids_that_are_not_prim_names(pxr, tmp_path):
    scene, assets = tiny_scene(["1 lamp/0", "a|b", "a_b", "a/b"])
    stage = pxr.Usd.Stage.Open(str(write_usd(scene, assets, tmp_path / "s.usda")))
    prims = object_prims(stage)
    assert sorted(prims) == sorted(o.id for o in scene.objects)
    names = [p.GetName() for p in prims.values()]
    assert len(set(names)) == len(names)
    assert all(pxr.Sdf.Path.IsValidIdentifier(n) for n in names)


def test_dynamic_policies(pxr, bedroom, tmp_path):
    from pxr import UsdPhysics

    scene, assets = bedroom
    counts = {}
    for policy in ("none", "small", "all"):
        path = write_usd(scene, assets, tmp_path / f"{policy}.usdc", policy)
        stage = pxr.Usd.Stage.Open(str(path))  # (a new name: USD caches open layers)
        counts[policy] = sum(p.HasAPI(UsdPhysics.RigidBodyAPI) for p in stage.Traverse())
        expected = sum(b.dynamic for b in scene_physics(scene, assets, policy).values())
        assert counts[policy] == expected
    assert counts["none"] == 0 < counts["small"] <= counts["all"]
    with pytest.raises(UserError):
        write_usd(scene, assets, tmp_path / "s.usdc", "some")


def test_without_usd_core_says_what_to_install(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "pxr", None)  # import pxr raises ImportError
    scene, assets = tiny_scene()
    with pytest.raises(UserError) as info:
        write_usd(scene, assets, tmp_path / "scene.usda")
    assert str(info.value) == NEEDS_USD
    assert "pip install 'pair2scene[usd]'" in str(info.value)
    assert not any(tmp_path.iterdir())


def tiny_scene(mug_ids=("mug_0",)) -> tuple[Scene, dict]:
    """A table (fixed) with mugs (free) on it, one per id."""
    room = Room("bedroom", np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float), 2.6)
    table = OrientedBox.from_yaw([1, 1, 0.3], [0.8, 0.8, 0.6])
    objects = [SceneObject("table", "side_table", table, None, FLOOR)]
    for i, oid in enumerate(mug_ids):
        box = OrientedBox.from_yaw([0.8 + 0.15 * i, 1.0, 0.7], [0.1, 0.1, 0.2], 0.3 * i)
        objects.append(SceneObject(oid, "mug", box, None, "table"))
    assets = {o.id: generate(o.category, o.box.size, 0) for o in objects}
    return Scene("tiny", room, objects), assets
