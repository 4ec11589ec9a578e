"""The pair table (model/pair_prior.py): which pairs get a centre and which member keys
it, that the predictor adds exactly the table's centre to every component, the trainer
fills it from the train tuples only, and checkpoints keep it (older ones read as off)."""

from __future__ import annotations

import json

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from pair2scene.curation.dataset import CATEGORY_VOCAB  # noqa: E402
from pair2scene.curation.frames import (  # noqa: E402
    FRAME_FUNCTIONAL,
    FRAME_SUPPORT,
    FRAME_WALL,
)
from pair2scene.model.checkpoint import (  # noqa: E402
    expected_shapes,
    layout_config_from_dict,
    layout_config_to_dict,
)
from pair2scene.model.config import (  # noqa: E402
    FLOOR_INDEX,
    PAIR_PRIOR_MIN_TUPLES,
    WALL_INDEX,
    LayoutConfig,
    LayoutVariant,
)
from pair2scene.model.features import category_index  # noqa: E402
from pair2scene.model.layout import LayoutBatch, LayoutPredictor  # noqa: E402
from pair2scene.model.pair_prior import (  # noqa: E402
    CENTRE_DIMS,
    SHARE_PSEUDO_COUNT,
    frame_anchor,
    kmeans,
    mode_table_shape,
    pair_centre_table,
    pair_mode_table,
    pair_turn_table,
    table_rows,
    table_shape,
    turn_table_shape,
)

N = len(CATEGORY_VOCAB)
BED, PILLOW, BOOK = category_index("bed"), category_index("pillow"), category_index("book")
DESK, CHAIR = category_index("desk"), category_index("chair")


def tuples(rows: list[tuple[int, int, int, int, float, float]]):
    """(categories (n, 3), frames (n,), centres (n, 2)) from (dependent, support,
    functional or -1, frame, x, y) rows."""
    a = np.array(rows, dtype=np.float64)
    return a[:, :3].astype(np.int64), a[:, 3].astype(np.int64), a[:, 4:6]


def test_a_pair_with_enough_tuples_gets_its_median_and_a_rarer_one_none():
    k = PAIR_PRIOR_MIN_TUPLES
    ys = np.linspace(-0.7, -0.5, k)
    rows = [(PILLOW, BED, -1, FRAME_SUPPORT, 0.1 * i, y) for i, y in enumerate(ys)]
    rows += [(BOOK, BED, -1, FRAME_SUPPORT, 0.3, 0.2)] * (k - 1)
    cats, frames, centres = tuples(rows)
    table = pair_centre_table(cats, frames, centres, N)
    assert table.shape == table_shape(N) and table.dtype == np.float32
    np.testing.assert_allclose(
        table[BED, PILLOW, FRAME_SUPPORT],
        [np.median(0.1 * np.arange(k)), np.median(ys)],
        atol=1e-6,
    )
    assert not table[BED, BOOK].any()  # one tuple short
    assert np.count_nonzero(table.any(axis=-1)) == 1


def test_the_frame_anchor_keys_the_pair():
    """A chair in a desk's frame is keyed by the desk, not by its support (the floor); a
    floor object against a wall by the wall; no frames: the support for every tuple."""
    k = PAIR_PRIOR_MIN_TUPLES
    rows = [(CHAIR, FLOOR_INDEX, DESK, FRAME_FUNCTIONAL, 0.0, 0.8)] * k
    rows += [(BED, FLOOR_INDEX, -1, FRAME_WALL, 0.1, 0.4)] * k
    cats, frames, centres = tuples(rows)
    np.testing.assert_array_equal(frame_anchor(cats, frames), [DESK] * k + [WALL_INDEX] * k)
    np.testing.assert_array_equal(frame_anchor(cats, None), [FLOOR_INDEX] * (2 * k))
    table = pair_centre_table(cats, frames, centres, N)
    np.testing.assert_allclose(table[DESK, CHAIR, FRAME_FUNCTIONAL], [0.0, 0.8])
    np.testing.assert_allclose(table[WALL_INDEX, BED, FRAME_WALL], [0.1, 0.4])
    assert not table[FLOOR_INDEX].any()
    np.testing.assert_allclose(table_rows(table, cats[:1], frames[:1]), [[0.0, 0.8]])
    assert not table_rows(table, cats[:1], None).any()  # the floor's row is empty


def test_no_tuples_give_an_empty_table():
    empty = np.zeros((0, 3), np.int64)
    assert not pair_centre_table(empty, None, np.zeros((0, 2)), N).any()


def tiny(**kw) -> LayoutConfig:
    return LayoutConfig(width=32, depth=1, heads=4, queries=2, point_dim=8, **kw)


def batch_on_a_bed(b: int = 3) -> LayoutBatch:
    g = torch.Generator().manual_seed(3)
    cats = torch.tensor([[PILLOW, BED, -1]] * b)
    boxes = torch.zeros(b, 2, 12)
    boxes[:, 0] = torch.tensor([0, 0, 0, 2, 2, 2, 1, 0, 0, 0, 1, 0.0])
    return LayoutBatch(
        categories=cats,
        scales=torch.rand(b, 3, 3, generator=g) + 0.2,
        anchor_boxes=boxes,
        member_mask=torch.tensor([[True, True, False]] * b),
        frames=torch.zeros(b, dtype=torch.long),
        frame_sizes=torch.rand(b, 3, generator=g) + 0.5,
    )


def test_the_predictor_adds_the_tables_centre_to_every_component():
    config = tiny(variant=LayoutVariant.CLASS_ONLY, pair_prior=True)
    model = LayoutPredictor(config, None, torch.Generator().manual_seed(0)).eval()
    assert not model.pair_centre.any()  # empty until the trainer fills it
    batch = batch_on_a_bed()
    with torch.no_grad():
        before = model(batch)[0]
        model.pair_centre[BED, PILLOW, FRAME_SUPPORT] = torch.tensor([0.25, -0.6])
        after = model(batch)[0]
    shift = after.loc - before.loc
    torch.testing.assert_close(shift[..., 0], torch.full_like(shift[..., 0], 0.25))
    torch.testing.assert_close(shift[..., 1], torch.full_like(shift[..., 1], -0.6))
    assert not shift[..., 2:].any()
    torch.testing.assert_close(after.logits, before.logits)
    torch.testing.assert_close(after.log_scale, before.log_scale)


def _a_checkpoint_tensor_off_in_older_configs(on: LayoutConfig, flag: str) -> dict:
    """``on``'s expected checkpoint shapes, after checking that a predictor's state dict has
    them, that its config reads back, and that a config without ``flag`` (written before
    it) reads it as off."""
    shapes = expected_shapes(on, None)
    model = LayoutPredictor(on, None, materialise=False)
    assert {k: tuple(v.shape) for k, v in model.state_dict().items()} == shapes
    doc = json.loads(json.dumps(layout_config_to_dict(on)))
    assert layout_config_from_dict(doc) == on
    del doc[flag]
    assert getattr(layout_config_from_dict(doc), flag) is False
    return shapes


def test_the_table_is_a_checkpoint_tensor_and_older_configs_read_as_off():
    on, off = tiny(pair_prior=True), tiny()
    shapes = _a_checkpoint_tensor_off_in_older_configs(on, "pair_prior")
    assert shapes["pair_centre"] == table_shape(on.n_categories)
    assert "pair_centre" not in expected_shapes(off, None)
    assert not tiny(variant=LayoutVariant.GLOBAL, pair_prior=True).uses_pair_prior


def test_a_pairs_yaw_turns_are_its_smoothed_log_shares():
    """Pillows on a bed: 6 along it (two of them a few degrees off), 3 turned end-on
    (+90), 1 upside down (180): log shares with one pseudo-count per turn, centred."""
    k = max(PAIR_PRIOR_MIN_TUPLES, 10)
    yaws = np.radians([0, 0, 0, 0, 2, -3, 90, 90, 91, 180] + [0] * (k - 10))
    cats = np.array([[PILLOW, BED, -1]] * k)
    frames = np.full(k, FRAME_SUPPORT)
    rot = np.stack([np.cos(yaws), np.sin(yaws)], axis=1)
    rare = np.array([[BOOK, BED, -1]] * (PAIR_PRIOR_MIN_TUPLES - 1))
    table = pair_turn_table(
        np.concatenate([cats, rare]),
        np.full(len(cats) + len(rare), FRAME_SUPPORT),
        np.concatenate([rot, np.tile([[0.0, 1.0]], (len(rare), 1))]),
        N,
        4,
    )
    assert table.shape == turn_table_shape(N, 4) and table.dtype == np.float32
    counts = np.array([6 + k - 10, 3, 1, 0]) + 1.0
    want = np.log(counts / counts.sum())
    np.testing.assert_allclose(table[BED, PILLOW, FRAME_SUPPORT], want - want.mean(), atol=1e-6)
    assert not table[BED, BOOK].any()  # one tuple short: the network's split alone
    np.testing.assert_allclose(
        table_rows(table, cats[:1], frames[:1])[0], table[BED, PILLOW, FRAME_SUPPORT]
    )


def _class_only_with(table: str, **flags):
    """(a class-only predictor with the pair table and ``flags``, its empty ``table``
    checked, a batch on a bed, K, Q)."""
    config = tiny(variant=LayoutVariant.CLASS_ONLY, pair_prior=True, **flags)
    model = LayoutPredictor(config, None, torch.Generator().manual_seed(0)).eval()
    assert not getattr(model, table).any()  # empty until the trainer fills it
    return model, batch_on_a_bed(), config.mixture.num_components, config.mixture.yaw_modes


def test_the_predictor_adds_the_pairs_turn_shares_to_every_components_turn_logits():
    model, batch, k, q = _class_only_with("pair_turn", pair_turns=True)
    prior = torch.tensor([1.5, -0.5, -0.2, -0.8])
    with torch.no_grad():
        before = model(batch)[0]
        model.pair_turn[BED, PILLOW, FRAME_SUPPORT] = prior
        after = model(batch)[0]
    # each component's weight stays; its split among the turns moves by the prior
    w_before = before.logits.reshape(3, k, q).logsumexp(-1)
    w_after = after.logits.reshape(3, k, q).logsumexp(-1)
    torch.testing.assert_close(w_after.log_softmax(-1), w_before.log_softmax(-1))
    split_before = before.logits.reshape(3, k, q).log_softmax(-1)
    split_after = after.logits.reshape(3, k, q).log_softmax(-1)
    torch.testing.assert_close(split_after, (split_before + prior).log_softmax(-1))
    torch.testing.assert_close(after.loc, before.loc)
    torch.testing.assert_close(after.log_scale, before.log_scale)


def test_the_turn_table_is_a_checkpoint_tensor_and_older_configs_read_as_off():
    on = tiny(pair_turns=True)
    shapes = _a_checkpoint_tensor_off_in_older_configs(on, "pair_turns")
    assert shapes["pair_turn"] == turn_table_shape(on.n_categories, on.mixture.yaw_modes)
    assert "pair_turn" not in expected_shapes(tiny(), None)
    assert not tiny(variant=LayoutVariant.GLOBAL, pair_turns=True).uses_pair_turns


# -- the pair table's clusters -------------------------------------------------------------
def test_kmeans_finds_two_places_largest_first_and_is_seeded():
    rng = np.random.default_rng(0)
    head = rng.normal([0.0, -0.6], 0.02, (30, 2))
    foot = rng.normal([0.1, 0.5], 0.02, (10, 2))
    points = np.concatenate([foot, head])
    centres, counts = kmeans(points, 2, seed=(1, 2, 0))
    np.testing.assert_allclose(centres, [head.mean(0), foot.mean(0)], atol=1e-9)
    np.testing.assert_array_equal(counts, [30, 10])
    again = kmeans(points, 2, seed=(1, 2, 0))
    np.testing.assert_array_equal(again[0], centres)
    # more clusters than distinct points: the spare ones sit on the largest, empty
    centres, counts = kmeans(np.array([[0.0, 1.0], [0.0, 1.0], [2.0, 0.0]]), 4)
    np.testing.assert_array_equal(counts, [2, 1, 0, 0])
    np.testing.assert_array_equal(centres, [[0, 1], [2, 0], [0, 1], [0, 1]])


def test_mode_table_offsets_from_the_median_and_centred_log_shares():
    head = [(PILLOW, BED, -1, FRAME_SUPPORT, 0.0, -0.6)] * 8
    foot = [(PILLOW, BED, -1, FRAME_SUPPORT, 0.0, 0.5)] * 2
    rare = [(BOOK, BED, -1, FRAME_SUPPORT, 0.3, 0.3)] * (PAIR_PRIOR_MIN_TUPLES - 1)
    cats, frames, centres = tuples(head + foot + rare)
    table = pair_mode_table(cats, frames, centres, N, 3)
    assert table.shape == mode_table_shape(N, 3) and table.dtype == np.float32
    row = table[BED, PILLOW, FRAME_SUPPORT]  # median (0, -0.6): the head
    np.testing.assert_allclose(row[:, :CENTRE_DIMS], [[0, 0], [0, 1.1], [0, 0]], atol=1e-6)
    share = np.log(np.array([8, 2, 0]) + SHARE_PSEUDO_COUNT)
    np.testing.assert_allclose(row[:, CENTRE_DIMS], share - share.mean(), atol=1e-6)
    assert not table[BED, BOOK].any()  # one tuple short: the median alone
    np.testing.assert_allclose(table_rows(table, cats[:1], frames[:1])[0], row)


def test_the_predictor_gives_each_component_its_clusters_centre_and_share():
    model, batch, k, q = _class_only_with("pair_mode", pair_modes=True)
    modes = torch.randn(k, 3, generator=torch.Generator().manual_seed(1))
    with torch.no_grad():
        before = model(batch)[0]
        model.pair_mode[BED, PILLOW, FRAME_SUPPORT] = modes
        after = model(batch)[0]
    turned = modes.repeat_interleave(q, dim=0)  # (K*Q, 3): a component's turns alike
    torch.testing.assert_close(after.loc[..., :2], before.loc[..., :2] + turned[:, :2])
    torch.testing.assert_close(after.loc[..., 2:], before.loc[..., 2:])
    torch.testing.assert_close(after.logits, before.logits + turned[:, 2])
    torch.testing.assert_close(after.log_scale, before.log_scale)


def test_the_mode_table_is_a_checkpoint_tensor_and_older_configs_read_as_off():
    on = tiny(pair_prior=True, pair_modes=True)
    shapes = _a_checkpoint_tensor_off_in_older_configs(on, "pair_modes")
    assert shapes["pair_mode"] == mode_table_shape(on.n_categories, on.mixture.num_components)
    assert "pair_mode" not in expected_shapes(tiny(pair_prior=True), None)
    assert not tiny(pair_modes=True).uses_pair_modes  # it refines the pair table
