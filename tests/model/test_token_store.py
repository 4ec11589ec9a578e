"""Assets' encoder tokens kept on disk between processes, and the asset library that makes
them come back: the same scene whether tokens were read or computed."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.model.token_store import TokenStore, encoder_digest

G, D = 4, 6


def _tokens(seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return rng.standard_normal((G, D)).astype(np.float32), rng.random((G, 3)).astype(np.float32)


def test_tokens_come_back_bit_for_bit_and_bad_files_are_recomputed(tmp_path):
    store = TokenStore("abc", tmp_path)
    assert store.get("k1", (G, D)) is None
    tokens, centers = _tokens()
    store.put("k1", tokens, centers)
    back = store.get("k1", (G, D))
    assert back is not None
    assert back[0].tobytes() == tokens.tobytes() and back[1].tobytes() == centers.tobytes()
    assert store.get("k1", (G, D + 1)) is None  # another encoder's width: not these
    assert not store.path("k1").exists()  # (and the file is gone)
    store.path("k2").parent.mkdir(parents=True, exist_ok=True)
    store.path("k2").write_bytes(b"not an array")
    assert store.get("k2", (G, D)) is None and not store.path("k2").exists()
    assert not list(tmp_path.rglob("*.tmp"))  # written to a temporary name, then renamed
    left = store.path("k3").parent / ".k3.npy.abcdefgh.tmp"  # what a killed write left
    left.parent.mkdir(parents=True, exist_ok=True)
    left.write_bytes(b"half")
    store.put("k3", tokens, centers)
    assert not left.exists() and store.get("k3", (G, D)) is not None


def test_an_unwritable_store_costs_only_the_encoding(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("a file where the folder would go")
    store = TokenStore("abc", blocker)
    store.put("k1", *_tokens())  # no error
    assert store.get("k1", (G, D)) is None


def test_the_digest_changes_with_the_weights_and_the_point_count():
    state = {"a": np.ones((2, 3), np.float32), "b": np.zeros(4, np.float32)}
    same = encoder_digest({"b": state["b"], "a": state["a"]}, 2048)
    assert encoder_digest(state, 2048) == same
    assert encoder_digest(state, 1024) != same
    assert encoder_digest({**state, "a": state["a"] * 2}, 2048) != same


def test_a_scene_is_the_same_whether_its_tokens_were_read_or_computed(tmp_path, monkeypatch):
    """Two processes (two models) on one cache folder: the second encodes no asset of a
    scene the first made, and writes the same bytes; so does a model with no store."""
    pytest.importorskip("torch")
    from pair2scene.generate import Pair2Scene
    from pair2scene.io.scene_json import dumps_scene
    from pair2scene.model import api

    monkeypatch.setenv("PAIR2SCENE_CACHE", str(tmp_path))
    first = Pair2Scene.from_pretrained()
    scene = dumps_scene(first.generate(room="bedroom", seed=3).scene)
    stored = list((tmp_path / "tokens").rglob("*.npy"))
    assert stored  # the bedroom's assets

    second = Pair2Scene.from_pretrained()
    built = []  # an asset's cloud is built only to encode it
    cloud = api.asset_cloud
    monkeypatch.setattr(api, "asset_cloud", lambda *a, **k: built.append(1) or cloud(*a, **k))
    assert dumps_scene(second.generate(room="bedroom", seed=3).scene) == scene
    assert built == []
    assert sorted((tmp_path / "tokens").rglob("*.npy")) == sorted(stored)

    monkeypatch.setenv("PAIR2SCENE_CACHE", str(tmp_path / "other"))
    third = Pair2Scene.from_pretrained()
    third.model._store = False  # (as LayoutModel(..., token_store=False))
    assert third.model.token_store is None
    assert dumps_scene(third.generate(room="bedroom", seed=3).scene) == scene
    assert built and not (tmp_path / "other").exists()


def test_the_library_gives_one_mesh_per_observed_size(tmp_path, monkeypatch):
    """Assets of a category at an observed size are one mesh in every scene (its seed a
    function of category and size), at the size table's sizes unjittered; without the
    library each object's size is jittered and its mesh drawn anew."""
    pytest.importorskip("torch")
    from dataclasses import replace

    from pair2scene.assets.identity import library_seed
    from pair2scene.generate import Pair2Scene

    monkeypatch.setenv("PAIR2SCENE_CACHE", str(tmp_path))
    p2s = Pair2Scene.from_pretrained()
    sizes = p2s.placer.sizes
    seen: dict[tuple, int] = {}
    for seed in range(4):
        for asset in p2s.generate(room="bedroom", seed=seed).assets.values():
            key = (asset.category, np.round(asset.size, 4).tobytes())
            mesh = asset.extra.get("seed")
            assert seen.setdefault(key, mesh) == mesh
    assert len(seen) < sum(len(p2s.generate(room="bedroom", seed=s).assets) for s in range(4))
    bed = next(a for a in p2s.generate(room="bedroom", seed=0).assets.values()
               if a.category == "bed")  # fmt: skip
    observed = sizes.observed("bed")
    assert np.isclose(observed, bed.size).all(1).any()
    assert bed.extra["seed"] == library_seed("bed", bed.size)

    p2s.placer.config = replace(p2s.placer.config, asset_library=False)
    bed = next(a for a in p2s.generate(room="bedroom", seed=0).assets.values()
               if a.category == "bed")  # fmt: skip
    assert not np.isclose(observed, bed.size).all(1).any()  # jittered


def test_the_library_encoded_once_ahead(tmp_path, monkeypatch):
    """``library_assets`` builds each observed size's asset as generation does (a wall
    size turned wider than deep); ``store_tokens`` encodes those not stored yet."""
    from pair2scene.assembly.place import library_assets
    from pair2scene.assembly.sizes import SizeTable
    from pair2scene.assets.identity import library_seed
    from pair2scene.model.api import LayoutModel

    monkeypatch.setenv("PAIR2SCENE_CACHE", str(tmp_path))
    sizes = SizeTable({"chair": np.array([[0.5, 0.5, 0.9], [0.45, 0.5, 0.85]]),
                       "painting@wall": np.array([[0.04, 0.8, 0.6]])})  # fmt: skip
    assets = list(library_assets(sizes))
    assert [a.category for a in assets] == ["chair", "chair", "painting"]
    np.testing.assert_allclose(assets[2].size, [0.8, 0.04, 0.6])
    assert assets[0].extra["seed"] == library_seed("chair", [0.5, 0.5, 0.9])
    model = LayoutModel.from_pretrained()
    assert model.store_tokens(assets) == (3, 3)
    assert LayoutModel.from_pretrained().store_tokens(library_assets(sizes)) == (3, 0)


def test_cli_tokens_refuses_a_missing_model(tmp_path):
    from clitools import run_cli

    proc = run_cli("assets", "tokens", "--model", str(tmp_path / "nope"))
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1
    assert "nope" in proc.stderr and "Traceback" not in proc.stderr
