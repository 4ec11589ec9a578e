"""The surface store: support surfaces kept on disk by asset geometry, read back to the bit."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assets import surface_store, surfaces
from pair2scene.assets.pointcloud import mesh_digest
from pair2scene.assets.registry import generate
from pair2scene.assets.surface_store import SurfaceStore, decode, encode
from pair2scene.assets.surfaces import support_surfaces, surfaces_of

# a counter with a sink cut in (a hole), a bunk bed (two levels, one under the other:
# a finite clearance), a shelving unit (tiers), a mug (a small top)
CASES = [
    ("counter_top", (1.8, 0.6, 0.9), {"style": 0}),
    ("sink", (0.6, 0.5, 0.9), {}),
    ("bed", (1.15, 2.5, 2.3), {}),
    ("shelving_unit", (0.8, 0.3, 1.8), {}),
    ("mug", (0.09, 0.09, 0.1), {}),
]


def _same(a, b) -> bool:
    return len(a) == len(b) and all(
        x.z == y.z
        and x.area == y.area
        and x.clearance == y.clearance
        and x.polygon.dtype == y.polygon.dtype
        and np.array_equal(x.polygon, y.polygon)
        and len(x.holes) == len(y.holes)
        and all(np.array_equal(h, k) for h, k in zip(x.holes, y.holes, strict=True))
        for x, y in zip(a, b, strict=True)
    )


@pytest.fixture(scope="module")
def assets():
    return [generate(c, size, rng=3, **kw) for c, size, kw in CASES]


def test_encode_decode_is_exact(assets):
    kinds = set()
    for asset in assets:
        found = support_surfaces(asset)
        assert found, asset.category
        back = decode(encode(found))
        assert _same(found, back)
        kinds |= {"hole" for s in found if s.holes}
        kinds |= {"open" if np.isinf(s.clearance) else "covered" for s in found}
    assert kinds == {"hole", "open", "covered"}  # the cases cover every field


def test_store_round_trip_and_bad_files(tmp_path, assets):
    store = SurfaceStore(tmp_path)
    asset = assets[0]
    key = mesh_digest(asset)
    assert store.get(key) is None
    found = support_surfaces(asset)
    store.put(key, found)
    assert store.path(key).is_file()
    assert _same(store.get(key), found)
    # a file that does not decode is deleted, and the next get finds nothing
    for garbage in (b"not numpy", None):
        if garbage is None:
            np.save(store.path(key), np.array([3.0, 1.0]))  # a count with nothing behind
        else:
            store.path(key).write_bytes(garbage)
        assert store.get(key) is None
        assert not store.path(key).exists()


@pytest.mark.parametrize(
    "data",
    [
        np.array([1.0, 0.1, 0.2, np.inf, 3.0]),  # truncated header
        np.array([1.0, 0.1, 0.2, np.inf, 1.0, 0.0, 0.0, 0.0, 1.0]),  # trailing value
        np.array([1.0, 0.1, 0.2, np.inf, -1.0, 0.0]),  # negative count
        np.array([1.0, 0.1, np.nan, np.inf, 1.0, 0.0, 0.0, 0.0]),  # NaN area
        np.array([0.5]),  # a count that is not whole
        np.array([[0.0]]),  # not flat
        np.array([0], np.int64),  # not float64
    ],
)
def test_decode_refuses_what_encode_never_wrote(data):
    with pytest.raises(ValueError):
        decode(data)


def test_surfaces_of_reads_what_another_process_stored(tmp_path, monkeypatch, assets):
    monkeypatch.setenv("PAIR2SCENE_CACHE", str(tmp_path))
    c, size, kw = CASES[0]
    first = surfaces_of(generate(c, size, rng=3, **kw))
    assert list((tmp_path / "surfaces").rglob("*.npy"))
    # a new asset object of the same geometry (as another process builds it): read, not
    # computed
    monkeypatch.setattr(surfaces, "support_surfaces", lambda *a, **k: pytest.fail("computed"))
    again = surfaces_of(generate(c, size, rng=3, **kw))
    assert _same(first, again)


def test_unwritable_cache_still_gives_surfaces(tmp_path, monkeypatch, assets):
    blocked = tmp_path / "file"
    blocked.write_text("a file where the cache folder would be")
    monkeypatch.setenv("PAIR2SCENE_CACHE", str(blocked))
    c, size, kw = CASES[3]
    assert _same(surfaces_of(generate(c, size, rng=3, **kw)), support_surfaces(assets[3]))


def test_the_folder_follows_the_code(monkeypatch):
    before = surface_store.code_digest()
    surface_store.code_digest.cache_clear()
    monkeypatch.setattr(surface_store, "STORE_FORMAT", surface_store.STORE_FORMAT + 1)
    try:
        assert surface_store.code_digest() != before
    finally:
        surface_store.code_digest.cache_clear()


def test_the_library_pass_fills_the_store(tmp_path, monkeypatch):
    """``library_assets(..., surfaces=True)`` (what ``pair2scene assets tokens`` walks)
    leaves each asset's surfaces in the store; without it, nothing is worked out."""
    from pair2scene.assembly.place import library_assets
    from pair2scene.assembly.sizes import SizeTable

    monkeypatch.setenv("PAIR2SCENE_CACHE", str(tmp_path))
    sizes = SizeTable({"side_table": np.array([[0.5, 0.45, 0.6], [0.4, 0.4, 0.55]])})
    stored = tmp_path / "surfaces"
    assert len(list(library_assets(sizes))) == 2 and not stored.exists()
    assets = list(library_assets(sizes, surfaces=True))
    assert len(list(stored.rglob("*.npy"))) == 2
    keys = {p.stem for p in stored.rglob("*.npy")}
    assert keys == {mesh_digest(a) for a in assets}
