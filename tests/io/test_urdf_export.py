"""URDF export (:mod:`pair2scene.io.urdf`): a generated bedroom written with ``write_urdf``
and read back by a URDF parser (yourdfpy, optional: ``pip install yourdfpy``), by MuJoCo
(a dependency: it compiles ``scene.urdf`` and simulates it) and, where installed, by
PyBullet the way its users load scenes (one ``loadURDF`` per ``scene_urdf.json`` entry).
Also the rotation conversions, names of awkward ids and the atomic folder write."""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from pair2scene.assets.registry import generate
from pair2scene.io import urdf as urdf_module
from pair2scene.io.physical import scene_physics
from pair2scene.io.scene_meshes import room_meshes
from pair2scene.io.urdf import (
    COMBINED_FILE,
    ROOM_FILE,
    SCENE_FILE,
    quat_xyzw,
    rpy,
    write_urdf,
)
from pair2scene.scene.geometry import OrientedBox, rot_x, rot_y, rot_z
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

SETTLE_S = 0.5
"""Seconds of MuJoCo simulation in which the generated scene must stay put."""
SETTLE_TOL_M = 0.02
"""How far a free body may move in that time (a resting object moves well under 1 mm)."""


@pytest.fixture(scope="module")
def bedroom():
    from pair2scene import Pair2Scene

    r = Pair2Scene.from_pretrained().generate(room="bedroom", seed=0)
    return r.scene, r.assets


@pytest.fixture(scope="module")
def written(bedroom, tmp_path_factory):
    """(scene, assets, folder, scene_urdf.json document) of the bedroom written as URDF."""
    scene, assets = bedroom
    folder = write_urdf(scene, assets, tmp_path_factory.mktemp("urdf") / "bedroom")
    doc = json.loads((folder / SCENE_FILE).read_text())
    return scene, assets, folder, doc


def all_urdfs(folder: Path) -> list[Path]:
    objects = sorted((folder / "objects").glob("*.urdf"))
    return [folder / COMBINED_FILE, folder / ROOM_FILE, *objects]


def box_transform(obj) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = obj.box.rotation, obj.box.center
    return m


def test_scene_file_lists_every_object(written):
    scene, assets, folder, doc = written
    bodies = scene_physics(scene, assets)
    assert doc["format"] == "pair2scene.scene_urdf" and doc["up_axis"] == "z"
    assert [e["id"] for e in doc["objects"]] == [o.id for o in scene.objects]
    assert (folder / doc["room"]["urdf"]).is_file() and doc["room"]["fixed"]
    for entry, obj in zip(doc["objects"], scene.objects):
        assert (folder / entry["urdf"]).is_file()
        assert entry["fixed"] is not bodies[obj.id].dynamic
        assert entry["category"] == obj.category
        assert np.allclose(entry["position"], obj.box.center, atol=1e-6)
        from_xyzw = Rotation.from_quat(entry["quat_xyzw"]).as_matrix()
        from_wxyz = Rotation.from_quat(np.roll(entry["quat_wxyz"], -1)).as_matrix()
        from_rpy = Rotation.from_euler("xyz", entry["rpy"]).as_matrix()  # fixed axes x, y, z
        for m in (from_xyzw, from_wxyz, from_rpy):
            assert np.allclose(m, obj.box.rotation, atol=1e-6)
        assert entry["mass"] == pytest.approx(bodies[obj.id].mass, rel=1e-6)
    assert any(e["fixed"] for e in doc["objects"]) and not all(e["fixed"] for e in doc["objects"])


def test_every_urdf_loads_with_its_meshes(written):
    yourdfpy = pytest.importorskip("yourdfpy")
    _, _, folder, _ = written
    for path in all_urdfs(folder):
        robot = yourdfpy.URDF.load(
            str(path),
            load_meshes=True,
            build_collision_scene_graph=True,
            load_collision_meshes=True,
        )
        assert robot.validate(), path
        for mesh in ET.parse(path).iter("mesh"):
            file = path.parent / mesh.get("filename")
            assert not Path(mesh.get("filename")).is_absolute() and file.is_file(), file
        colliding = [link.name for link in robot.robot.links if link.collisions]
        assert len(robot.collision_scene.geometry) == len(colliding)  # one mesh per link


def test_object_links(written):
    yourdfpy = pytest.importorskip("yourdfpy")
    scene, assets, folder, doc = written
    bodies = scene_physics(scene, assets)
    for entry in doc["objects"]:
        body = bodies[entry["id"]]
        robot = yourdfpy.URDF.load(str(folder / entry["urdf"]), load_meshes=False)
        (link,) = robot.robot.links
        inertial = link.inertial
        assert inertial.mass == pytest.approx(body.mass, rel=1e-6) and inertial.mass > 0
        assert np.allclose(inertial.origin[:3, 3], body.com, atol=1e-8)
        assert np.allclose(inertial.origin[:3, :3], np.eye(3))
        tensor = np.asarray(inertial.inertia)
        assert np.allclose(tensor, tensor.T)
        assert np.allclose(tensor, body.inertia, rtol=1e-6, atol=1e-12)
        moments = np.linalg.eigvalsh(tensor)
        assert moments[0] > 0  # positive definite
        a, b, c = moments
        assert a + b >= c * (1 - 1e-9)  # triangle inequality of the principal moments
        assert len(link.collisions) == len(body.parts) and len(link.visuals) == 1
        for collision, part in zip(link.collisions, body.parts):
            file = (folder / entry["urdf"]).parent / collision.geometry.mesh.filename
            mesh = trimesh.load(file, force="mesh", process=False)
            assert np.allclose(mesh.vertices, part.vertices, atol=1e-8)
            assert np.array_equal(mesh.faces, part.faces)


def test_combined_scene_poses(written):
    yourdfpy = pytest.importorskip("yourdfpy")
    scene, assets, folder, doc = written
    robot = yourdfpy.URDF.load(str(folder / COMBINED_FILE), load_meshes=False)
    assert len(robot.robot.links) == len(scene.objects) + 2  # world, room
    joints = {j.child: j for j in robot.robot.joints}
    for entry, obj in zip(doc["objects"], scene.objects):
        joint = joints[entry["name"]]
        assert joint.parent == "world"
        assert joint.type == ("fixed" if entry["fixed"] else "floating")
        pose = robot.get_transform(entry["name"], "world")
        assert np.allclose(pose, box_transform(obj), atol=1e-7)


def test_mujoco_loads_and_simulates_scene_urdf(written):
    """MuJoCo compiles ``scene.urdf``: fixed objects fused into the world, one free body
    per dynamic object at its pose with its mass, a geom per convex part and room piece;
    half a second of simulation leaves every object where it was placed."""
    import mujoco

    scene, assets, folder, doc = written
    bodies = scene_physics(scene, assets)
    model = mujoco.MjModel.from_xml_path(str(folder / COMBINED_FILE))
    free = [e for e in doc["objects"] if not e["fixed"]]
    assert model.nbody == 1 + len(free)
    assert model.njnt == len(free)
    assert all(t == mujoco.mjtJoint.mjJNT_FREE for t in model.jnt_type)
    n_parts = sum(len(b.parts) for b in bodies.values())
    assert model.ngeom == n_parts + len(room_meshes(scene.room))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    for entry in free:
        body = model.body(entry["name"])
        assert body.mass[0] == pytest.approx(entry["mass"], rel=1e-6)
        assert np.allclose(data.xpos[body.id], entry["position"], atol=1e-6)
        assert abs(abs(np.dot(data.xquat[body.id], entry["quat_wxyz"])) - 1) < 1e-6
    start = data.xpos.copy()
    for _ in range(round(SETTLE_S / model.opt.timestep)):
        mujoco.mj_step(model, data)
    moved = np.linalg.norm(data.xpos - start, axis=1)
    assert moved.max() < SETTLE_TOL_M, dict(zip([e["id"] for e in free], moved[1:].round(4)))
    for path in all_urdfs(folder)[1:]:  # the single files compile too (as static bodies)
        mujoco.MjModel.from_xml_path(str(path))


def test_pybullet_loads_the_scene_file(written):
    """What a PyBullet user does: ``room.urdf`` fixed, then each entry of
    ``scene_urdf.json`` at its pose, fixed or free."""
    pybullet = pytest.importorskip("pybullet")
    scene, assets, folder, doc = written
    bodies = scene_physics(scene, assets)
    client = pybullet.connect(pybullet.DIRECT)
    try:
        kw = {"physicsClientId": client}
        pybullet.loadURDF(str(folder / ROOM_FILE), useFixedBase=True, **kw)
        for e in doc["objects"]:
            uid = pybullet.loadURDF(
                str(folder / e["urdf"]),
                e["position"],
                e["quat_xyzw"],
                useFixedBase=e["fixed"],
                **kw,
            )
            # PyBullet reports the base's centre of mass, the link frame's origin + com
            com = Rotation.from_quat(e["quat_xyzw"]).apply(bodies[e["id"]].com)
            position, orientation = pybullet.getBasePositionAndOrientation(uid, **kw)
            assert np.allclose(position, np.add(e["position"], com), atol=1e-6)
            assert abs(abs(np.dot(orientation, e["quat_xyzw"])) - 1) < 1e-6
            if not e["fixed"]:
                mass = pybullet.getDynamicsInfo(uid, -1, **kw)[0]
                assert mass == pytest.approx(e["mass"], rel=1e-6)
        assert pybullet.getNumBodies(**kw) == len(doc["objects"]) + 1
    finally:
        pybullet.disconnect(client)


@pytest.mark.parametrize(
    "rotation",
    [
        np.eye(3),
        rot_z(np.pi),
        rot_z(-np.pi / 2),
        rot_x(np.pi),
        rot_y(np.pi / 2) @ rot_z(0.3),  # gimbal lock: pitch +90
        rot_y(-np.pi / 2) @ rot_x(0.7),  # pitch -90
        *Rotation.random(20, random_state=0).as_matrix(),
    ],
)
def test_rotation_conversions(rotation):
    q = quat_xyzw(rotation)
    assert q[3] >= 0 and math.isclose(np.linalg.norm(q), 1.0)
    assert np.allclose(Rotation.from_quat(q).as_matrix(), rotation, atol=1e-12)
    assert np.allclose(Rotation.from_euler("xyz", rpy(rotation)).as_matrix(), rotation, atol=1e-9)


def test_awkward_ids_get_unique_portable_names(tmp_path):
    ids = ["world", "room", "Lamp", "lamp", "a/b", "a|b", "../x"]
    scene, assets = tiny_scene(ids)
    folder = write_urdf(scene, assets, tmp_path / "out")
    doc = json.loads((folder / SCENE_FILE).read_text())
    names = [e["name"] for e in doc["objects"]]
    assert [e["id"] for e in doc["objects"]] == [o.id for o in scene.objects]
    lowered = [n.lower() for n in names] + ["world", "room"]
    assert len(set(lowered)) == len(lowered)
    for e in doc["objects"]:
        path = (folder / e["urdf"]).resolve()
        assert path.parent == (folder / "objects").resolve() and path.is_file()
    root = ET.parse(folder / COMBINED_FILE).getroot()
    links = [link.get("name") for link in root.iter("link")]
    assert len(set(links)) == len(links) == len(scene.objects) + 2


def test_folder_is_replaced_atomically(tmp_path, monkeypatch):
    scene, assets = tiny_scene(["mug_0"])
    folder = write_urdf(scene, assets, tmp_path / "out")
    before = {p.relative_to(folder): p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    bigger, bigger_assets = tiny_scene(["mug_0", "mug_1"])

    def broken(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(urdf_module, "_write_xml", broken)
    with pytest.raises(OSError, match="disk full"):
        write_urdf(bigger, bigger_assets, folder)
    after = {p.relative_to(folder): p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    assert after == before  # the old folder is untouched
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no temporary folder left
    monkeypatch.undo()
    write_urdf(bigger, bigger_assets, folder)
    doc = json.loads((folder / SCENE_FILE).read_text())
    assert [e["id"] for e in doc["objects"]] == ["table", "mug_0", "mug_1"]
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def tiny_scene(mug_ids=("mug_0",)) -> tuple[Scene, dict]:
    """A table (fixed) with mugs (free) on it, one per id."""
    room = Room("kitchen", np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float), 2.6)
    table = OrientedBox.from_yaw([1, 1, 0.3], [0.8, 0.8, 0.6])
    objects = [SceneObject("table", "side_table", table, None, FLOOR)]
    for i, oid in enumerate(mug_ids):
        box = OrientedBox.from_yaw([0.7 + 0.1 * i, 1.0, 0.65], [0.08, 0.08, 0.1], 0.3 * i)
        objects.append(SceneObject(oid, "mug", box, None, "table"))
    assets = {o.id: generate(o.category, o.box.size, 0) for o in objects}
    return Scene("tiny", room, objects), assets
