"""Layout predictor: shapes per variant, masking, cross-attention isolation, keys/values-only
spatial embeddings, determinism, learning a synthetic rule, the real Point-MAE encoder, presets.

Run with ``-s`` to see the printed parameter counts and step timings.
"""

from __future__ import annotations

import math

import pytest

torch = pytest.importorskip("torch")

from torch import nn  # noqa: E402

from pair2scene.curation.dataset import CATEGORY_VOCAB  # noqa: E402
from pair2scene.model.layout import (  # noqa: E402
    CrossAttention,
    LayoutBatch,
    LayoutBlock,
    LayoutConfig,
    LayoutPredictor,
    LayoutVariant,
    PointMemory,
    RelationalSelfAttention,
)
from pair2scene.model.mixture import (  # noqa: E402
    BOX_DIM,
    log_prob,
    rotation_to_6d,
    target_from_box_vector,
)
from pair2scene.model.presets import PRESETS, preset  # noqa: E402

UNIT_CUBE = torch.tensor([0.0, 0, 0, 2, 2, 2, 1, 0, 0, 0, 1, 0])
"""The support anchor's box in its own canonical frame (centre, size, 6D)."""


class LinearPointEncoder(nn.Module):
    """Stand-in for PointMAEEncoder: consecutive chunks of points form the groups; each
    token is the max over its group of a linear map of the points relative to the
    group's mean. Same interface: (R, N, 3) -> (tokens (R, G, D), centres (R, G, 3))."""

    def __init__(self, groups: int, width: int, seed: int = 0) -> None:
        super().__init__()
        self.groups = groups
        self.lin = nn.Linear(3, width)
        g = torch.Generator().manual_seed(seed)
        with torch.no_grad():
            self.lin.weight.copy_(torch.randn(width, 3, generator=g))
            self.lin.bias.zero_()

    def forward(self, points):
        r, n, _ = points.shape
        groups = points.reshape(r, self.groups, n // self.groups, 3)  # (R, G, n/G, 3)
        centers = groups.mean(dim=2)  # (R, G, 3)
        tokens = self.lin(groups - centers[:, :, None]).amax(dim=2)  # (R, G, D)
        return tokens, centers


def tiny_config(variant: LayoutVariant | str = "full", **kw) -> LayoutConfig:
    kw = {"width": 32, "depth": 2, "heads": 4, "queries": 4, "point_dim": 16, **kw}
    return LayoutConfig(variant=LayoutVariant(variant), **kw)


def tiny_model(config: LayoutConfig, seed: int = 0) -> LayoutPredictor:
    encoder = LinearPointEncoder(8, config.point_dim) if config.uses_points else None
    return LayoutPredictor(config, encoder, torch.Generator().manual_seed(seed))


def make_batch(
    b: int = 6, n_points: int = 64, seed: int = 1, functional: torch.Tensor | None = None
) -> LayoutBatch:
    """A random batch in the layout of the module docstring; the functional anchor is
    present in every other row unless ``functional`` (B,) bool says otherwise."""
    g = torch.Generator().manual_seed(seed)
    if functional is None:
        functional = torch.arange(b) % 2 == 0
    mask = torch.ones(b, 3, dtype=torch.bool)
    mask[:, 2] = functional
    cats = torch.randint(0, len(CATEGORY_VOCAB), (b, 3), generator=g)
    cats[~functional, 2] = -1  # as the shards store an absent member
    func_box = torch.cat(
        [
            torch.randn(b, 3, generator=g),
            torch.rand(b, 3, generator=g) + 0.1,
            torch.tensor([1.0, 0, 0, 0, 1, 0]).expand(b, 6),
        ],
        dim=1,
    )
    func_box[~functional] = float("nan")
    scales = torch.rand(b, 3, 3, generator=g) + 0.05
    scales[~functional, 2] = float("nan")
    return LayoutBatch(
        categories=cats,
        scales=scales,
        anchor_boxes=torch.stack([UNIT_CUBE.expand(b, 12), func_box], dim=1),
        member_mask=mask,
        points=torch.randn(b, 3, n_points, 3, generator=g),
        target=torch.randn(b, BOX_DIM, generator=g),
    )


def perturbed(batch: LayoutBatch, rows: torch.Tensor, seed: int = 7) -> LayoutBatch:
    """``batch`` with the functional anchor's inputs of ``rows`` replaced by new values."""
    g = torch.Generator().manual_seed(seed)
    out = LayoutBatch(**{k: (None if v is None else v.clone()) for k, v in batch.__dict__.items()})
    k = int(rows.sum())
    out.points[rows, 2] = torch.randn(k, out.points.shape[2], 3, generator=g) * 3
    out.scales[rows, 2] = torch.rand(k, 3, generator=g) + 2
    out.categories[rows, 2] = torch.randint(0, len(CATEGORY_VOCAB), (k,), generator=g)
    out.anchor_boxes[rows, 1] = torch.randn(k, 12, generator=g).abs() + 0.5
    return out


# -- shapes --------------------------------------------------------------------------


@pytest.mark.parametrize("variant", list(LayoutVariant))
def test_shapes_and_gradients_for_every_variant(variant):
    config = tiny_config(variant)
    model = tiny_model(config)
    batch = make_batch()
    if not config.uses_points:
        batch.points = None  # class-only needs no geometry
    params, loss = model(batch)
    k = config.mixture.num_components * config.mixture.yaw_modes
    assert params.logits.shape == (6, k)
    assert params.loc.shape == (6, k, BOX_DIM)
    assert params.log_scale.shape == (6, k, BOX_DIM)
    assert loss.shape == () and torch.isfinite(loss)
    loss.backward()
    own = [p for n, p in model.named_parameters() if not n.startswith("point_encoder.")]
    assert all(p.grad is not None and torch.isfinite(p.grad).all() for p in own)
    encoder_grads = [p.grad for p in model.point_encoder.parameters()] if config.uses_points else []
    if variant is LayoutVariant.NO_PRETRAIN:
        assert all(gr is not None for gr in encoder_grads)
    else:
        assert all(gr is None for gr in encoder_grads)  # frozen (or absent)

    params2, loss2 = model(LayoutBatch(**{**batch.__dict__, "target": None}))
    assert loss2 is None
    assert torch.equal(params2.loc, params.loc)


def test_variant_flags():
    full, cls, nop, glob = (tiny_config(v) for v in LayoutVariant)
    assert (full.n_members, glob.n_members) == (3, 2)
    assert not cls.uses_points and cls.n_members == 3
    assert full.loads_pretrained_encoder and not full.trains_encoder
    assert not nop.loads_pretrained_encoder and nop.trains_encoder
    assert tiny_config("full", finetune_encoder=True).trains_encoder
    assert not tiny_config("class-only", finetune_encoder=True).trains_encoder
    assert tiny_model(cls).point_encoder is None
    assert full.n_categories == len(CATEGORY_VOCAB)


def test_bad_shapes_and_configs_are_reported():
    model = tiny_model(tiny_config())
    batch = make_batch()
    batch.anchor_boxes = batch.anchor_boxes[:, :1]
    with pytest.raises(ValueError, match="anchor_boxes"):
        model(batch)
    batch = make_batch()
    batch.points = None
    with pytest.raises(ValueError, match="needs points"):
        model(batch)
    with pytest.raises(ValueError, match="divide"):
        LayoutConfig(width=30, heads=4)


# -- masking -------------------------------------------------------------------------


@pytest.mark.parametrize("variant", ["full", "class-only"])
def test_absent_functional_anchor_changes_nothing(variant):
    model = tiny_model(tiny_config(variant)).eval()
    batch = make_batch(b=6)
    absent = ~batch.member_mask[:, 2]
    with torch.no_grad():
        before, loss_before = model(batch)
        after, loss_after = model(perturbed(batch, absent))
        present_changed, _ = model(perturbed(batch, ~absent))
    for a, b in zip(before, after):
        assert torch.equal(a, b)  # bit for bit: absent inputs never reach any computation
    assert torch.equal(loss_before, loss_after)
    assert torch.isfinite(loss_before)  # NaN placeholders of absent members stay out
    # Sanity: the same perturbation does reach the output where the anchor is present.
    assert torch.equal(present_changed.loc[absent], before.loc[absent])
    assert not torch.allclose(present_changed.loc[~absent], before.loc[~absent])


def test_global_variant_ignores_the_functional_anchor_even_when_present():
    model = tiny_model(tiny_config("global")).eval()
    batch = make_batch(functional=torch.ones(6, dtype=torch.bool))
    with torch.no_grad():
        before, _ = model(batch)
        after, _ = model(perturbed(batch, torch.ones(6, dtype=torch.bool)))
    assert torch.equal(before.loc, after.loc)


# -- attention structure -------------------------------------------------------------


def test_cross_attention_isolation_within_a_block():
    """Member j's point tokens reach only member j's tokens in a block: the others see j
    only through the next block's self-attention."""
    config = tiny_config(dropout=0.0)
    block = LayoutBlock(config)  # default torch init is fine for a structural test
    g = torch.Generator().manual_seed(3)
    b, m, q, d, gt = 4, 3, config.queries, config.width, 8
    x = torch.randn(b, m * q, d, generator=g)
    spatial = torch.randn(b, m * q, d, generator=g)
    key_mask = torch.ones(b, m * q, dtype=torch.bool)
    tokens = torch.randn(b * m, gt, d, generator=g)
    rows = torch.arange(b * m)
    out = block(x, spatial, key_mask, PointMemory(tokens, rows)).reshape(b, m, q, d)
    for j in range(m):
        bumped = tokens.clone().reshape(b, m, gt, d)
        bumped[:, j] += torch.randn(b, gt, d, generator=g)
        new = block(x, spatial, key_mask, PointMemory(bumped.reshape(b * m, gt, d), rows))
        new = new.reshape(b, m, q, d)
        others = [i for i in range(m) if i != j]
        torch.testing.assert_close(new[:, others], out[:, others], rtol=0, atol=1e-6)
        assert (new[:, j] - out[:, j]).abs().max() > 1e-3


def test_cross_attention_rows_are_independent():
    attn = CrossAttention(tiny_config())
    g = torch.Generator().manual_seed(4)
    x = torch.randn(5, 4, 32, generator=g)
    mem = torch.randn(5, 8, 32, generator=g)
    full = attn(x, mem)
    for r in range(5):
        torch.testing.assert_close(attn(x[r : r + 1], mem[r : r + 1])[0], full[r])


def test_spatial_embedding_enters_keys_and_values_not_queries():
    """A token masked out as a key influences nobody; if its spatial embedding also fed
    its own query, its own output would change. It must not."""
    attn = RelationalSelfAttention(tiny_config())
    g = torch.Generator().manual_seed(5)
    x = torch.randn(2, 6, 32, generator=g)
    spatial = torch.randn(2, 6, 32, generator=g)
    key_mask = torch.ones(2, 6, dtype=torch.bool)
    key_mask[:, 4:] = False
    out = attn(x, spatial, key_mask)
    moved = spatial.clone()
    moved[:, 4:] += 10 * torch.randn(2, 2, 32, generator=g)
    torch.testing.assert_close(attn(x, moved, key_mask), out, rtol=0, atol=0)
    moved = spatial.clone()
    moved[:, 1] += torch.randn(2, 32, generator=g)  # an unmasked key: everyone hears it
    assert not torch.allclose(attn(x, moved, key_mask), out)


# -- determinism ---------------------------------------------------------------------


def test_same_seed_same_model_and_output_global_rng_untouched():
    config = tiny_config()
    encoder = LinearPointEncoder(8, config.point_dim)  # nn.Linear's own init reads it
    state = torch.random.get_rng_state()
    LayoutPredictor(config, encoder, torch.Generator().manual_seed(11))
    assert torch.equal(torch.random.get_rng_state(), state)
    a = tiny_model(config, seed=11)
    b = tiny_model(config, seed=11)
    c = tiny_model(config, seed=12)
    sa, sb, sc = a.state_dict(), b.state_dict(), c.state_dict()
    assert all(torch.equal(sa[k], sb[k]) for k in sa)
    assert any(not torch.equal(sa[k], sc[k]) for k in sa if not k.startswith("point_encoder"))
    batch = make_batch()
    pa, la = a(batch)
    pb, lb = b(batch)
    assert torch.equal(pa.loc, pb.loc) and torch.equal(la, lb)
    # Known values pin the initialisation (update deliberately if it changes).
    assert la.item() == pytest.approx(LOSS_AT_SEED_11, abs=1e-4)


LOSS_AT_SEED_11 = 21.415358
"""Loss of the tiny seed-11 model on make_batch(); recorded from this implementation."""


# -- learning ------------------------------------------------------------------------


def synthetic_batch(b: int, seed: int) -> LayoutBatch:
    """Target = a function of the functional anchor's box: the dependent sits 0.5 along
    +y from the anchor's centre, at half its size, with its rotation.

    Rotations are uniformly random in 3D. With yaw-only rotations two 6D entries are
    exactly 0 in every target; their scales then collapse to the mixture's floor and,
    at the default floor (e^-7), the predictor stalls on the marginal for thousands of
    steps (measured): a property of the loss on degenerate dimensions, kept out of
    this test of the architecture.
    """
    batch = make_batch(b=b, seed=seed, n_points=16, functional=torch.ones(b, dtype=torch.bool))
    g = torch.Generator().manual_seed(seed + 99)
    rotation, _ = torch.linalg.qr(torch.randn(b, 3, 3, generator=g))
    batch.anchor_boxes[:, 1, 6:] = rotation_to_6d(rotation)
    anchor = target_from_box_vector(batch.anchor_boxes[:, 1])  # (B, 12) log sizes
    offset = torch.tensor([0.0, 0.5, 0.0])
    batch.target = torch.cat(
        [anchor[:, :3] + offset, anchor[:, 3:6] - math.log(2), anchor[:, 6:]], 1
    )
    return batch


@pytest.mark.parametrize("variant", ["full", "class-only"])
def test_a_few_steps_learn_a_rule_of_the_anchor_box(variant):
    model = tiny_model(tiny_config(variant, width=48), seed=0)
    opt = torch.optim.AdamW([p for p in model.parameters() if p.requires_grad], lr=1e-3)
    held_out = synthetic_batch(64, seed=10_000)
    with torch.no_grad():
        start = model(held_out)[1].item()
    for step in range(STEPS):
        _, loss = model(synthetic_batch(64, seed=step))
        opt.zero_grad()
        loss.backward()
        opt.step()
    model.eval()
    with torch.no_grad():
        params, end = model(held_out)
    own = log_prob(params, held_out.target).mean().item()
    shuffled = log_prob(params, held_out.target.roll(1, dims=0)).mean().item()
    print(
        f"\n{variant}: held-out loss {start:.2f} -> {end.item():.2f} in {STEPS} steps; "
        f"log p own targets {own:.2f}, other rows' targets {shuffled:.2f}"
    )
    assert end.item() < start - 10.0
    # It used the anchor: other rows' targets (other anchors) score far worse.
    assert own > shuffled + 5.0


STEPS = 200
"""Enough for the tiny predictor to leave the marginal (~10.5 nats, reached by step 25)
and learn the rule (~150 steps); about 3 s on 2 cores."""


# -- the real Point-MAE encoder ------------------------------------------------------


def real_encoder_setup(variant: str = "full"):
    from pair2scene.model.pointmae import PointMAEConfig, PointMAEEncoder

    enc_config = PointMAEConfig.tiny()
    encoder = PointMAEEncoder(enc_config, torch.Generator().manual_seed(0))
    config = tiny_config(variant, point_dim=enc_config.width)
    model = LayoutPredictor(config, encoder, torch.Generator().manual_seed(0))
    return model, make_batch(n_points=enc_config.n_points)


def test_with_the_real_pointmae_encoder_frozen():
    model, batch = real_encoder_setup("full")
    before = {k: v.clone() for k, v in model.point_encoder.state_dict().items()}
    opt = torch.optim.AdamW([p for p in model.parameters() if p.requires_grad], lr=1e-3)
    model.train()
    assert not model.point_encoder.training  # frozen encoder stays in eval mode
    for _ in range(2):
        _, loss = model(batch)
        opt.zero_grad()
        loss.backward()
        opt.step()
    after = model.point_encoder.state_dict()
    assert all(torch.equal(before[k], after[k]) for k in before)

    # Cached tokens give what raw points give.
    model.eval()
    with torch.no_grad():
        tokens, centers = model.point_encoder(batch.points.flatten(0, 1))  # (B*3, G, .)
        cached = LayoutBatch(
            **{
                **batch.__dict__,
                "points": None,
                "point_tokens": tokens.reshape(6, 3, *tokens.shape[1:]),
                "point_centers": centers.reshape(6, 3, *centers.shape[1:]),
            }
        )
        torch.testing.assert_close(model(cached)[0].loc, model(batch)[0].loc)


def test_with_the_real_pointmae_encoder_trained_from_scratch():
    model, batch = real_encoder_setup("no-pretrain")
    _, loss = model(batch)
    loss.backward()
    assert all(p.grad is not None for p in model.point_encoder.parameters())
    batch.point_tokens = torch.zeros(6, 3, 16, 32)
    batch.point_centers = torch.zeros(6, 3, 16, 3)
    with pytest.raises(ValueError, match="raw points"):
        model(batch)


# -- presets -------------------------------------------------------------------------


def test_presets_build_and_parameter_counts():
    from pair2scene.model.pointmae import PointMAEEncoder, count_parameters

    counts = {}
    for name, p in PRESETS.items():
        assert p.layout.point_dim == p.encoder.width
        model = LayoutPredictor(p.layout, None, torch.Generator().manual_seed(0))
        encoder = PointMAEEncoder(p.encoder, torch.Generator().manual_seed(0))
        counts[name] = (model.num_parameters(), count_parameters(encoder))
        print(
            f"\npreset {name}: predictor {counts[name][0]:,} parameters, "
            f"encoder {counts[name][1]:,}, {p.n_points} points, batch {p.batch_size}, "
            f"{p.epochs} epochs"
        )
    assert counts["tiny"][0] < counts["cpu"][0] < counts["paper"][0]
    assert counts["cpu"][0] < 3_000_000
    assert preset().name == "cpu"
    assert preset("cpu", "no-pretrain").epochs < preset("cpu").epochs
    assert preset("cpu", "class-only").layout.variant is LayoutVariant.CLASS_ONLY
    with pytest.raises(ValueError, match="unknown preset"):
        preset("huge")
