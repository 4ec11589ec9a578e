"""The shared shape helpers (assets/generators/shapes.py): known values, and one home each."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import numpy as np
import pytest

import pair2scene.assets.generators as generators_pkg
from pair2scene.assets.generators.shapes import (
    FINE_SEGMENTS,
    ROD_SEGMENTS,
    ROUND_SEGMENTS,
    clip,
    lathe,
    slab,
)

GENERATOR_DIR = Path(generators_pkg.__file__).parent
SHAPES = GENERATOR_DIR / "shapes.py"
HELPER_NAME = re.compile(r"_*(lathe|clip|clamp|slab|box)", re.IGNORECASE)
"""Names of the shared helpers (and their old spellings) no family module may define again."""
SEGMENT_CONSTANTS = {"ROUND_SEGMENTS", "FINE_SEGMENTS", "ROD_SEGMENTS"}


def _family_modules() -> list[Path]:
    return sorted(
        p for p in GENERATOR_DIR.glob("*.py") if p.name not in {"shapes.py", "__init__.py"}
    )


def _tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text(), filename=str(path))


# -- one home ------------------------------------------------------------------------------
def test_there_are_family_modules():
    names = {p.stem for p in _family_modules()}
    assert {"tables", "seating", "beds", "storage", "tableware", "appliances", "food"} <= names


@pytest.mark.parametrize("path", _family_modules(), ids=lambda p: p.name)
def test_no_second_lathe_clip_or_slab(path):
    """A family module defining its own lathe / clip / slab (at any depth) would be a second
    copy of a helper in shapes.py: use that one."""
    defined = [
        n.name
        for n in ast.walk(_tree(path))
        if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) and HELPER_NAME.fullmatch(n.name)
    ]
    assert not defined, f"{path.name} defines {defined}; import them from shapes.py"


@pytest.mark.parametrize("path", _family_modules(), ids=lambda p: p.name)
def test_segment_counts_are_not_redefined(path):
    assigned = {
        t.id
        for n in ast.walk(_tree(path))
        if isinstance(n, ast.Assign)
        for t in n.targets
        if isinstance(t, ast.Name)
    }
    assert not assigned & SEGMENT_CONSTANTS, f"{path.name} redefines {assigned & SEGMENT_CONSTANTS}"


@pytest.mark.parametrize("path", _family_modules(), ids=lambda p: p.name)
def test_helpers_come_from_shapes_not_a_sibling(path):
    siblings = {f"pair2scene.assets.generators.{p.stem}" for p in _family_modules()}
    for n in ast.walk(_tree(path)):
        if isinstance(n, ast.ImportFrom):
            assert n.module not in siblings, f"{path.name} imports from {n.module}"


def test_shapes_defines_each_helper_once():
    top = [n.name for n in _tree(SHAPES).body if isinstance(n, ast.FunctionDef)]
    for name in ("lathe", "clip", "slab"):
        assert top.count(name) == 1


# -- known values --------------------------------------------------------------------------
def test_segment_counts():
    # multiples of 4 put a vertex on each of +-x and +-y, so round parts reach the box faces
    assert (ROUND_SEGMENTS, FINE_SEGMENTS, ROD_SEGMENTS) == (12, 16, 8)
    assert ROUND_SEGMENTS % 4 == FINE_SEGMENTS % 4 == ROD_SEGMENTS % 4 == 0


def test_clip():
    assert clip(5.0, 0.0, 1.0) == 1.0
    assert clip(-1.0, 0.0, 1.0) == 0.0
    assert clip(0.5, 0.0, 1.0) == 0.5
    assert clip(0.5, 0.0, 1.0, cap=0.2) == 0.2
    # a box too small for the real-world minimum: the upper limit wins
    assert clip(0.5, 0.6, 0.4) == 0.4
    assert type(clip(np.float64(0.5), 0.0, 1.0)) is float


def test_slab():
    part = slab("top", (-1.0, -0.5, 0.0), (1.0, 0.5, 0.1))
    assert part.name == "top"
    assert part.mesh.vertices.shape == (8, 3)
    np.testing.assert_array_equal(part.mesh.bounds, [[-1.0, -0.5, 0.0], [1.0, 0.5, 0.1]])


@pytest.mark.parametrize("hull_of_rings", [True, False])
def test_lathe_of_a_two_point_profile_is_an_elliptic_cylinder(hull_of_rings):
    m = lathe([(1.0, 0.0), (1.0, 0.5)], 2.0, 1.0, 8, center=(0.5, 0.0), hull_of_rings=hull_of_rings)
    # two rings of 8; the fan construction adds one centre vertex per end
    assert len(m.vertices) == (16 if hull_of_rings else 18)
    np.testing.assert_allclose(m.bounds, [[-1.5, -1.0, 0.0], [2.5, 1.0, 0.5]], atol=1e-12)
    ring = m.vertices[np.isclose(m.vertices[:, 2], 0.0)]
    ring = ring[~np.all(np.isclose(ring[:, :2], (0.5, 0.0)), axis=1)]  # not a centre vertex
    np.testing.assert_allclose(((ring[:, 0] - 0.5) / 2.0) ** 2 + ring[:, 1] ** 2, 1.0)
    assert m.is_watertight() and m.is_convex(tol=1e-9)


def test_lathe_radius_factor_and_apex():
    m = lathe([(0.0, 0.0), (1.0, 1.0), (0.5, 2.0)], 1.0, 1.0, 12, hull_of_rings=False)
    # apex, a full ring, a half ring, and the top's centre
    assert len(m.vertices) == 1 + 12 + 12 + 1
    np.testing.assert_allclose(np.hypot(*m.vertices[13:25, :2].T), 0.5)
    np.testing.assert_allclose(m.bounds, [[-1.0, -1.0, 0.0], [1.0, 1.0, 2.0]], atol=1e-12)
    assert m.is_watertight() and m.is_convex(tol=1e-9)
