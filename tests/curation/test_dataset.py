"""3D-Pairs on disk: round trip, determinism, integrity checks, the resumable writer."""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest

from pair2scene.curation.dataset import (
    CATEGORY_VOCAB,
    MANIFEST,
    PairsWriter,
    load_pairs,
    write_pairs,
)
from pair2scene.curation.tuples import PairTuple, RelationKind, scene_tuples
from pair2scene.errors import UserError
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, AssetRef, Room, Scene, SceneObject


def make_scene(i: int, rng: np.random.Generator) -> Scene:
    """A room with a table (rotated), a chair at it, a mug on it and a sofa."""
    room = Room(["bedroom", "kitchen"][i % 2], np.array([[0, 0], [5, 0], [5, 4], [0, 4]], float))
    yaw = rng.uniform(-np.pi, np.pi)
    table = OrientedBox.from_yaw([2.5, 2.0, 0.375], [1.2, 0.8, 0.75], yaw)
    objects = [
        SceneObject("table_0", "dining_table", table, AssetRef("ai2thor", f"T{i}", None), FLOOR),
        SceneObject("mug_0", "mug", OrientedBox.from_yaw([2.5, 2.0, 0.8], [0.1] * 3, yaw + 0.3),
                    AssetRef("procedural", None, i % 3), "table_0"),
        SceneObject("chair_0", "chair", OrientedBox.from_yaw([2.5, 1.2, 0.45], [0.5, 0.5, 0.9]),
                    None, FLOOR, functional_anchor="table_0"),
        SceneObject("sofa_0", "unknown", OrientedBox.from_yaw([1, 3.5, 0.4], [2, 0.9, 0.8]),
                    AssetRef("user", "my sofa ü", None), FLOOR),
    ]  # fmt: skip
    split = None if i == 0 else ["train", "val"][i % 2]
    return Scene(f"test/{i}", room, objects, source=["ai2thor", "procthor"][i % 2], split=split)


def make_tuples(n_scenes: int = 5, seed: int = 0) -> list[PairTuple]:
    rng = np.random.default_rng(seed)
    return [t for i in range(n_scenes) for t in scene_tuples(make_scene(i, rng))]


def assert_same_tuples(a: list[PairTuple], b: list[PairTuple]) -> None:
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert (x.source, x.scene_id, x.split, x.room_type, x.kind) == (
            y.source, y.scene_id, y.split, y.room_type, y.kind
        )  # fmt: skip
        for mx, my in ((x.dependent, y.dependent), (x.support, y.support),
                       (x.functional, y.functional)):  # fmt: skip
            assert (mx is None) == (my is None)
            if mx is not None:
                assert (mx.id, mx.category, mx.asset) == (my.id, my.category, my.asset)
                assert mx.box.allclose(my.box, atol=1e-5)
        assert x.canonical.allclose(y.canonical, atol=1e-5)
        assert (x.canonical_functional is None) == (y.canonical_functional is None)
        if x.canonical_functional is not None:
            assert x.canonical_functional.allclose(y.canonical_functional, atol=1e-5)


def test_round_trip(tmp_path):
    tuples = make_tuples()
    manifest = write_pairs(tuples, tmp_path, shard_size=7)
    assert manifest["count"] == len(tuples) == 20
    assert [s["count"] for s in manifest["shards"]] == [7, 7, 6]
    ds = load_pairs(tmp_path)
    assert len(ds) == 20
    assert_same_tuples(ds.to_tuples(), tuples)
    # the arrays themselves
    assert ds.dependent.box.shape == (20, 12) and ds.dependent.box.dtype == np.float32
    assert ds.categories == CATEGORY_VOCAB
    assert [ds.categories[c] for c in ds.dependent.category[:4]] == [
        "dining_table", "mug", "chair", "unknown"
    ]  # fmt: skip
    assert list(ds.support.id[:4]) == [FLOOR, "table_0", FLOOR, FLOOR]
    assert list(ds.support.asset_source[:2]) == ["", "ai2thor"]  # the floor has no asset
    assert list(ds.functional.present[:4]) == [False, False, True, False]
    assert np.isnan(ds.functional.box[0]).all() and np.isnan(ds.canonical_functional[0]).all()
    assert ds.kind_mask(RelationKind.FUNCTIONAL).sum() == 5
    assert list(ds.split[:1]) == [""] and ds.tuple(0).split is None
    np.testing.assert_allclose(ds.canonical[1, :3], [0, 0, (0.8 - 0.375) / 0.375], atol=1e-6)


def test_counts_in_the_manifest(tmp_path):
    manifest = write_pairs(make_tuples(), tmp_path, shard_size=7)
    counts = manifest["counts"]
    assert counts["tuples"] == 20
    assert counts["per_source"] == {"ai2thor": 12, "procthor": 8}
    assert counts["per_kind"] == {"floor": 10, "functional": 5, "support": 5}
    assert counts["per_source_kind"]["procthor"] == {"floor": 4, "functional": 2, "support": 2}
    assert counts["per_pair"]["support"]["floor"] == {"chair": 5, "dining_table": 5, "unknown": 5}
    assert counts["per_pair"]["support"]["dining_table"] == {"mug": 5}
    assert counts["per_pair"]["functional"] == {"dining_table": {"chair": 5}}
    assert manifest["kinds"] == ["floor", "support", "functional"]
    on_disk = json.loads((tmp_path / MANIFEST).read_text())
    assert on_disk == manifest and on_disk["complete"] is True


def test_shards_hold_plain_arrays_only(tmp_path):
    manifest = write_pairs(make_tuples(), tmp_path)
    path = tmp_path / manifest["shards"][0]["file"]
    with np.load(path, allow_pickle=False) as z:
        assert all(z[k].dtype != object for k in z.files)
        assert z["dep_box"].dtype == np.float32 and z["dep_cat"].dtype == np.int32
    with zipfile.ZipFile(path) as zf:
        assert {i.date_time for i in zf.infolist()} == {(1980, 1, 1, 0, 0, 0)}


def test_same_tuples_same_bytes(tmp_path):
    a = write_pairs(make_tuples(), tmp_path / "a", shard_size=7)
    b = write_pairs(make_tuples(), tmp_path / "b", shard_size=7)
    assert a == b
    for s in a["shards"]:
        files = [tmp_path / run / s["file"] for run in ("a", "b")]
        assert files[0].read_bytes() == files[1].read_bytes()


def test_empty_dataset(tmp_path):
    manifest = write_pairs([], tmp_path)
    assert manifest["count"] == 0
    ds = load_pairs(tmp_path)
    assert len(ds) == 0 and ds.canonical.shape == (0, 12) and ds.to_tuples() == []


def test_corrupt_shard_is_detected(tmp_path):
    manifest = write_pairs(make_tuples(), tmp_path, shard_size=7)
    shard = tmp_path / manifest["shards"][1]["file"]
    data = bytearray(shard.read_bytes())
    data[len(data) // 2] ^= 0xFF
    shard.write_bytes(bytes(data))
    with pytest.raises(UserError, match=r"corrupt shard .*rerun curate"):
        load_pairs(tmp_path)
    writer = PairsWriter(tmp_path)
    keys = [s["key"] for s in manifest["shards"]]
    assert [writer.finished(k) is not None for k in keys] == [True, False, True]
    shard.unlink()
    with pytest.raises(UserError, match="cannot read shard"):
        load_pairs(tmp_path)


def test_writer_resumes_and_finalizes(tmp_path):
    tuples = make_tuples()
    writer = PairsWriter(tmp_path)
    writer.write("a", tuples[:5], meta={"n": 1})
    writer.write("stale", tuples[5:6])
    with pytest.raises(UserError, match="did not finish"):
        load_pairs(tmp_path)
    assert len(load_pairs(tmp_path, allow_incomplete=True)) == 6

    again = PairsWriter(tmp_path)  # a new run: what the first one finished is there
    assert again.finished("a")["meta"] == {"n": 1}
    assert again.finished("b") is None
    again.write("b", tuples[5:])
    manifest = again.finalize(["b", "a"])
    assert [s["key"] for s in manifest["shards"]] == ["b", "a"]
    assert sorted(p.name for p in (tmp_path / "shards").iterdir()) == [
        "shard-a.npz",
        "shard-b.npz",
    ]  # the stale shard is gone
    assert_same_tuples(load_pairs(tmp_path).to_tuples(), tuples[5:] + tuples[:5])

    fresh = PairsWriter(tmp_path, fresh=True)
    assert fresh.finished("a") is None


def test_refuses_a_foreign_manifest(tmp_path):
    (tmp_path / MANIFEST).write_text('{"format": "something.else"}')
    with pytest.raises(UserError, match="not a pair2scene.pairs manifest"):
        PairsWriter(tmp_path)
    with pytest.raises(UserError, match="not a pair2scene.pairs manifest"):
        load_pairs(tmp_path)
    with pytest.raises(UserError, match="no such file"):
        load_pairs(tmp_path / "nowhere")


def test_bad_keys_and_categories(tmp_path):
    writer = PairsWriter(tmp_path)
    with pytest.raises(ValueError, match="shard key"):
        writer.write("../x", [])
    t = make_tuples(1)[0]
    bad = PairTuple(
        **{**t.__dict__, "dependent": type(t.dependent)("x", "spaceship", None, t.dependent.box)}
    )
    with pytest.raises(ValueError, match="not in the canonical vocabulary"):
        writer.write("k", [bad])
