import json
import zipfile

import pytest

from pair2scene.data import fetch as fetch_mod
from pair2scene.errors import UserError


@pytest.fixture()
def tmp_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PAIR2SCENE_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def test_unknown_source(tmp_cache):
    with pytest.raises(UserError, match="unknown source 'nope'"):
        fetch_mod.fetch("nope")


def test_missing_local_wheel(tmp_cache, tmp_path):
    with pytest.raises(UserError, match="no such wheel"):
        fetch_mod.fetch("ai2thor", wheel=tmp_path / "missing.whl")


def test_wrong_checksum_is_refused_and_nothing_is_left(tmp_cache, tmp_path):
    fake = tmp_path / "procthor-0.0.1.dev2-py3-none-any.whl"
    with zipfile.ZipFile(fake, "w") as zf:
        zf.writestr("procthor/databases/asset-database.json", "{}")
    with pytest.raises(UserError, match="sha256 .* does not match"):
        fetch_mod.fetch("ai2thor", wheel=fake)
    assert not (tmp_cache / "ai2thor").exists()
    assert not any(p.name.startswith(".ai2thor-") for p in tmp_cache.iterdir())


def test_fetch_downloads_checks_and_extracts(tmp_cache):
    """A real download from PyPI, as `pair2scene data fetch ai2thor` on a fresh machine."""
    root = fetch_mod.fetch("ai2thor")
    assert root == tmp_cache / "ai2thor"
    marker = json.loads((root / fetch_mod.MARKER).read_text())
    assert marker["sha256"] == fetch_mod.PROCTHOR_WHEEL.sha256
    for name in ("ai2thor-object-metadata.json", "asset-database.json"):
        assert (root / "databases" / name).stat().st_size > 1_000_000
    mtime = (root / fetch_mod.MARKER).stat().st_mtime_ns
    assert fetch_mod.fetch("ai2thor") == root  # cached: no second download
    assert (root / fetch_mod.MARKER).stat().st_mtime_ns == mtime
