"""Every registered generator: fills its box, convex watertight parts, deterministic;
and every category of the two Unity corpora has a real generator (not the box)."""

import numpy as np
import pytest

from pair2scene.assets.registry import generate, generators
from pair2scene.categories import CATEGORIES, SuperCategory

SIZES = {
    SuperCategory.LARGE_FURNITURE: (1.0, 0.6, 0.8),
    SuperCategory.FIXTURE: (0.7, 0.5, 0.8),
    SuperCategory.PART: (0.4, 0.35, 0.15),
    SuperCategory.WALL_OBJECT: (0.8, 0.05, 0.6),
    SuperCategory.SMALL_OBJECT: (0.2, 0.15, 0.12),
}
OBJECT_CATEGORIES = [c for c in CATEGORIES if c.super is not SuperCategory.STRUCTURE]


@pytest.mark.parametrize("cat", [c.name for c in OBJECT_CATEGORIES])
def test_generator_contract(cat):
    gen = generators().get(cat)
    if gen is None:
        pytest.fail(f"{cat}: no generator (box fallback)")
    size = np.array(SIZES[next(c.super for c in OBJECT_CATEGORIES if c.name == cat)])
    for style in range(gen.variants):
        a = generate(cat, size, rng=7, style=style)
        assert a.source == "procedural" and a.style == style
        assert np.allclose(a.mesh.bounds, [-size / 2, size / 2], atol=1e-6)
        for part in a.parts:
            assert part.mesh.is_watertight(), (cat, style, part.name)
            assert part.mesh.is_convex(tol=1e-5), (cat, style, part.name)
        b = generate(cat, size, rng=7, style=style)
        assert np.array_equal(a.mesh.vertices, b.mesh.vertices)


def test_unknown_category_gets_a_labelled_box():
    a = generate("unknown", (0.3, 0.2, 0.1), rng=0)
    assert a.is_fallback and a.source == "box" and len(a.parts) == 1


@pytest.mark.shared_data
def test_every_corpus_category_has_a_real_generator(ai2thor_corpus, procthor_1k):
    from pair2scene.data.procthor import load_procthor

    cats = {o.category for s in ai2thor_corpus.scenes for o in s.objects}
    for f in ("train.jsonl.gz", "val.jsonl.gz"):
        cats |= {o.category for s in load_procthor(procthor_1k / f).scenes for o in s.objects}
    missing = sorted(c for c in cats if c not in generators())
    print(f"corpus categories: {len(cats)}, with a generator: {len(cats) - len(missing)}")
    assert not missing
