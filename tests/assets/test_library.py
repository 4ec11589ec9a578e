"""AssetLibrary: user meshes, a fake 3D-FUTURE folder, size fitting and fallbacks."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh

from pair2scene.assets import library as library_mod
from pair2scene.assets.library import MAX_PARTS, PARTS_NOTE, AssetLibrary, axis_rotation
from pair2scene.assets.mesh import Mesh, box_between
from pair2scene.assets.surfaces import support_surfaces
from pair2scene.errors import UserError


def write_obj(path: Path, mesh: Mesh) -> Path:
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in mesh.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in mesh.faces]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")
    return path


def write_ply(path: Path, mesh: Mesh) -> Path:
    trimesh.Trimesh(mesh.vertices, mesh.faces, process=False).export(path)
    return path


def chair_yup() -> Mesh:
    """A seat and a back modelled y-up with the front at +z: the back is at -z."""
    seat = box_between((-0.2, 0.40, -0.2), (0.2, 0.45, 0.2))
    back = box_between((-0.2, 0.45, -0.2), (0.2, 0.90, -0.16))
    return Mesh.concat([seat, back])


def make_lib(tmp_path: Path, entries: list[dict], **kw) -> AssetLibrary:
    (tmp_path / "assets.json").write_text(json.dumps(entries))
    return AssetLibrary(user_dir=tmp_path, bounds_cache=tmp_path / "cache" / "bounds.json", **kw)


def _back_side(asset) -> float:
    """Mean y of the render mesh's vertices in the upper half (the chair's back)."""
    v = asset.extra["render_mesh"].vertices
    return float(v[v[:, 2] > 0.1, 1].mean())


def test_axis_rotation_is_proper():
    r = axis_rotation("+y", "+z")
    assert np.allclose(r @ [0, 1, 0], [0, 0, 1])  # model up -> +z
    assert np.allclose(r @ [0, 0, 1], [0, 1, 0])  # model front -> +y
    assert np.linalg.det(r) == pytest.approx(1)
    assert np.allclose(axis_rotation(), np.eye(3))


def test_user_mesh_y_up_front_z_is_turned_and_fitted(tmp_path):
    write_obj(tmp_path / "chair_a.obj", chair_yup())
    lib = make_lib(
        tmp_path, [{"file": "chair_a.obj", "category": "chair", "up": "+y", "front": "+z"}]
    )
    size = np.array([0.5, 0.45, 1.0])
    a = lib.retrieve("chair", size, rng=0)
    assert a.source == "user" and a.asset_id == "chair_a.obj" and a.category == "chair"
    assert a.extra["parts"] == PARTS_NOTE
    assert np.allclose(a.mesh.bounds, [-size / 2, size / 2])
    assert np.allclose(a.extra["render_mesh"].bounds, [-size / 2, size / 2])
    assert len(a.parts) == 2 and all(p.mesh.is_convex() for p in a.parts)
    assert all(p.mesh.volume > 0 for p in a.parts)  # still outward after the rotation
    assert _back_side(a) < -0.2  # the back ends up behind (-y), the seat opening at +y
    # the seat is a support surface of the fitted asset (the back stands behind it)
    seat = [s for s in support_surfaces(a) if s.z < 0]
    assert len(seat) == 1 and seat[0].polygon[:, 1].max() == pytest.approx(size[1] / 2)


def test_default_orientation_and_scale(tmp_path):
    # modelled z-up, front +y, in centimetres
    m = box_between((0, 0, 0), (40, 40, 90))
    write_ply(tmp_path / "cm.ply", m)
    lib = make_lib(tmp_path, [{"file": "cm.ply", "category": "cabinet", "scale": 0.01}])
    (entry,) = lib.entries("cabinet")
    assert np.allclose(lib.extent(entry), [0.4, 0.4, 0.9])
    a = lib.retrieve("cabinet", [0.4, 0.4, 0.9])
    assert np.allclose(a.size, [0.4, 0.4, 0.9])


def test_closest_fit_between_aspects(tmp_path):
    write_obj(tmp_path / "tall.obj", box_between((0, 0, 0), (0.4, 0.4, 0.8)))
    write_ply(tmp_path / "wide.ply", box_between((0, 0, 0), (0.8, 0.4, 0.4)))
    lib = make_lib(
        tmp_path,
        [
            {"file": "tall.obj", "category": "side_table"},
            {"file": "wide.ply", "category": "side_table"},
        ],
    )
    for seed in range(5):
        assert lib.retrieve("side_table", [0.7, 0.4, 0.45], seed).asset_id == "wide.ply"
        assert lib.retrieve("side_table", [0.45, 0.4, 0.7], seed).asset_id == "tall.obj"


def test_near_ties_drawn_by_rng(tmp_path):
    write_obj(tmp_path / "a.obj", box_between((0, 0, 0), (0.5, 0.5, 0.5)))
    write_obj(tmp_path / "b.obj", box_between((0, 0, 0), (0.5, 0.5, 0.51)))
    lib = make_lib(
        tmp_path, [{"file": "a.obj", "category": "box"}, {"file": "b.obj", "category": "box"}]
    )
    picks = {lib.retrieve("box", [0.5, 0.5, 0.5], s).asset_id for s in range(12)}
    assert picks == {"a.obj", "b.obj"}
    same = [lib.retrieve("box", [0.5, 0.5, 0.5], 3).asset_id for _ in range(3)]
    assert len(set(same)) == 1


def test_fallbacks_for_categories_without_meshes(tmp_path):
    write_obj(tmp_path / "c.obj", chair_yup())
    lib = make_lib(tmp_path, [{"file": "c.obj", "category": "chair"}])
    a = lib.retrieve("bed", [1.6, 2.0, 0.9], rng=1)
    assert a.source in ("procedural", "box") and a.category == "bed"
    lib = make_lib(tmp_path, [{"file": "c.obj", "category": "chair"}], procedural=False)
    assert lib.retrieve("bed", [1.6, 2.0, 0.9]).source == "box"
    assert AssetLibrary(bounds_cache=tmp_path / "b.json").mesh_categories() == set()


@pytest.mark.parametrize(
    "mapping, needle",
    [
        ("{not json", "not valid JSON"),
        ('{"chairs": []}', "expected a list"),
        ('[{"file": "missing.obj", "category": "chair"}]', "no such file"),
        ('[{"file": "c.obj", "category": "throne"}]', "unknown category 'throne'"),
        ('[{"file": "c.obj", "category": "chair", "up": "up"}]', "'up' must be one of"),
        ('[{"file": "c.obj", "category": "chair", "up": "+y", "front": "-y"}]', "perpendicular"),
        ('[{"file": "c.obj", "category": "chair", "scale": -1}]', "'scale' must be"),
        ('[{"file": "c.obj", "category": "chair", "frnt": "+y"}]', "unknown key(s) frnt"),
        ('["c.obj"]', "expected an object"),
        ('[{"file": "notes.txt", "category": "chair"}]', "unsupported mesh format"),
    ],
)
def test_malformed_mapping_is_a_user_error(tmp_path, mapping, needle):
    write_obj(tmp_path / "c.obj", chair_yup())
    (tmp_path / "notes.txt").write_text("hello")
    (tmp_path / "assets.json").write_text(mapping)
    lib = AssetLibrary(user_dir=tmp_path, bounds_cache=tmp_path / "b.json")
    with pytest.raises(UserError) as err:
        lib.retrieve("chair", [0.5, 0.5, 0.9])
    msg = str(err.value)
    assert needle in msg and "assets.json" in msg and "\n" not in msg


def test_missing_mapping_or_folder_or_bad_mesh(tmp_path):
    with pytest.raises(UserError, match="assets.json"):
        AssetLibrary(user_dir=tmp_path).entries()
    with pytest.raises(UserError, match="not a folder"):
        AssetLibrary(user_dir=tmp_path / "nope").entries()
    (tmp_path / "bad.obj").write_text("this is not an obj\n")
    lib = make_lib(tmp_path, [{"file": "bad.obj", "category": "chair"}])
    with pytest.raises(UserError, match="bad.obj"):
        lib.retrieve("chair", [0.5, 0.5, 0.9])
    with pytest.raises(UserError, match="size"):
        lib.retrieve("chair", [0.5, 0.0, 0.9])


def test_future3d_folder(tmp_path):
    root = tmp_path / "3D-FUTURE-model"
    write_obj(root / "jid-chair" / "raw_model.obj", chair_yup())
    write_obj(root / "jid-sofa" / "normalized_model.obj", box_between((-1, -1, -0.5), (1, 1, 0.5)))
    info = [
        {"model_id": "jid-chair", "category": "Dining Chair", "super-category": "Chair"},
        {"model_id": "jid-sofa", "category": None, "super-category": "Sofa"},
        {"model_id": "jid-odd", "category": "Weird Thing", "super-category": "Others"},
        {"model_id": "jid-gone", "category": "armchair", "super-category": "Chair"},
    ]
    (root / "model_info.json").write_text(json.dumps(info))
    lib = AssetLibrary(future_dir=root, bounds_cache=tmp_path / "b.json")
    assert lib.mesh_categories() == {"chair", "sofa"}  # jid-gone has no files
    assert lib.future_labels.unknown["Weird Thing"] == 1
    a = lib.retrieve("chair", [0.45, 0.5, 0.9])
    assert a.source == "3dfuture" and a.asset_id == "jid-chair"
    assert _back_side(a) < -0.2  # y-up, front +z converted to z-up, front +y
    s = lib.retrieve("sofa", [2.0, 0.9, 0.8])
    assert s.asset_id == "jid-sofa" and np.allclose(s.mesh.bounds[1], [1.0, 0.45, 0.4])


def test_bounds_are_cached_on_disk(tmp_path, monkeypatch):
    write_obj(tmp_path / "a.obj", box_between((0, 0, 0), (0.4, 0.4, 0.8)))
    write_obj(tmp_path / "b.obj", box_between((0, 0, 0), (0.8, 0.4, 0.4)))
    entries = [{"file": "a.obj", "category": "desk"}, {"file": "b.obj", "category": "desk"}]
    make_lib(tmp_path, entries).retrieve("desk", [0.8, 0.4, 0.4])
    calls = []
    real = library_mod._read_mesh
    monkeypatch.setattr(library_mod, "_read_mesh", lambda p: calls.append(p.name) or real(p))
    assert make_lib(tmp_path, entries).retrieve("desk", [0.8, 0.4, 0.4]).asset_id == "b.obj"
    assert calls == ["b.obj"]  # ranking used the saved bounds; only the winner was read


def test_many_components_are_capped_and_flat_ones_thickened(tmp_path):
    cubes = [
        box_between((i % 10, i // 10, 0), (i % 10 + 0.5, i // 10 + 0.5, 0.5)) for i in range(90)
    ]
    quad = Mesh(
        np.array([[0, 0, 2.0], [9.5, 0, 2], [9.5, 8.5, 2], [0, 8.5, 2]]),
        np.array([[0, 1, 2], [0, 2, 3]]),
    )  # a top modelled as one flat quad
    write_obj(tmp_path / "grid.obj", Mesh.concat(cubes + [quad]))
    lib = make_lib(tmp_path, [{"file": "grid.obj", "category": "dining_table"}])
    a = lib.retrieve("dining_table", [1.9, 1.7, 0.4])
    assert len(a.parts) <= MAX_PARTS
    assert all(p.mesh.is_convex() for p in a.parts)
    assert np.allclose(a.mesh.bounds, [[-0.95, -0.85, -0.2], [0.95, 0.85, 0.2]])
    top = support_surfaces(a)[-1]
    assert top.area == pytest.approx(1.9 * 1.7, rel=1e-6)


def test_split_vertices_are_welded(tmp_path):
    # every triangle with its own vertices, as a file split along UV seams stores them
    m = box_between((0, 0, 0), (0.6, 0.4, 0.7))
    soup = Mesh(m.triangles.reshape(-1, 3), np.arange(len(m.faces) * 3).reshape(-1, 3))
    write_obj(tmp_path / "soup.obj", soup)
    lib = make_lib(tmp_path, [{"file": "soup.obj", "category": "safe"}])
    assert len(lib.retrieve("safe", [0.6, 0.4, 0.7]).parts) == 1
