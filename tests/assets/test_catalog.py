"""The asset catalogue, the typical-size table and the asset contact sheet."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from pair2scene.assets.catalog import parse_categories
from pair2scene.assets.sheet import asset_sheet
from pair2scene.assets.typical_sizes import asset_categories, typical_size, typical_sizes
from pair2scene.categories import CATEGORIES, is_structure
from pair2scene.errors import UserError


def test_typical_sizes_cover_every_asset_category():
    table = typical_sizes()
    names = {c.name for c in CATEGORIES if not is_structure(c.name)}
    assert set(table) == names
    for name, ts in table.items():
        assert all(0 < x < 5 for x in ts.size), name
        assert ts.source in {"ai2thor", "procthor", "hand"}
        assert (ts.count > 0) == (ts.source != "hand"), name
    assert table["chair"].source == "ai2thor" and table["wardrobe"].source == "hand"
    assert typical_size("not_in_table").source == "default"


def test_parse_categories():
    assert parse_categories(" bed, mug,bed ") == ["bed", "mug"]
    assert parse_categories(None) == asset_categories()
    for bad in ("nope", "bed,floor", " , "):
        with pytest.raises(UserError):
            parse_categories(bad)


def test_asset_sheet_marks_fallbacks_and_is_deterministic(tmp_path, monkeypatch):
    from pair2scene.assets import registry

    gens = dict(registry.generators())
    gens.pop("mug", None)  # mug falls back to a box whatever is registered by now
    monkeypatch.setattr(registry, "generators", lambda: gens)
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    res = asset_sheet(a, categories="bed,mug", seed=3, cell_px=64)
    asset_sheet(b, categories="bed,mug", seed=3, cell_px=64)
    assert res.categories == ["bed", "mug"] and res.box_fallback == ["mug"]
    assert not res.errors
    assert a.read_bytes() == b.read_bytes()
    with Image.open(a) as img:
        assert img.format == "PNG" and img.size == res.image_size
        px = np.asarray(img.convert("RGB")).astype(int)
    assert ((px[..., 0] > 150) & (px[..., 1] < 60) & (px[..., 2] < 60)).any()  # red label


def test_asset_sheet_shows_a_broken_generator(tmp_path, monkeypatch):
    from pair2scene.assets import registry

    def boom(size, rng, style, heights):
        raise ValueError("bad leg")

    gens = {"bed": registry.Generator("bed", boom, 1, "broken")}
    monkeypatch.setattr(registry, "generators", lambda: gens)
    res = asset_sheet(tmp_path / "s.png", categories=["bed"], cell_px=48)
    assert res.errors == {"bed": "ValueError: bad leg"}
    assert (tmp_path / "s.png").is_file()
