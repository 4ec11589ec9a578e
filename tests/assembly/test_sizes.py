"""Sizes drawn from the data: observed combinations, jitter, fallback, file errors."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.sizes import KEEP_PER_CATEGORY, SizeTable
from pair2scene.curation.dataset import load_pairs
from pair2scene.errors import UserError
from synthetic_pairs import write_synthetic_pairs


def test_table_from_pairs_round_trips_and_draws_observed_sizes(tmp_path):
    data = load_pairs(write_synthetic_pairs(tmp_path / "pairs"))
    table = SizeTable.from_pairs(data)
    assert set(table.sizes) == {"desk", "mug", "chair", "sofa"}
    np.testing.assert_allclose(table.sizes["desk"], [[1.2, 0.6, 0.75]])
    table.save(tmp_path / "sizes.json")
    back = SizeTable.load(tmp_path / "sizes.json")
    rng = np.random.default_rng(0)
    draws = np.stack([back.draw("desk", rng) for _ in range(500)])
    ratio = np.log(draws / [1.2, 0.6, 0.75])
    assert abs(ratio.mean()) < 0.01 and 0.04 < ratio.std() < 0.06
    a = back.draw("sofa", np.random.default_rng(3))
    assert np.array_equal(a, back.draw("sofa", np.random.default_rng(3)))
    assert back.draw("bed", rng).shape == (3,)  # unseen: the typical size


def test_bundled_table_and_errors(tmp_path):
    table = SizeTable.load()
    assert len(table.sizes) > 80
    assert all(1 <= len(s) <= KEEP_PER_CATEGORY for s in table.sizes.values())
    bed = table.sizes["bed"]
    assert (bed[:, 1] > 1.5).all() and (bed[:, 2] < 2.5).all()  # bunk beds reach 2.3 m
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "pair2scene.sizes", "version": 1, "sizes": {"bed": [[1, -2, 3]]}}')
    with pytest.raises(UserError, match="finite and positive"):
        SizeTable.load(bad)
    bad.write_text('{"format": "other"}')
    with pytest.raises(UserError, match="format is not"):
        SizeTable.load(bad)


def test_a_mounted_size_is_never_deeper_than_wide():
    """A source box read a quarter turn off (a towel rail 0.66 m out from its wall) is
    turned when drawn for a wall; on the floor the same size stays as observed."""
    from pair2scene.curation.stats import WALL_MARK

    rail = [0.11, 0.66, 0.04]
    table = SizeTable({"towel_holder" + WALL_MARK: np.array([rail]),
                       "towel_holder": np.array([rail])})  # fmt: skip
    for seed in range(20):
        hung = table.draw("towel_holder", np.random.default_rng(seed), mounted=True)
        assert hung[0] > hung[1] and hung[0] == pytest.approx(0.66, rel=0.2)
        free = table.draw("towel_holder", np.random.default_rng(seed))
        np.testing.assert_allclose(free, hung[[1, 0, 2]])  # the same draw, not turned
    bundled = SizeTable.load()
    cats = ("towel_holder", "microwave", "toilet_paper_hanger")
    draws = [
        bundled.draw(c, np.random.default_rng(s), mounted=True) for c in cats for s in range(40)
    ]
    assert all(d[0] >= d[1] for d in draws)


def test_a_bat_rests_lying_on_a_face_of_its_round_parts():
    """The data's bats stand on end (they lean in their simulator; ours toppled): drawn to
    rest, a bat's size is laid down, longest along x and shortest up, and its round
    parts lie on a face (two vertices at the lowest height), not an edge it rolls off."""
    from pair2scene.assembly.place import library_assets
    from pair2scene.assets.registry import generate

    table = SizeTable.load()
    assert (table.sizes["baseball_bat"][:, 2] > table.sizes["baseball_bat"][:, 0]).all()
    rng = np.random.default_rng(0)
    for _ in range(8):
        size = table.draw("baseball_bat", rng)
        assert size[0] > 4 * max(size[1], size[2])  # (the two thin sides within jitter)
        bat = generate("baseball_bat", size, int(rng.integers(2**31)))
        for part in bat.parts:
            if part.name in ("barrel", "handle", "grip", "end_cap"):
                z = part.mesh.vertices[:, 2]
                assert (z < z.min() + 1e-6).sum() >= 2, part.name
    sofa = table.draw("sofa", rng, jitter=0.0)  # any other category as the data has it
    assert any(np.array_equal(sofa, row) for row in table.sizes["sofa"])
    bats = [a for a in library_assets(table) if a.category == "baseball_bat"]
    assert bats and all(a.size[0] > a.size[2] for a in bats)
