"""generate() keeps what it built for an integer seed: a rebuilt scene reuses its assets."""

from __future__ import annotations

import numpy as np

from pair2scene.assets import registry
from pair2scene.assets.registry import generate


def test_same_seed_same_object_and_other_keys_build_anew():
    a = generate("chair", [0.5, 0.5, 0.9], 7)
    assert generate("chair", np.array([0.5, 0.5, 0.9]), 7) is a
    assert generate("chair", [0.5, 0.5, 0.91], 7) is not a
    assert generate("chair", [0.5, 0.5, 0.9], 8) is not a
    other_style = generate("chair", [0.5, 0.5, 0.9], 7, style=(a.style + 1) % 2)
    assert other_style is not a
    # a Generator is consumed by the build: never cached
    rng = np.random.default_rng(7)
    assert generate("chair", [0.5, 0.5, 0.9], rng) is not generate("chair", [0.5, 0.5, 0.9], rng)


def test_cached_asset_equals_a_fresh_build(monkeypatch):
    a = generate("shelving_unit", [0.8, 0.3, 1.8], 3, support_heights=[0.4, 0.8])
    monkeypatch.setattr(registry, "_BUILT", type(registry._BUILT)())
    b = generate("shelving_unit", [0.8, 0.3, 1.8], 3, support_heights=[0.4, 0.8])
    assert b is not a and len(a.parts) == len(b.parts)
    for p, q in zip(a.parts, b.parts, strict=True):
        assert np.array_equal(p.mesh.vertices, q.mesh.vertices)


def test_the_cache_is_bounded(monkeypatch):
    monkeypatch.setattr(registry, "BUILT_CACHE_ENTRIES", 3)
    monkeypatch.setattr(registry, "_BUILT", type(registry._BUILT)())
    for seed in range(5):
        generate("mug", [0.1, 0.1, 0.1], seed)
    assert len(registry._BUILT) == 3
