"""scene.html and index.html (pair2scene.io.viewer): the pages are self-contained (nothing
fetched from anywhere), embed the scene's GLB, list every object and every scene folder;
and, in headless Chromium (Debian: ``apt-get install -y chromium``; skipped without it),
the page draws without a console error, shows the scene upright in glTF's y-up frame,
reads any GLB of the kind (nested transforms, strides, strips, normals, trimesh's files)
and answers the mouse."""

from __future__ import annotations

import base64
import html
import importlib.util
import io
import json
import math
import re
import struct
from pathlib import Path

import numpy as np
import pytest

from pair2scene.assets.registry import generate
from pair2scene.io.export import write_scene_folder
from pair2scene.io.glb import glb_bytes
from pair2scene.io.scene_meshes import FLOOR_THICKNESS_M, WALL_THICKNESS_M, object_meshes
from pair2scene.io.viewer import (
    INDEX_HTML,
    SCENE_HTML,
    index_html,
    page_html,
    scene_html,
    scene_info,
    write_index,
    write_viewer,
)
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Opening, Room, Scene, SceneObject

ROOT = Path(__file__).resolve().parents[2]
ROOM = Room(
    "bedroom",
    np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float),
    2.6,
    (Opening("door", (1.0, 0.0), (1.9, 0.0), 0.0, 2.1, "door_0"),),
    (Opening("window", (1.0, 3.0), (2.5, 3.0), 0.8, 2.0, "window_0"),),
)
BACKGROUND = (236, 238, 242)
"""The viewer's clear colour (0.925, 0.935, 0.95) as 8-bit sRGB."""


def bedroom(scene_id: str = "bedroom_0007") -> tuple[Scene, dict]:
    bed = OrientedBox.from_yaw([2.0, 1.9, 0.3], [1.6, 2.0, 0.6])
    wardrobe = OrientedBox.from_yaw([3.35, 1.0, 1.0], [0.8, 1.2, 2.0], np.pi / 2)
    table = OrientedBox.from_yaw([0.5, 2.5, 0.3], [0.5, 0.5, 0.6], np.pi / 2)
    lamp = OrientedBox.from_yaw([0.5, 2.5, 0.8], [0.2, 0.2, 0.4])
    objects = [
        SceneObject("bed_0", "bed", bed, None, FLOOR),
        SceneObject("wardrobe_0", "wardrobe", wardrobe, None, FLOOR),
        SceneObject("side_table_0", "side_table", table, None, FLOOR, "bed_0"),
        SceneObject("table_lamp_0", "table_lamp", lamp, None, "side_table_0"),
    ]
    assets = {o.id: generate(o.category, o.box.size, 0) for o in objects}
    return Scene(scene_id, ROOM, objects), assets


def embedded_glb(page: str) -> bytes:
    m = re.search(r'<script type="application/octet-stream" id="scene-glb">([^<]*)</script>', page)
    assert m is not None
    return base64.b64decode(m.group(1), validate=True)


def embedded_info(page: str) -> dict:
    m = re.search(r'<script type="application/json" id="scene-info">([^<]*)</script>', page)
    assert m is not None
    return json.loads(m.group(1))


def glb_document(data: bytes) -> dict:
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    json_length, json_type = struct.unpack_from("<I4s", data, 12)
    assert json_type == b"JSON"
    return json.loads(data[20 : 20 + json_length])


def assert_offline(page: str, files_beside: bool = False) -> None:
    """Nothing in the page names a network location; it loads no file beside it, or
    (``files_beside``, the gallery) only by relative links into its folder."""
    assert not re.search(r"(?i)\b(https?|ftp|wss?):", page)
    assert not re.search(r"(?i)//[a-z0-9.-]+\.[a-z]{2,}/", page)  # protocol-relative
    assert "<link" not in page and "@import" not in page and "url(" not in page
    loads = re.findall(
        r"(?i)<(?:script|img|iframe|audio|video|source)\b[^>]*\bsrc=\"([^\"]*)", page
    )
    if not files_beside:
        assert loads == []
    for link in loads + re.findall(r'(?i)\bhref="([^"]*)"', page):
        assert re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9._%-]*/[a-z]+\.(png|html|glb|json)", link), link


# ------------------------------------------------------------------ structure


def test_the_scene_page_is_self_contained_and_embeds_the_scene_glb():
    scene, assets = bedroom()
    page = scene_html(scene, assets).decode("utf-8")
    assert_offline(page)
    assert re.search(r"<title>bedroom_0007</title>", page)
    glb = embedded_glb(page)
    assert glb == glb_bytes(scene, assets)
    doc = glb_document(glb)
    names = {n.get("name") for n in doc["nodes"]}
    assert {"floor", *(o.id for o in scene.objects)} <= names
    assert "window.viewerReady = true" in page  # the viewer's own code is inline


def test_the_page_lists_every_object_and_says_what_the_room_is():
    scene, assets = bedroom()
    page = scene_html(scene, assets).decode("utf-8")
    listed = re.findall(r'<li data-id="([^"]+)"[^>]*>.*?<span class="cat">([^<]+)</span>', page)
    assert listed == [(o.id, o.category) for o in scene.objects]
    info = embedded_info(page)
    assert info == json.loads(json.dumps(scene_info(scene)))
    assert info["room_type"] == "bedroom" and info["height"] == 2.6
    assert ">4 objects<" in page and ">bedroom<" in page


def test_ids_and_names_are_escaped():
    scene, assets = bedroom('x</script><b>&"y')
    page = scene_html(scene, assets, back_link="../index.html").decode("utf-8")
    assert "</script><b>" not in page
    assert f"<title>{html.escape(scene.id)}</title>" in page
    assert embedded_info(page)["id"] == scene.id
    assert '<a href="../index.html">' in page


def test_write_viewer_writes_scene_html_atomically(tmp_path):
    scene, assets = bedroom()
    path = write_viewer(tmp_path / "s", scene, assets)
    assert path == tmp_path / "s" / SCENE_HTML
    assert path.read_bytes() == scene_html(scene, assets)
    assert sorted(p.name for p in path.parent.iterdir()) == [SCENE_HTML]


def scene_folders(out: Path) -> list[str]:
    """Four scenes in ``out`` (written as generate writes them, two with a scene.html),
    a hidden and a foreign folder, and a scene folder with a broken scene.json."""
    ids = ["living_room_0001", "bedroom_0002", "bedroom_0000", "kitchen_0000"]
    for i, scene_id in enumerate(ids):
        scene, assets = bedroom(scene_id)
        if scene_id.startswith("living"):
            scene = Scene(scene_id, Room("living_room", ROOM.floor_polygon), scene.objects[:2])
        write_scene_folder(out / scene_id, scene, assets)
        if i % 2:
            write_viewer(out / scene_id, scene, assets)
    (out / ".bedroom_0009.tmp").mkdir()
    (out / ".bedroom_0009.tmp" / "scene.json").write_text("{}")
    (out / "notes").mkdir()
    (out / "broken_0000").mkdir()
    (out / "broken_0000" / "scene.json").write_text("{not json")
    return ids


def test_the_gallery_lists_every_scene_folder_sorted_by_id(tmp_path):
    ids = scene_folders(tmp_path)
    page = index_html(tmp_path).decode("utf-8")
    assert_offline(page, files_beside=True)
    cards = re.findall(r'<article class="card[^"]*" data-id="([^"]+)"', page)
    assert cards == sorted([*ids, "broken_0000"])
    for scene_id in ids:
        card = re.search(rf'data-id="{scene_id}".*?</article>', page).group(0)
        assert f'<img src="{scene_id}/bev.png"' in card
        count = 2 if scene_id.startswith("living") else 4
        assert f">{count} objects<" in card
        assert f">{'living_room' if scene_id.startswith('living') else 'bedroom'}<" in card
        has_page = (tmp_path / scene_id / SCENE_HTML).exists()
        assert (f'href="{scene_id}/{SCENE_HTML}"' in card) == has_page
        assert f'href="{scene_id}/scene.glb"' in card
    broken = re.search(r'data-id="broken_0000".*?</article>', page).group(0)
    assert "unreadable scene.json" in broken and "no bev.png" in broken
    assert ".bedroom_0009" not in page and "notes" not in page
    assert "5 scenes: 3 bedroom, 1 living_room" in page
    path = write_index(tmp_path)
    assert path == tmp_path / INDEX_HTML and path.read_bytes() == index_html(tmp_path)


def test_an_empty_or_missing_folder_gives_an_empty_gallery(tmp_path):
    assert "0 scenes" in index_html(tmp_path).decode()
    assert "0 scenes" in index_html(tmp_path / "missing").decode()


# ------------------------------------------------------------------ in a browser


def _load_driver():
    spec = importlib.util.spec_from_file_location(
        "viewer_shots", ROOT / "benchmarks" / "viewer_shots.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


shots = _load_driver()
CHROMIUM = shots.find_chromium()
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None,
    reason="no chromium on PATH: the browser tests need it (Debian: apt-get install -y chromium)",
)


@pytest.fixture(scope="module")
def browser():
    with shots.Chromium(CHROMIUM, 1280, 800) as b:
        yield b


def open_page(browser, path: Path) -> None:
    browser.errors.clear()
    browser.requests.clear()
    browser.open(path)
    assert browser.evaluate("window.viewerError || null") is None
    assert browser.evaluate("window.viewerReady") is True


def png_pixels(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))


def to_viewer(points: np.ndarray) -> np.ndarray:
    """pair2scene's z-up points in glTF's y-up frame: (x, y, z) -> (x, z, -y)."""
    points = np.asarray(points, float)
    return np.stack([points[..., 0], points[..., 2], -points[..., 1]], -1)


def assert_bounds(bounds: dict, lo, hi, tol: float = 1e-4) -> None:
    assert np.allclose(bounds["min"], lo, atol=tol), (bounds, lo)
    assert np.allclose(bounds["max"], hi, atol=tol), (bounds, hi)


@needs_chromium
def test_the_page_draws_the_scene_upright_without_errors(browser, tmp_path):
    scene, assets = bedroom()
    path = write_viewer(tmp_path, scene, assets)
    open_page(browser, path)
    png = browser.screenshot()
    assert browser.errors == []
    assert browser.requests == [path.resolve().as_uri()]  # nothing else was fetched

    # upright: the floor's top at y = 0, the walls from 0 to the room's height
    t, h = WALL_THICKNESS_M, ROOM.height
    assert_bounds(
        browser.evaluate("window.viewerBounds"), [-t, -FLOOR_THICKNESS_M, -3 - t], [4 + t, h, t]
    )
    assert_bounds(
        browser.evaluate("window.viewer.bounds('floor')"),
        [-t, -FLOOR_THICKNESS_M, -3 - t],
        [4 + t, 0, t],
    )
    walls = [
        browser.evaluate(f"window.viewer.bounds('{n}')")
        for n in browser.evaluate("window.viewer.nodes()")
        if n.startswith("wall_")
    ]
    assert walls and all(abs(w["min"][1]) < 1e-6 and abs(w["max"][1] - h) < 1e-6 for w in walls)
    # each object where pair2scene put it (its world mesh, seen in the y-up frame)
    for oid, _, mesh in object_meshes(scene, assets):
        v = to_viewer(mesh.vertices)
        assert_bounds(browser.evaluate(f"window.viewer.bounds('{oid}')"), v.min(0), v.max(0))

    # a real picture: many colours, the room (not the background) in the view's centre
    pixels = png_pixels(png)
    assert pixels.shape == (800, 1280, 3)
    assert len(np.unique(pixels.reshape(-1, 3), axis=0)) > 200
    canvas = browser.evaluate(
        "(r => [r.left, r.top, r.width, r.height])(document.getElementById('view')"
        ".getBoundingClientRect())"
    )
    cx, cy = int(canvas[0] + canvas[2] / 2), int(canvas[1] + canvas[3] / 2)
    assert np.abs(pixels[cy, cx].astype(int) - BACKGROUND).max() > 12
    assert (
        np.abs(pixels[int(canvas[1]) + 2, int(canvas[0]) + 2].astype(int) - BACKGROUND).max() <= 2
    )


@needs_chromium
def test_clicking_an_object_in_the_list_or_the_view_highlights_it(browser, tmp_path):
    scene, assets = bedroom()
    open_page(browser, write_viewer(tmp_path, scene, assets))
    before = png_pixels(browser.screenshot())
    browser.evaluate("document.querySelector('#objects li[data-id=\"bed_0\"]').click()")
    assert browser.evaluate("window.viewer.selected()") == "bed_0"
    assert browser.evaluate("document.querySelector('#objects li.selected').dataset.id") == "bed_0"
    assert "bed_0" in browser.evaluate("document.getElementById('status').textContent")
    after = png_pixels(browser.screenshot())
    assert (np.abs(after.astype(int) - before).max(-1) > 30).mean() > 0.05  # the rest dims

    # a click on the wardrobe's top (nearest the camera) in the canvas selects it
    b = browser.evaluate("window.viewer.bounds('wardrobe_0')")
    top = [(b["min"][0] + b["max"][0]) / 2, b["max"][1], (b["min"][2] + b["max"][2]) / 2]
    x, y = browser.evaluate(f"window.viewer.project({json.dumps(top)})")
    left, top_px = browser.evaluate(
        "(r => [r.left, r.top])(document.getElementById('view').getBoundingClientRect())"
    )
    x, y = x + left, y + top_px + 3  # just inside the top face
    for kind in ("mousePressed", "mouseReleased"):
        browser.send(
            "Input.dispatchMouseEvent",
            {"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1},
        )
    browser.settle()
    assert browser.evaluate("window.viewer.selected()") == "wardrobe_0"
    assert browser.errors == []


@needs_chromium
def test_drag_orbits_wheel_zooms_and_shift_drag_pans(browser, tmp_path):
    scene, assets = bedroom()
    open_page(browser, write_viewer(tmp_path, scene, assets))
    start = browser.evaluate("window.viewer.camera()")

    def drag(x0, y0, x1, y1, modifiers=0, button="left"):
        browser.send(
            "Input.dispatchMouseEvent",
            {
                "type": "mousePressed",
                "x": x0,
                "y": y0,
                "button": button,
                "clickCount": 1,
                "modifiers": modifiers,
            },
        )
        for k in range(1, 6):
            x, y = x0 + (x1 - x0) * k / 5, y0 + (y1 - y0) * k / 5
            browser.send(
                "Input.dispatchMouseEvent",
                {"type": "mouseMoved", "x": x, "y": y, "button": button, "modifiers": modifiers},
            )
        browser.send(
            "Input.dispatchMouseEvent",
            {
                "type": "mouseReleased",
                "x": x1,
                "y": y1,
                "button": button,
                "clickCount": 1,
                "modifiers": modifiers,
            },
        )
        browser.settle()

    drag(800, 400, 900, 380)
    cam = browser.evaluate("window.viewer.camera()")
    assert cam["yaw"] < start["yaw"] - 0.3 and cam["target"] == start["target"]
    browser.send(
        "Input.dispatchMouseEvent",
        {"type": "mouseWheel", "x": 800, "y": 400, "deltaX": 0, "deltaY": 300},
    )
    browser.settle()
    zoomed = browser.evaluate("window.viewer.camera()")
    assert zoomed["distance"] > cam["distance"] * 1.2
    drag(800, 400, 700, 400, modifiers=8)  # shift
    panned = browser.evaluate("window.viewer.camera()")
    assert panned["yaw"] == zoomed["yaw"] and panned["target"] != zoomed["target"]
    drag(800, 400, 800, 300, button="right")
    assert browser.evaluate("window.viewer.camera()")["target"] != panned["target"]
    browser.evaluate("document.getElementById('reset').click()")
    browser.settle()
    assert browser.evaluate("window.viewer.camera()") == start
    assert browser.errors == []


@needs_chromium
def test_one_finger_orbits_and_two_fingers_pinch_zoom(browser, tmp_path):
    scene, assets = bedroom()
    open_page(browser, write_viewer(tmp_path, scene, assets))
    browser.send("Emulation.setTouchEmulationEnabled", {"enabled": True, "maxTouchPoints": 5})
    try:

        def touch(kind, points):
            browser.send(
                "Input.dispatchTouchEvent",
                {
                    "type": kind,
                    "touchPoints": [{"x": x, "y": y, "id": i} for i, (x, y) in enumerate(points)],
                },
            )

        start = browser.evaluate("window.viewer.camera()")
        touch("touchStart", [(800, 400)])
        for k in range(1, 6):
            touch("touchMove", [(800 + 20 * k, 400)])
        touch("touchEnd", [])
        browser.settle()
        turned = browser.evaluate("window.viewer.camera()")
        assert turned["yaw"] < start["yaw"] - 0.5
        touch("touchStart", [(700, 400), (900, 400)])
        for k in range(1, 6):
            touch("touchMove", [(700 - 20 * k, 400), (900 + 20 * k, 400)])
        touch("touchEnd", [])
        browser.settle()
        assert browser.evaluate("window.viewer.camera()")["distance"] < turned["distance"] * 0.7
    finally:
        browser.send("Emulation.setTouchEmulationEnabled", {"enabled": False})
    assert browser.errors == []


# -- any GLB of the kind: hand-made files and trimesh's


def rotation(q) -> np.ndarray:
    x, y, z, w = np.asarray(q, float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def trs(t=(0, 0, 0), q=(0, 0, 0, 1), s=(1, 1, 1)) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = rotation(q) * np.asarray(s, float)
    m[:3, 3] = t
    return m


def hand_made_glb() -> tuple[bytes, dict[str, np.ndarray]]:
    """A GLB using what our writer does not: a node matrix, nested TRS with a negative
    scale, an interleaved buffer view with byteStride (POSITION + NORMAL), uint32 and
    uint8 indices, a triangle strip, a primitive without indices, a data: URI buffer;
    and the expected world points (y-up) of each named node."""
    cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 2)], "<f4")
    faces = np.array(
        [
            [0, 1, 3],
            [0, 3, 2],
            [4, 6, 7],
            [4, 7, 5],
            [0, 4, 5],
            [0, 5, 1],
            [2, 3, 7],
            [2, 7, 6],
            [0, 2, 6],
            [0, 6, 4],
            [1, 5, 7],
            [1, 7, 3],
        ]
    )
    normals = np.tile(np.array([0, 0, 1], "<f4"), (8, 1))
    interleaved = np.hstack([cube, normals]).astype("<f4").tobytes()  # stride 24
    blob = bytearray()

    def view(raw: bytes, **extra) -> int:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(raw), **extra})
        blob.extend(raw + bytes(-len(raw) % 4))
        return len(views) - 1

    views: list[dict] = []
    accessors: list[dict] = []

    def accessor(**a) -> int:
        accessors.append(a)
        return len(accessors) - 1

    inter = view(interleaved, byteStride=24)
    pos = accessor(
        bufferView=inter,
        componentType=5126,
        count=8,
        type="VEC3",
        min=cube.min(0).tolist(),
        max=cube.max(0).tolist(),
    )
    nor = accessor(bufferView=inter, byteOffset=12, componentType=5126, count=8, type="VEC3")
    idx32 = accessor(
        bufferView=view(faces.astype("<u4").tobytes()), componentType=5125, count=36, type="SCALAR"
    )
    idx8 = accessor(
        bufferView=view(faces.astype("<u1").tobytes()), componentType=5121, count=36, type="SCALAR"
    )
    strip_pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 2, 0.5]], "<f4")
    strip = accessor(
        bufferView=view(strip_pts.tobytes()),
        componentType=5126,
        count=5,
        type="VEC3",
        min=strip_pts.min(0).tolist(),
        max=strip_pts.max(0).tolist(),
    )
    tri_pts = np.array([[0, 0, 0], [3, 0, 0], [0, 0, -1]], "<f4")
    uri = "data:application/octet-stream;base64," + base64.b64encode(tri_pts.tobytes()).decode()
    views.append({"buffer": 1, "byteLength": 36})
    tri = accessor(
        bufferView=len(views) - 1,
        componentType=5126,
        count=3,
        type="VEC3",
        min=tri_pts.min(0).tolist(),
        max=tri_pts.max(0).tolist(),
    )
    material = {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.1, 1]}}
    meshes = [
        {
            "primitives": [
                {"attributes": {"POSITION": pos, "NORMAL": nor}, "indices": idx32, "material": 0}
            ]
        },
        {"primitives": [{"attributes": {"POSITION": pos}, "indices": idx8}]},
        {"primitives": [{"attributes": {"POSITION": strip}, "mode": 5, "material": 0}]},
        {"primitives": [{"attributes": {"POSITION": tri}}]},
    ]
    m_root = trs((1, 0, -2), (0, math.sin(0.3), 0, math.cos(0.3)))
    m_group = trs((0, 1, 0), (math.sin(0.2), 0, 0, math.cos(0.2)), (1, 2, 1))
    m_a = trs((0.5, 0, 0))
    m_b = trs((2, 0, 0), (0, 0, math.sin(0.5), math.cos(0.5)), (-1, 1, 0.5))
    nodes = [
        {"name": "root", "matrix": m_root.T.reshape(-1).tolist(), "children": [1, 4]},
        {
            "name": "group",
            "translation": [0, 1, 0],
            "rotation": [math.sin(0.2), 0, 0, math.cos(0.2)],
            "scale": [1, 2, 1],
            "children": [2, 3],
        },
        {"name": "a", "mesh": 0, "translation": [0.5, 0, 0]},
        {
            "name": "b",
            "mesh": 1,
            "translation": [2, 0, 0],
            "rotation": [0, 0, math.sin(0.5), math.cos(0.5)],
            "scale": [-1, 1, 0.5],
        },
        {"name": "strip", "mesh": 2, "children": [5]},
        {"mesh": 3, "scale": [1, 1, 2]},
    ]
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": [material],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}, {"byteLength": 36, "uri": uri}],
    }

    def world(m, pts):
        return (np.c_[pts, np.ones(len(pts))] @ m.T)[:, :3]

    expected = {
        "a": world(m_root @ m_group @ m_a, cube),
        "b": world(m_root @ m_group @ m_b, cube),
        "strip": world(m_root, strip_pts),
        "node_5": world(m_root @ trs(s=(1, 1, 2)), tri_pts),
    }
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    body = (
        struct.pack("<I4s", len(text), b"JSON")
        + text
        + struct.pack("<I4s", len(blob), b"BIN\0")
        + bytes(blob)
    )
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body, expected


def info_for(objects: list[str]) -> dict:
    return {
        "id": "hand",
        "room_type": "test",
        "height": 1.0,
        "size": [1.0, 1.0],
        "objects": [{"id": o, "category": "box", "support": None} for o in objects],
    }


@needs_chromium
def test_the_viewer_reads_nested_transforms_strides_strips_and_data_uris(browser, tmp_path):
    glb, expected = hand_made_glb()
    path = tmp_path / "hand.html"
    path.write_bytes(page_html(glb, info_for(["a", "b"])))
    open_page(browser, path)
    png = png_pixels(browser.screenshot())
    assert browser.errors == []
    for name, pts in expected.items():
        assert_bounds(
            browser.evaluate(f"window.viewer.bounds('{name}')"), pts.min(0), pts.max(0), 1e-5
        )
    assert sorted(browser.evaluate("window.viewer.groups()")) == ["a", "b", "node_5", "strip"]
    # cube 12 + cube 12 + strip 3 + triangle 1
    assert browser.evaluate("window.viewer.triangles") == 28
    assert len(np.unique(png.reshape(-1, 3), axis=0)) > 50


@needs_chromium
def test_the_viewer_reads_a_trimesh_glb(browser, tmp_path):
    """The scene.glb that trimesh wrote before our own writer (no root rotation: z up)."""
    trimesh = pytest.importorskip("trimesh")
    tm_scene = trimesh.Scene()
    tm_scene.add_geometry(
        trimesh.creation.box([1, 2, 3]),
        node_name="box_0",
        transform=trs((1, 2, 1.5), (0, 0, math.sin(0.4), math.cos(0.4))),
    )
    tm_scene.add_geometry(
        trimesh.creation.icosphere(2), node_name="ball_0", transform=trs((-2, 0, 1))
    )
    path = tmp_path / "old.html"
    path.write_bytes(page_html(tm_scene.export(file_type="glb"), info_for(["box_0", "ball_0"])))
    open_page(browser, path)
    assert browser.errors == []
    lo, hi = tm_scene.bounds
    assert_bounds(browser.evaluate("window.viewerBounds"), lo, hi, 1e-5)
    assert sorted(browser.evaluate("window.viewer.groups()")) == ["ball_0", "box_0"]


@needs_chromium
def test_a_broken_glb_is_reported_on_the_page(browser, tmp_path):
    path = tmp_path / "bad.html"
    path.write_bytes(page_html(b"glTF\x02\x00\x00\x00" + bytes(8), info_for([])))
    browser.errors.clear()
    browser.open(path)
    assert "GLB" in browser.evaluate("window.viewerError")
    assert "Cannot show the scene" in browser.evaluate(
        "document.getElementById('status').textContent"
    )
    assert browser.errors and "pair2scene viewer" in browser.errors[0]
    browser.errors.clear()
