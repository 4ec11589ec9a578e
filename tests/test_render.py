"""The headless renderer (GL and CPU paths) and labelled grids."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from pair2scene import render
from pair2scene.assets.mesh import Mesh, box

RED, BLUE = (220, 40, 40), (40, 40, 220)
WHITE = (255, 255, 255)
FRAME = np.array([[-1.0, -1.0, 0.0], [1.0, 1.0, 1.0]])
"""Explicit bounds, so object positions map to known pixels."""


def _gl_available() -> bool:
    return render._gl() is not None


BACKENDS = [
    pytest.param("gl", marks=pytest.mark.skipif(not _gl_available(), reason="no EGL here")),
    "cpu",
]


def _mask(img: Image.Image, background=WHITE) -> np.ndarray:
    """(H, W) bool: pixels that are not background."""
    return np.any(np.asarray(img) != np.asarray(background, dtype=np.uint8), axis=2)


def _hue_mask(img: Image.Image, channel: int) -> np.ndarray:
    """(H, W) bool: pixels where ``channel`` clearly dominates (a shaded red or blue)."""
    a = np.asarray(img).astype(int)
    others = [c for c in range(3) if c != channel]
    return (a[..., channel] > a[..., others[0]] + 40) & (a[..., channel] > a[..., others[1]] + 40)


@pytest.mark.parametrize("backend", BACKENDS)
def test_top_view_puts_plus_x_right_and_plus_y_up(backend):
    meshes = [box((0.6, 0.0, 0.2), (0.4, 0.4, 0.4)), box((0.0, 0.6, 0.2), (0.3, 0.3, 0.4))]
    img = render.render_meshes(meshes, [RED, BLUE], "top", size=64, bounds=FRAME, backend=backend)
    assert img.size == (64, 64) and img.mode == "RGB"
    red, blue = _hue_mask(img, 0), _hue_mask(img, 2)
    assert red.sum() > 50 and blue.sum() > 30
    ys, xs = np.nonzero(red)
    assert xs.min() > 32 and 20 < ys.mean() < 44  # right half, vertically centred
    ys, xs = np.nonzero(blue)
    assert ys.max() < 32 and 20 < xs.mean() < 44  # upper half, horizontally centred


@pytest.mark.parametrize("backend", BACKENDS)
def test_three_quarter_view_sees_the_front(backend):
    """A small panel behind a large one (both facing +y): hidden from the front-right,
    seen from the back-left."""
    front = box((0.0, 0.1, 0.5), (1.0, 0.02, 1.0))
    back = box((0.0, -0.1, 0.5), (0.6, 0.02, 0.6))
    img = render.render_meshes([front, back], [RED, BLUE], "three_quarter", 96, backend=backend)
    red, blue = _hue_mask(img, 0).sum(), _hue_mask(img, 2).sum()
    assert red > 2000 and blue < 0.02 * red
    behind = render.render_meshes([front, back], [RED, BLUE], (215.0, 30.0), 96, backend=backend)
    assert _hue_mask(behind, 2).sum() > max(1000, 20 * blue)


@pytest.mark.parametrize("backend", BACKENDS)
def test_lit_faces_differ_and_outline_is_drawn(backend):
    img = render.render_meshes([box((0, 0, 0), (1, 1, 1))], [(200, 200, 200)], size=96,
                               backend=backend)  # fmt: skip
    a = np.asarray(img).reshape(-1, 3)
    shades = {tuple(c) for c in a[_mask(img).reshape(-1)]}
    assert len(shades) >= 4  # top, front, right face and the outline
    assert min(s[0] for s in shades) < 80  # the dark outline
    plain = render.render_meshes([box((0, 0, 0), (1, 1, 1))], [(200, 200, 200)], size=96,
                                 outline=None, backend=backend)  # fmt: skip
    assert np.asarray(plain).min() > 60


def test_camera_project_matches_the_picture():
    cam = render.fit_camera("top", render._box_corners(FRAME), size=(80, 40), margin=0.0)
    assert cam.scale == pytest.approx(20.0)  # 2 m into 40 px
    px = cam.project(np.array([[0.5, 0.5, 0.0], [-1.0, -1.0, 0.0]]))
    np.testing.assert_allclose(px, [[50.0, 10.0], [20.0, 40.0]])
    img = render.render_meshes([box((0.5, 0.5, 0.1), (0.2, 0.2, 0.2))], [RED], camera=cam)
    assert img.size == (80, 40)
    assert _hue_mask(img, 0)[10, 50]


def test_empty_and_background():
    img = render.render_meshes([], size=(30, 20), background=(10, 20, 30))
    assert img.size == (30, 20)
    assert np.all(np.asarray(img) == (10, 20, 30))
    empty = Mesh(np.zeros((0, 3)), np.zeros((0, 3)))
    assert not _mask(render.render_meshes([empty], size=16)).any()
    img = render.render_meshes([empty, box((0, 0, 0), (1, 1, 1))], [BLUE, RED], size=16)
    assert _hue_mask(img, 0).any() and not _hue_mask(img, 2).any()
    with pytest.raises(ValueError):
        render.render_meshes([box((0, 0, 0), (1, 1, 1))] * 2, [RED] * 3)


def test_gl_and_cpu_agree_on_the_silhouette():
    if not _gl_available():
        pytest.skip("no EGL here")
    m = [box((0.2, 0.1, 0.3), (0.8, 0.5, 0.6))]
    gl = _mask(render.render_meshes(m, view="three_quarter", size=64, backend="gl"))
    cpu = _mask(render.render_meshes(m, view="three_quarter", size=64, backend="cpu"))
    assert (gl ^ cpu).sum() < 0.1 * cpu.sum()


@pytest.mark.parametrize("backend", BACKENDS)
def test_renders_started_before_the_last_is_read_give_their_own_pictures(backend):
    """A render started while another is pending (the same render targets) finishes the
    pending one first: each gives the picture a render on its own gives."""
    red = [box((-0.5, -0.5, 0), (0.0, 0.0, 0.5))]
    blue = [box((0.0, 0.0, 0), (0.5, 0.5, 0.5))]
    alone = [
        np.asarray(render.render_meshes(m, [c], "top", 48, bounds=FRAME, backend=backend))
        for m, c in ((red, RED), (blue, BLUE))
    ]
    first = render.start_render(red, [RED], "top", 48, bounds=FRAME, backend=backend)
    second = render.start_render(blue, [BLUE], "top", 48, bounds=FRAME, backend=backend)
    assert np.array_equal(np.asarray(second.image()), alone[1])
    assert np.array_equal(np.asarray(first.image()), alone[0])
    assert first.image() is first.image()  # read once


def test_failed_gl_falls_back_once(monkeypatch):
    calls = []

    def broken():
        calls.append(1)
        raise RuntimeError("no EGL display\nsecond line")

    monkeypatch.setattr(render, "_GL", broken)
    monkeypatch.setattr(render, "_GL_STATE", None)
    monkeypatch.setattr(render, "_GL_ERROR", None)
    for _ in range(2):
        img = render.render_meshes([box((0, 0, 0), (1, 1, 1))], size=32)
        assert _mask(img).sum() > 100
    assert len(calls) == 1
    assert render.renderer_info() == "cpu (RuntimeError: no EGL display)"
    with pytest.raises(RuntimeError, match="unavailable"):
        render.render_meshes([box((0, 0, 0), (1, 1, 1))], backend="gl")


def test_compose_grid_layout_and_captions():
    cells = [
        render.GridCell(Image.new("RGB", (40, 30), (0, 200, 0)), (render.Caption("a"),)),
        render.GridCell(Image.new("RGB", (40, 30), (0, 200, 0)),
                        (render.Caption("b"), render.Caption("warn", (255, 0, 0)))),
        render.GridCell(Image.new("RGB", (20, 30), (0, 200, 0))),
    ]  # fmt: skip
    sheet = render.compose_grid(cells, columns=2, title="a title long enough to wrap " * 3)
    assert sheet.width == 2 * (40 + render.GRID_PAD_PX) + render.GRID_PAD_PX
    a = np.asarray(sheet).astype(int)
    assert ((a[..., 0] > 200) & (a[..., 1] < 80)).any()  # the red caption
    assert (np.all(a == (0, 200, 0), axis=2).sum()) == 2 * 40 * 30 + 20 * 30
    with pytest.raises(ValueError):
        render.compose_grid([])
