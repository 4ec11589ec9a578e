"""MuJoCo export (pair2scene.io.mjcf): a generated bedroom loads from another working
directory, has one body per object with the shared physical properties, starts without
deep penetrations and stays put under gravity."""

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

from pair2scene.errors import UserError  # noqa: E402
from pair2scene.io.mjcf import (  # noqa: E402
    MESH_DIR,
    SCENE_XML,
    mjcf_files,
    model_text,
    write_mjcf,
)
from pair2scene.io.physical import scene_physics  # noqa: E402

MAX_PENETRATION_M = 0.005
MAX_MOTION_M = 0.02


@pytest.fixture(scope="module")
def bedroom():
    from pair2scene import Pair2Scene

    r = Pair2Scene.from_pretrained().generate(room="bedroom", seed=0)
    return r.scene, r.assets


@pytest.fixture(scope="module")
def exported(bedroom, tmp_path_factory):
    scene, assets = bedroom
    folder = tmp_path_factory.mktemp("mjcf") / "bedroom"
    return write_mjcf(scene, assets, folder)


@pytest.fixture()
def model(exported, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # relative mesh paths resolve against the XML's folder
    return mujoco.MjModel.from_xml_path(str(exported))


def _free_bodies(model) -> set[str]:
    free = mujoco.mjtJoint.mjJNT_FREE
    return {
        model.body(model.jnt_bodyid[j]).name for j in range(model.njnt) if model.jnt_type[j] == free
    }


def test_files_and_relative_mesh_paths(exported):
    folder = exported.parent
    assert exported.name == SCENE_XML and exported.is_file()
    meshes = sorted((folder / MESH_DIR).iterdir())
    assert meshes and all(p.suffix == ".obj" for p in meshes)
    xml = exported.read_text()
    assert f'meshdir="{MESH_DIR}"' in xml and str(folder) not in xml
    assert not [p for p in folder.parent.iterdir() if p.name.startswith(".")]  # no temporaries


def test_bodies_joints_and_properties(model, bedroom):
    scene, assets = bedroom
    physics = scene_physics(scene, assets)
    names = {model.body(b).name for b in range(1, model.nbody)}
    assert names == {o.id for o in scene.objects}
    assert model.nbody - 1 == len(scene.objects)
    assert _free_bodies(model) == {oid for oid, p in physics.items() if p.dynamic}
    assert any(p.dynamic for p in physics.values()) and not all(p.dynamic for p in physics.values())
    for oid, p in physics.items():
        b = model.body(oid)
        # (MJCF numbers have 6 significant digits)
        assert b.mass[0] == pytest.approx(p.mass, rel=1e-5)
        assert np.allclose(b.ipos, p.com, rtol=1e-5, atol=1e-6)
        assert np.allclose(np.sort(b.inertia), np.linalg.eigvalsh(p.inertia), rtol=1e-5)
        o = scene.get(oid)
        assert model_text(model, f"category:{oid}") == o.category
        assert model_text(model, f"support:{oid}") == o.support
        geoms = [model.geom(g) for g in range(model.ngeom) if model.geom_bodyid[g] == b.id]
        visual = [g for g in geoms if g.name == f"{oid}/visual"]
        assert len(visual) == 1 and visual[0].contype[0] == 0 and visual[0].conaffinity[0] == 0
        collision = [g for g in geoms if g.group[0] == 3]
        assert len(collision) == len(p.parts)
        assert all(g.friction[0] == pytest.approx(p.friction) for g in collision)


def test_room_is_static(model):
    floor = model.geom("floor")
    assert floor.bodyid[0] == 0 and floor.type[0] == mujoco.mjtGeom.mjGEOM_PLANE
    walls = [model.geom(g).name for g in range(model.ngeom) if model.geom_bodyid[g] == 0]
    assert any(n.startswith("wall_") for n in walls)


def test_no_deep_initial_penetration(model):
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert data.ncon > 0
    worst = float(data.contact.dist[: data.ncon].min())
    assert worst > -MAX_PENETRATION_M, worst


def test_free_objects_stay_put_for_one_second(model):
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    free = sorted(_free_bodies(model))
    ids = [model.body(n).id for n in free]
    start = data.xpos[ids].copy()
    for _ in range(int(round(1.0 / model.opt.timestep))):
        mujoco.mj_step(model, data)
    assert np.all(np.isfinite(data.qpos))
    moved = np.linalg.norm(data.xpos[ids] - start, axis=1)
    assert moved.max() < MAX_MOTION_M, dict(zip(free, moved.round(4)))


def test_dynamic_policies(bedroom):
    scene, assets = bedroom
    for dynamic in ("all", "none"):
        files = mjcf_files(scene, assets, dynamic)
        m = mujoco.MjModel.from_xml_string(files[SCENE_XML].decode(), _assets(files))
        expected = {o for o, p in scene_physics(scene, assets, dynamic).items() if p.dynamic}
        assert _free_bodies(m) == expected
    assert any(p.dynamic for p in scene_physics(scene, assets, "all").values())
    with pytest.raises(UserError):
        mjcf_files(scene, assets, "most")


def _assets(files: dict[str, bytes]) -> dict[str, bytes]:
    return {k[len(MESH_DIR) + 1 :]: v for k, v in files.items() if k.startswith(MESH_DIR + "/")}


def test_rewrite_into_an_existing_folder_keeps_other_files(bedroom, tmp_path):
    scene, assets = bedroom
    folder = tmp_path / "scene"
    folder.mkdir()
    (folder / "scene.json").write_text("{}")
    (folder / MESH_DIR).mkdir()
    (folder / MESH_DIR / "stale.obj").write_text("v 0 0 0\n")
    path = write_mjcf(scene, assets, folder)
    assert (folder / "scene.json").read_text() == "{}"
    assert not (folder / MESH_DIR / "stale.obj").exists()
    assert not [p for p in folder.iterdir() if p.name.startswith(".")]
    mujoco.MjModel.from_xml_path(str(path))
