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


def test_sizes_drawn_as_often_as_the_room_types_objects_had_them(tmp_path):
    """Counts per size, pooled and per room type: a kitchen draws its counters as
    kitchens had them, a room type with few of a category draws as every room did, a
    table without counts, or a category but counters, draws evenly; fits narrows the
    weighted draw; JSON keeps them."""
    sizes = np.array([[0.6, 0.5, 0.9], [2.0, 0.6, 0.9], [3.0, 0.7, 0.9]])
    table = SizeTable(
        {"counter_top": sizes},
        counts={"counter_top": np.array([30.0, 60.0, 10.0])},
        room_counts={
            "kitchen": {"counter_top": np.array([0.0, 50.0, 10.0])},
            "bathroom": {"counter_top": np.array([30.0, 0.0, 0.0])},
            "bedroom": {"counter_top": np.array([0.0, 0.0, 2.0])},  # too few: pooled
        },
    )

    def shares(room_type, fits=None, t=table):
        rng = np.random.default_rng(0)
        got = [t.draw("counter_top", rng, 0.0, fits=fits, room_type=room_type)[0]
               for _ in range(3000)]  # fmt: skip
        return np.array([np.mean(np.isclose(got, w)) for w in sizes[:, 0]])

    np.testing.assert_allclose(shares("kitchen"), [0.0, 5 / 6, 1 / 6], atol=0.03)
    np.testing.assert_allclose(shares("bathroom"), [1.0, 0.0, 0.0])
    np.testing.assert_allclose(shares("bedroom"), [0.3, 0.6, 0.1], atol=0.03)
    np.testing.assert_allclose(shares(None), [0.3, 0.6, 0.1], atol=0.03)
    even = SizeTable({"counter_top": sizes})
    np.testing.assert_allclose(shares("kitchen", t=even), [1 / 3] * 3, atol=0.03)
    # furniture: its observed sizes evenly, whatever the counts
    sofa = SizeTable({"sofa": sizes}, counts={"sofa": np.array([30.0, 60.0, 10.0])})
    rng = np.random.default_rng(0)
    got = [sofa.draw("sofa", rng, 0.0, room_type="living_room")[0] for _ in range(3000)]
    np.testing.assert_allclose([np.mean(np.isclose(got, w)) for w in sizes[:, 0]], [1 / 3] * 3,
                               atol=0.03)  # fmt: skip
    assert sofa.weights("sofa") is None
    # fits: only the long ones; a bathroom had none of them, so every room's counts
    long = lambda s: s[:, 0] > 1.0  # noqa: E731
    np.testing.assert_allclose(shares("bathroom", long), [0.0, 6 / 7, 1 / 7], atol=0.03)
    assert table.footprint("counter_top") == pytest.approx(2.0 * 0.6)  # the weighted median
    table.save(tmp_path / "sizes.json")
    back = SizeTable.load(tmp_path / "sizes.json")
    np.testing.assert_array_equal(back.counts["counter_top"], [30, 60, 10])
    np.testing.assert_array_equal(back.room_counts["kitchen"]["counter_top"], [0, 50, 10])
    for bad_counts in ('{"counter_top": [1, 2]}', '{"counter_top": [1, -2, 3]}',
                       '{"sofa": [1]}', '[1, 2]'):  # fmt: skip
        (tmp_path / "bad.json").write_text(
            '{"format": "pair2scene.sizes", "version": 1, "sizes": {"counter_top": '
            f'{sizes.tolist()}}}, "counts": {bad_counts}}}'
        )
        with pytest.raises(UserError, match="malformed size table counts"):
            SizeTable.load(tmp_path / "bad.json")


def test_counts_from_pairs_count_each_object_once(tmp_path):
    """A chair in a floor tuple and a functional tuple is one chair; every kept size
    carries the objects that had it, and the counts sum to the objects."""
    data = load_pairs(write_synthetic_pairs(tmp_path / "pairs"))
    table = SizeTable.from_pairs(data)
    rows = data.split == "train"
    for cat in table.sizes:
        ci = data.categories.index(cat)
        found = zip(data.scene_id[rows], data.dependent.id[rows], data.dependent.category[rows])
        objects = {(s, i) for s, i, c in found if c == ci}
        assert table.counts[cat].sum() == len(objects)
        assert sum(per[cat].sum() for per in table.room_counts.values() if cat in per) == len(
            objects
        )


def test_bundled_counts_follow_the_training_rooms():
    """The bundled table draws a kitchen's counters at the kitchens' mean footprint
    (2.57 m2 over 234 counters; evenly over the observed sizes it was 1.86)."""
    table = SizeTable.load()
    sizes = table.sizes["counter_top"]
    area = sizes[:, 0] * sizes[:, 1]
    w = table.weights("counter_top", "kitchen")
    assert 2.3 < (area * w).sum() / w.sum() < 2.8 and w.sum() > 200
    w = table.weights("counter_top", "bathroom")
    assert (area * w).sum() / w.sum() < 1.6
    assert all(len(table.counts[k]) == len(s) for k, s in table.sizes.items())
