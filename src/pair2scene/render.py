"""Headless pictures of meshes: a moderngl/EGL renderer, a PIL fallback, labelled grids.

``render_meshes`` draws world-space meshes with per-mesh colours in an
orthographic view (``top``: straight down, +y up in the picture, +x right;
``three_quarter``: from the front-right above, so the +y fronts face the
viewer), with a depth test, Lambert shading plus ambient light and a thin
outline between meshes. The frame is fitted to the content, or to explicit
world bounds (a room), or given as a :class:`Camera`.

The GPU path uses one OpenGL context per process over EGL (Mesa's llvmpipe
on machines without a GPU). When moderngl or EGL is unavailable the failure
is remembered and every later call draws with a pure-CPU painter's
algorithm in PIL (slower and without anti-aliasing, same framing and
shading).

Also here, as image utilities: labelled grids of pictures (:func:`compose_grid`)
and the caption font (:func:`caption_font`). The asset contact sheet built on them is
:mod:`pair2scene.assets.sheet`.
"""

from __future__ import annotations

import ctypes
import math
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Literal

import numpy as np

from pair2scene.assets.mesh import Mesh
from pair2scene.assets.preview import view_rotation

if TYPE_CHECKING:
    from PIL import Image as PILImage


RGB = tuple[int, int, int]
ViewLike = Literal["top", "three_quarter"] | tuple[float, float]
Backend = Literal["auto", "gl", "cpu"]

VIEWS: dict[str, tuple[float, float]] = {
    "top": (0.0, 90.0),
    "three_quarter": (35.0, 30.0),
}
"""(azimuth, elevation) in degrees; azimuth 0 looks at the +y front, positive turns to +x."""

LIGHT_DIR = np.array([0.25, 0.5, 0.85]) / np.linalg.norm([0.25, 0.5, 0.85])
"""World direction towards the light: above, slightly front-right, so that in the 3/4
view the top, front and right faces of a box get three distinct shades."""
AMBIENT = 0.35
"""Share of the colour a face gets even when turned away from the light."""
DEFAULT_COLOR: RGB = (200, 170, 130)
OUTLINE_COLOR: RGB = (45, 45, 45)
DEFAULT_MARGIN = 0.06
"""Fraction of the picture left empty on each side when fitting the frame."""
SUPERSAMPLE = 2
"""The GL path renders at twice the resolution and averages 2 x 2 samples (anti-aliasing);
fixed because the resolve shader is unrolled for it (loops are slow on llvmpipe)."""
DEPTH_PAD = 0.02
"""Relative padding of the depth range, so the nearest and farthest faces are not clipped."""
MAX_CACHED_TARGETS = 4
"""Render targets kept alive per size (a sheet uses one or two sizes)."""


# -- camera ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class Camera:
    """An orthographic camera and the picture it fills.

    Camera coordinates: ``rotation @ world`` gives (right, up, towards the viewer).
    """

    rotation: np.ndarray
    """(3, 3) world -> camera."""
    center: np.ndarray
    """(2,) camera-plane point (metres) at the centre of the picture."""
    scale: float
    """Pixels per metre."""
    width: int
    height: int

    def project(self, points: np.ndarray) -> np.ndarray:
        """World points (N, 3) -> pixel coordinates (N, 2): x right, y down (PIL's)."""
        c = np.asarray(points, dtype=float).reshape(-1, 3) @ self.rotation.T
        x = self.width / 2 + (c[:, 0] - self.center[0]) * self.scale
        y = self.height / 2 - (c[:, 1] - self.center[1]) * self.scale
        return np.stack([x, y], axis=1)

    @property
    def pixel_m(self) -> float:
        """Metres per pixel."""
        return 1.0 / self.scale


def _view_angles(view: ViewLike) -> tuple[float, float]:
    if isinstance(view, str):
        if view not in VIEWS:
            raise ValueError(f"view must be one of {sorted(VIEWS)} or (azimuth, elevation)")
        return VIEWS[view]
    az, el = view
    return float(az), float(el)


def _wh(size: int | tuple[int, int]) -> tuple[int, int]:
    w, h = (size, size) if isinstance(size, int | np.integer) else size
    if w < 1 or h < 1:
        raise ValueError(f"picture size must be positive, got {size}")
    return int(w), int(h)


def _box_corners(bounds: np.ndarray) -> np.ndarray:
    """(2, 3) min/max corners -> (8, 3) box corners."""
    lo, hi = bounds
    idx = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    return np.where(idx == 0, lo, hi)


def fit_camera(
    view: ViewLike,
    points: np.ndarray,
    size: int | tuple[int, int] = 256,
    margin: float = DEFAULT_MARGIN,
) -> Camera:
    """The camera of ``view`` whose picture just holds ``points`` (N, 3), with a margin.

    For a room, pass the corners of its bounds: the frame then stays fixed whatever
    stands in the room."""
    w, h = _wh(size)
    rot = view_rotation(*_view_angles(view))
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if len(pts) == 0:
        return Camera(rot, np.zeros(2), 1.0, w, h)
    c = pts @ rot[:2].T  # (N, 2) camera plane
    lo, hi = c.min(0), c.max(0)
    extent = np.maximum(hi - lo, 1e-9)
    usable = np.array([w, h], dtype=float) * max(1.0 - 2.0 * margin, 1e-3)
    scale = float(np.min(usable / extent))
    return Camera(rot, (lo + hi) / 2, scale, w, h)


# -- the GL path ----------------------------------------------------------------------------
_SCENE_VS = """
#version 330
uniform mat4 mvp;
in vec3 in_pos;
in vec4 in_color_id;
out vec3 v_world;
out vec3 v_color;
flat out float v_id;
void main() {
    gl_Position = mvp * vec4(in_pos, 1.0);
    v_world = in_pos;
    v_color = in_color_id.rgb;
    v_id = in_color_id.a;
}
"""

# Flat normals from screen-space derivatives: no per-face vertex duplication, and they
# face the viewer, which lights open panels from either side.
_SCENE_FS = """
#version 330
uniform vec3 light;
uniform vec3 towards_viewer;
uniform float ambient;
in vec3 v_world;
in vec3 v_color;
flat in float v_id;
layout(location = 0) out vec4 f_color;
layout(location = 1) out float f_id;
void main() {
    vec3 n = normalize(cross(dFdx(v_world), dFdy(v_world)));
    if (dot(n, towards_viewer) < 0.0) n = -n;
    float lambert = max(dot(n, light), 0.0);
    f_color = vec4(v_color * (ambient + (1.0 - ambient) * lambert), 1.0);
    f_id = v_id;
}
"""

_POST_VS = """
#version 330
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
"""

# One output pixel averages its 2 x 2 samples. It is outlined when the mesh ids differ
# inside its block or towards the next block right and up: every id boundary is then
# drawn once, one output pixel wide. The block's four texels come in one textureGather
# per channel (four fetches with the id's, where ten texel fetches took 12 ms for
# 768 x 768 on llvmpipe). The sum runs over the block in the order x then y, as a loop
# over it would, for the same bits: a gather returns the texels (0, 1), (1, 1), (1, 0),
# (0, 0) as x, y, z, w.
_POST_FS = """
#version 400
uniform sampler2D t_color;
uniform sampler2D t_id;
uniform int outline_on;
uniform vec3 outline_color;
uniform vec3 background;
out vec4 f_color;
const int SS = 2;

vec3 sample_color(vec4 r, vec4 g, vec4 b, vec4 id, int k) {
    return id[k] > 0.0 ? vec3(r[k], g[k], b[k]) : background;
}

void main() {
    ivec2 b = ivec2(gl_FragCoord.xy) * SS;
    ivec2 size = textureSize(t_id, 0);
    vec2 uv = (vec2(b) + 0.75) / vec2(size);  // the block's footprint, a margin either way
    vec4 ids = textureGather(t_id, uv, 0);
    float id0 = ids.w;
    bool edge = any(notEqual(ids, vec4(id0)))
        || texelFetch(t_id, min(b + ivec2(SS, 0), size - 1), 0).r != id0
        || texelFetch(t_id, min(b + ivec2(0, SS), size - 1), 0).r != id0;
    vec4 r = textureGather(t_color, uv, 0);
    vec4 g = textureGather(t_color, uv, 1);
    vec4 bl = textureGather(t_color, uv, 2);
    vec3 acc = vec3(0.0);
    acc += sample_color(r, g, bl, ids, 3);
    acc += sample_color(r, g, bl, ids, 2);
    acc += sample_color(r, g, bl, ids, 0);
    acc += sample_color(r, g, bl, ids, 1);
    vec3 c = acc / float(SS * SS);
    f_color = vec4(outline_on == 1 && edge ? outline_color : c, 1.0);
}
"""


class _GL:
    """The process's one GL context, its two programs and cached render targets."""

    def __init__(self) -> None:
        import moderngl

        self.ctx = moderngl.create_standalone_context(backend="egl")
        self.scene = self.ctx.program(vertex_shader=_SCENE_VS, fragment_shader=_SCENE_FS)
        self.post = self.ctx.program(vertex_shader=_POST_VS, fragment_shader=_POST_FS)
        self.post_vao = self.ctx.vertex_array(self.post, [])
        self.targets: OrderedDict[tuple[int, int], tuple] = OrderedDict()
        self.renderer = self.ctx.info.get("GL_RENDERER", "unknown")
        self.flush = _gl_flush()
        self.pending: PendingImage | None = None  # the picture the targets hold, unread

    def target(self, w: int, h: int) -> tuple:
        """(scene fbo, colour tex, id tex, depth, output fbo, output rb) for w x h pixels."""
        key = (w, h)
        if key in self.targets:
            self.targets.move_to_end(key)
            return self.targets[key]
        size = (w * SUPERSAMPLE, h * SUPERSAMPLE)
        color = self.ctx.texture(size, 4)
        ident = self.ctx.texture(size, 1, dtype="f4")
        for t in (color, ident):
            t.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
        depth = self.ctx.depth_renderbuffer(size)
        fbo = self.ctx.framebuffer(color_attachments=[color, ident], depth_attachment=depth)
        rb = self.ctx.renderbuffer((w, h), 3)
        out = self.ctx.framebuffer(color_attachments=[rb])
        self.targets[key] = (fbo, color, ident, depth, out, rb)
        while len(self.targets) > MAX_CACHED_TARGETS:
            _, old = self.targets.popitem(last=False)
            for obj in old:
                obj.release()
        return self.targets[key]


_GL_STATE: _GL | None = None
_GL_ERROR: str | None = None


def _gl() -> _GL | None:
    """The lazily created GL state, or None when GL failed (remembered for the process)."""
    global _GL_STATE, _GL_ERROR
    if _GL_STATE is None and _GL_ERROR is None:
        try:
            _GL_STATE = _GL()
        except Exception as e:  # no moderngl, no EGL, no driver: all mean "use the CPU"
            _GL_ERROR = f"{type(e).__name__}: {e}".splitlines()[0]
    return _GL_STATE


def renderer_info() -> str:
    """Which renderer draws: ``gl (<GL renderer>)`` or ``cpu (<why GL failed>)``."""
    gl = _gl()
    return f"gl ({gl.renderer})" if gl is not None else f"cpu ({_GL_ERROR})"


def _pack(meshes: Sequence[Mesh], colors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 7) float32 [x, y, z, r, g, b, id] and faces (F, 3) uint32 of all meshes;
    ids count from 1 so that 0 is the background."""
    counts = np.array([len(m.vertices) for m in meshes])
    verts = np.empty((int(counts.sum()), 7), dtype=np.float32)
    verts[:, :3] = np.concatenate([m.vertices for m in meshes])
    per_mesh = np.c_[colors / 255.0, np.arange(1, len(meshes) + 1)]
    verts[:, 3:] = np.repeat(per_mesh, counts, axis=0)
    offsets = np.concatenate([[0], np.cumsum(counts)[:-1]])
    faces = np.concatenate([m.faces + o for m, o in zip(meshes, offsets)]).astype(np.uint32)
    return verts, faces


def _depth_range(camera: Camera, verts: np.ndarray) -> tuple[float, float]:
    """(nearest, farthest) camera depth of the content, padded; depth grows to the viewer."""
    z = verts @ camera.rotation[2]
    lo, hi = float(z.min()), float(z.max())
    pad = DEPTH_PAD * max(hi - lo, 1e-3) + 1e-4
    return hi + pad, lo - pad


def _gl_flush() -> Callable[[], None]:
    """``glFlush`` of the thread's current context (through GLVND's dispatch library,
    which routes it to moderngl's EGL context), or a no-op where it cannot be loaded
    (the draw then runs when its picture is read, as it would without it)."""
    for name in ("libOpenGL.so.0", "libGL.so.1"):
        try:
            return ctypes.CDLL(name).glFlush
        except (OSError, AttributeError):
            continue
    return lambda: None


class PendingImage:
    """A picture being drawn: :meth:`image` waits for it (once; later calls return it).
    On the GL path the drawing runs in the driver's threads (llvmpipe's) after
    :func:`start_render` returns, while the caller does other work."""

    def __init__(self, finish: Callable[[], PILImage.Image]) -> None:
        self._finish: Callable[[], PILImage.Image] | None = finish
        self._image: PILImage.Image | None = None

    def image(self) -> PILImage.Image:
        if self._finish is not None:
            self._image, self._finish = self._finish(), None
        assert self._image is not None
        return self._image


def _start_gl(
    gl: _GL,
    meshes: Sequence[Mesh],
    colors: np.ndarray,
    camera: Camera,
    background: RGB,
    outline: RGB | None,
) -> PendingImage:
    """Submit the scene pass and flush it (the driver draws it in its threads); the
    pending image's :meth:`~PendingImage.image` runs the resolve pass and reads the
    picture. The render targets stay the pending picture's until then: a render started
    before finishes it first."""
    from PIL import Image

    if gl.pending is not None:
        gl.pending.image()
    w, h = camera.width, camera.height
    fbo, color_tex, id_tex, _, out, _ = gl.target(w, h)
    fbo.use()
    gl.ctx.viewport = (0, 0, w * SUPERSAMPLE, h * SUPERSAMPLE)
    # clears the id attachment to 0 too; the post pass paints id 0 as background
    fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    if meshes:
        verts, faces = _pack(meshes, colors)
        near, far = _depth_range(camera, verts[:, :3].astype(float))
        mvp = np.eye(4)
        mvp[:3, :3] = camera.rotation
        mvp[:2, 3] = -camera.center
        mvp[0] *= 2 * camera.scale / w
        mvp[1] *= 2 * camera.scale / h
        # camera depth `near` -> NDC -1, `far` -> +1 (nearer passes the LESS depth test)
        mvp[2, :3] = -2.0 * camera.rotation[2] / (near - far)
        mvp[2, 3] = (near + far) / (near - far)
        prog = gl.scene
        prog["mvp"].write(mvp.T.astype("f4").tobytes())
        prog["light"].value = tuple(LIGHT_DIR)
        prog["towards_viewer"].value = tuple(camera.rotation[2])
        prog["ambient"].value = AMBIENT
        vbo = gl.ctx.buffer(verts.tobytes())
        ibo = gl.ctx.buffer(faces.tobytes())
        vao = gl.ctx.vertex_array(prog, [(vbo, "3f 4f", "in_pos", "in_color_id")], ibo, 4)
        gl.ctx.enable(gl.ctx.DEPTH_TEST)
        vao.render()
        gl.ctx.disable(gl.ctx.DEPTH_TEST)
        for obj in (vao, vbo, ibo):
            obj.release()
    # Without the flush, the resolve pass below would wait for this pass where it is
    # submitted: with it, llvmpipe draws while the caller goes on (a scene folder's
    # json, GLB and viewer page are written meanwhile: 15 of 27 ms of the top view).
    gl.flush()

    def finish() -> PILImage.Image:
        gl.pending = None
        out.use()
        gl.ctx.viewport = (0, 0, w, h)
        color_tex.use(0)
        id_tex.use(1)
        post = gl.post
        post["t_color"].value, post["t_id"].value = 0, 1
        post["background"].value = tuple(np.asarray(background, dtype=float) / 255.0)
        post["outline_on"].value = int(outline is not None and bool(meshes))
        post["outline_color"].value = tuple(np.asarray(outline or (0, 0, 0), dtype=float) / 255.0)
        gl.post_vao.render(vertices=3)
        data = out.read(components=3, alignment=1)
        return Image.frombytes("RGB", (w, h), data).transpose(Image.Transpose.FLIP_TOP_BOTTOM)

    gl.pending = PendingImage(finish)
    return gl.pending


# -- the CPU path ---------------------------------------------------------------------------
def _render_cpu(
    meshes: Sequence[Mesh],
    colors: np.ndarray,
    camera: Camera,
    background: RGB,
    outline: RGB | None,
) -> PILImage.Image:
    """Painter's algorithm in PIL, far faces first; same camera and shading as the GL path."""
    from PIL import Image, ImageDraw

    w, h = camera.width, camera.height
    img = Image.new("RGB", (w, h), background)
    ids = Image.new("I", (w, h), 0)
    if not meshes:
        return img
    towards = camera.rotation[2]
    polys, depths, shades, owner = [], [], [], []
    for i, m in enumerate(meshes):
        if len(m.faces) == 0:
            continue
        n = m.face_normals
        n = np.where((n @ towards < 0)[:, None], -n, n)  # two-sided, like the GL path
        shades.append(AMBIENT + (1 - AMBIENT) * np.clip(n @ LIGHT_DIR, 0, 1))
        polys.append(camera.project(m.vertices)[m.faces])  # (F, 3, 2)
        depths.append((m.vertices @ towards)[m.faces].mean(1))
        owner.append(np.full(len(m.faces), i))
    if not polys:
        return img
    polys_a, depths_a = np.concatenate(polys), np.concatenate(depths)
    shade_a, owner_a = np.concatenate(shades), np.concatenate(owner)
    fill = np.clip(colors[owner_a] * shade_a[:, None], 0, 255).astype(int)
    draw, draw_id = ImageDraw.Draw(img), ImageDraw.Draw(ids)
    for f in np.argsort(depths_a):  # far (small depth) to near
        pts = [tuple(p) for p in polys_a[f]]
        draw.polygon(pts, fill=tuple(fill[f]))
        draw_id.polygon(pts, fill=int(owner_a[f]) + 1)
    if outline is not None:
        idv = np.asarray(ids, dtype=np.int64)
        edge = np.zeros_like(idv, dtype=bool)
        edge[:, :-1] |= idv[:, :-1] != idv[:, 1:]
        edge[:-1, :] |= idv[:-1, :] != idv[1:, :]
        rgb = np.asarray(img).copy()
        rgb[edge] = outline
        img = Image.fromarray(rgb, "RGB")
    return img


# -- public rendering API -------------------------------------------------------------------
def start_render(
    meshes: Sequence[Mesh],
    colors: Sequence[RGB] | None = None,
    view: ViewLike = "three_quarter",
    size: int | tuple[int, int] = 256,
    background: RGB = (255, 255, 255),
    bounds: np.ndarray | None = None,
    camera: Camera | None = None,
    outline: RGB | None = OUTLINE_COLOR,
    margin: float = DEFAULT_MARGIN,
    backend: Backend = "auto",
) -> PendingImage:
    """Start drawing a picture of world-space ``meshes``, each in its own colour: its
    :meth:`~PendingImage.image` gives it (:func:`render_meshes` waits for it).

    meshes : world coordinates (z up); each is one outlined region (a part, an object).
    colors : one RGB (0..255) per mesh, or one for all; default a light wood colour.
    view : ``top`` (looking down, +x right, +y up in the picture), ``three_quarter``
        (azimuth 35 deg from +y towards +x, elevation 30 deg) or (azimuth, elevation).
    size : picture width = height, or (width, height), in pixels.
    bounds : (2, 3) world min/max corners to frame instead of the content (a room).
    camera : an explicit camera (overrides view, size, bounds, margin); get one from
        :func:`fit_camera` to draw overlays with ``camera.project``.
    outline : colour of the thin line around each mesh, or None for none.
    backend : ``auto`` (GL, else CPU), ``gl`` (raise if unavailable) or ``cpu``.

    The GL context is shared by the process: call from one thread at a time.
    """
    cols = np.asarray(DEFAULT_COLOR if colors is None else colors, dtype=float).reshape(-1, 3)
    if len(cols) not in (1, len(meshes)):
        raise ValueError(f"{len(cols)} colours for {len(meshes)} meshes")
    cols = np.broadcast_to(cols, (len(meshes), 3))
    keep = [i for i, m in enumerate(meshes) if len(m.faces) > 0]
    meshes, cols = [meshes[i] for i in keep], cols[keep]
    if camera is None:
        if bounds is not None:
            pts = _box_corners(np.asarray(bounds, dtype=float).reshape(2, 3))
        elif meshes:
            # the vertices, not their bounding box: a tighter frame in the 3/4 view
            pts = np.concatenate([m.vertices for m in meshes])
        else:
            pts = np.zeros((0, 3))
        camera = fit_camera(view, pts, size, margin)
    if backend != "cpu":
        gl = _gl()
        if gl is not None:
            return _start_gl(gl, meshes, cols, camera, background, outline)
        if backend == "gl":
            raise RuntimeError(f"GL renderer unavailable: {_GL_ERROR}")
    image = _render_cpu(meshes, cols, camera, background, outline)
    return PendingImage(lambda: image)


def render_meshes(*args, **kwargs) -> PILImage.Image:
    """A picture of world-space meshes: :func:`start_render` of the same arguments,
    waited for."""
    return start_render(*args, **kwargs).image()


# -- labelled grids -------------------------------------------------------------------------
@dataclass(frozen=True)
class Caption:
    """One line of text under a grid cell."""

    text: str
    color: RGB = (0, 0, 0)


@dataclass(frozen=True)
class GridCell:
    image: PILImage.Image
    captions: tuple[Caption, ...] = ()


CAPTION_FONT_PX = 13
GRID_PAD_PX = 8
"""Space around each cell."""


@lru_cache(maxsize=8)
def caption_font(px: int):
    """PIL's default font at ``px`` pixels (the bitmap font on Pillow < 10.1), cached."""
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=px)
    except TypeError:  # Pillow < 10.1: one fixed-size bitmap font
        return ImageFont.load_default()


def _fit_text(draw, text: str, font, max_w: int) -> str:
    """``text``, cut with an ellipsis to fit ``max_w`` pixels."""
    if draw.textlength(text, font=font) <= max_w:
        return text
    while text and draw.textlength(text + "…", font=font) > max_w:
        text = text[:-1]
    return text + "…"


def _wrap(draw, text: str, font, max_w: int) -> list[str]:
    """``text`` broken at spaces into lines of at most ``max_w`` pixels (a longer word
    keeps a line of its own, cut with an ellipsis)."""
    lines: list[str] = []
    for word in text.split():
        if lines and draw.textlength(lines[-1] + " " + word, font=font) <= max_w:
            lines[-1] += " " + word
        else:
            lines.append(_fit_text(draw, word, font, max_w))
    return lines


def compose_grid(
    cells: Sequence[GridCell],
    columns: int | None = None,
    title: str | None = None,
    background: RGB = (255, 255, 255),
    font_px: int = CAPTION_FONT_PX,
) -> PILImage.Image:
    """A contact sheet: cells in rows, each with its caption lines centred below it.

    Every cell gets the size of the largest image; ``columns`` defaults to a roughly
    square sheet."""
    from PIL import Image, ImageDraw

    if not cells:
        raise ValueError("compose_grid: no cells")
    font = caption_font(font_px)
    line_h = font_px + 4
    n_lines = max(len(c.captions) for c in cells)
    img_w = max(c.image.width for c in cells)
    img_h = max(c.image.height for c in cells)
    cell_w, cell_h = img_w + GRID_PAD_PX, img_h + n_lines * line_h + GRID_PAD_PX
    if columns is None:
        columns = max(1, math.ceil(math.sqrt(len(cells) * cell_h / cell_w)))
    rows = math.ceil(len(cells) / columns)
    width = columns * cell_w + GRID_PAD_PX
    title_font, title_lines = caption_font(font_px + 3), []
    if title:
        scratch = ImageDraw.Draw(Image.new("RGB", (1, 1)))
        title_lines = _wrap(scratch, title, title_font, width - 2 * GRID_PAD_PX)
    title_line_h = font_px + 8
    title_h = len(title_lines) * title_line_h + (line_h if title_lines else 0)
    sheet = Image.new("RGB", (width, rows * cell_h + GRID_PAD_PX + title_h), background)
    draw = ImageDraw.Draw(sheet)
    for k, line in enumerate(title_lines):
        y = GRID_PAD_PX + k * title_line_h
        draw.text((GRID_PAD_PX, y), line, fill=(0, 0, 0), font=title_font)
    for i, cell in enumerate(cells):
        r, c = divmod(i, columns)
        x0 = GRID_PAD_PX + c * cell_w
        y0 = GRID_PAD_PX + title_h + r * cell_h
        sheet.paste(cell.image, (x0 + (img_w - cell.image.width) // 2, y0))
        for k, cap in enumerate(cell.captions):
            text = _fit_text(draw, cap.text, font, img_w)
            tw = draw.textlength(text, font=font)
            draw.text((x0 + (img_w - tw) / 2, y0 + img_h + 2 + k * line_h), text,
                      fill=cap.color, font=font)  # fmt: skip
    return sheet
