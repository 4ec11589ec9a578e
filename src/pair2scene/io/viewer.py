"""``scene.html`` and ``index.html``: pages to look at generated scenes in a browser, offline.

:func:`scene_html` is one self-contained page per scene: the scene's ``scene.glb``
(:func:`pair2scene.io.glb.glb_bytes`) embedded as base64 and a small WebGL viewer of our
own (``resources/viewer/viewer.js``) that parses it (nodes' transforms, meshes, accessors,
materials' ``baseColorFactor``; flat normals where a primitive has none), draws it with
ambient + one directional light, orbits with the mouse or touch, and lists the objects
(id, category; a click highlights one, in the list or in the view). Walls between the
camera and the room are cut away (a checkbox). The page loads nothing from anywhere.

:func:`index_html` is a gallery of an output folder: one card per scene folder (its
``bev.png``, room type, object count, a link to its ``scene.html``), sorted by scene id,
with relative links only, so the folder can be moved or zipped as it is.

The page sets ``window.viewerReady = true`` once it has drawn a frame and
``window.viewerError`` when it cannot show the scene; ``window.viewer.bounds(name)`` gives
the world bounds (glTF's y-up frame, node transforms applied) of the whole scene, an
object (by id) or a room piece (``floor``, ``wall_0_0``...): tests and tools use them.
"""

from __future__ import annotations

import base64
import html
import json
import os
import re
from collections import Counter
from functools import cache
from importlib import resources
from pathlib import Path
from urllib.parse import quote

import numpy as np

from pair2scene.assets.mesh import Asset
from pair2scene.io.atomic import atomic_write_bytes
from pair2scene.io.glb import glb_bytes
from pair2scene.io.jsondoc import read_json_file
from pair2scene.io.scene_meshes import semantic_color
from pair2scene.scene.model import Scene

SCENE_HTML = "scene.html"
INDEX_HTML = "index.html"
_RESOURCES = "pair2scene.resources"
_FOLDER = "viewer"
_SLOT = re.compile(r"\{\{(\w+)\}\}")


@cache
def _resource(name: str) -> str:
    """The text of ``resources/viewer/<name>`` (installed as package data)."""
    return resources.files(_RESOURCES).joinpath(_FOLDER, name).read_text(encoding="utf-8")


def _fill(template: str, values: dict[str, str]) -> str:
    """``template`` with each ``{{name}}`` replaced by ``values[name]`` in one pass (what
    is put in is never scanned again); a missing value is an error."""
    return _SLOT.sub(lambda m: values[m.group(1)], template)


def _script_json(data: object) -> str:
    """JSON safe inside a ``<script>`` element: no ``<``, ``>`` or ``&`` (escaped as
    ``\\u003c``... which JSON.parse reads back), so no ``</script>`` can end it early."""
    text = json.dumps(data, ensure_ascii=False, separators=(",", ":"))
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def _hex(rgb: tuple[int, int, int]) -> str:
    return "#{:02x}{:02x}{:02x}".format(*rgb)


def _count(n: int, word: str) -> str:
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def scene_info(scene: Scene) -> dict:
    """What the page says about ``scene`` besides its geometry."""
    poly = np.asarray(scene.room.floor_polygon, float)
    extent = poly.max(0) - poly.min(0) if len(poly) else np.zeros(2)
    return {
        "id": scene.id,
        "room_type": scene.room.type,
        "height": float(scene.room.height),
        "size": [round(float(extent[0]), 3), round(float(extent[1]), 3)],
        "objects": [
            {"id": o.id, "category": o.category, "support": o.support} for o in scene.objects
        ],
    }


def page_html(glb: bytes, info: dict, back_link: str | None = None) -> bytes:
    """The viewer page for a GLB and its :func:`scene_info` (any GLB the viewer reads;
    objects are the nodes named by ``info["objects"][i]["id"]``)."""
    esc = html.escape
    items = []
    for o in info["objects"]:
        items.append(
            f'    <li data-id="{esc(o["id"])}" tabindex="0" role="option">'
            f'<span class="swatch" style="background:{_hex(semantic_color(o["category"]))}">'
            f'</span><span class="oid">{esc(o["id"])}</span>'
            f'<span class="cat">{esc(o["category"])}</span></li>'
        )
    w, d = info.get("size", (0.0, 0.0))
    back = f'<p><a href="{esc(back_link)}">&larr; all scenes</a></p>' if back_link else ""
    page = _fill(
        _resource("page.html"),
        {
            "title": esc(info["id"]),
            "css": _resource("viewer.css"),
            "back": back,
            "room_type": esc(info["room_type"].replace("_", " ")),
            "object_count": _count(len(info["objects"]), "object"),
            "room_size": f"{w:.1f} &times; {d:.1f} &times; {info['height']:.1f} m",
            "objects": "\n".join(items),
            "info": _script_json(info),
            "glb": base64.b64encode(glb).decode("ascii"),
            "js": _resource("viewer.js"),
        },
    )
    return page.encode("utf-8")


def scene_html(
    scene: Scene,
    assets: dict[str, Asset],
    back_link: str | None = None,
    glb: bytes | None = None,
) -> bytes:
    """The self-contained viewer page of ``scene`` (its :func:`glb_bytes` embedded: ``glb``
    when the caller has them already). ``back_link``: a relative link shown as "all
    scenes" (e.g. ``../index.html``)."""
    glb = glb_bytes(scene, assets) if glb is None else glb
    return page_html(glb, scene_info(scene), back_link)


def write_viewer(
    folder: str | os.PathLike, scene: Scene, assets: dict[str, Asset],
    back_link: str | None = None,
) -> Path:  # fmt: skip
    """Write ``folder/scene.html`` atomically; returns its path."""
    path = Path(folder) / SCENE_HTML
    atomic_write_bytes(path, scene_html(scene, assets, back_link))
    return path


def _card(folder: Path) -> tuple[str, str, str] | None:
    """(scene id, the card's HTML, room type) of one scene folder; None when it is not one."""
    path = folder / "scene.json"
    if not path.is_file():
        return None
    esc = html.escape
    href = quote(folder.name)
    try:
        doc = read_json_file(path, "scene.json")
        scene_id = doc["id"] if isinstance(doc.get("id"), str) else folder.name
        room_type = str(doc["room"]["type"])
        n = len(doc["objects"])
        facts = (
            f'<span class="tag">{esc(room_type)}</span> '
            f'<span class="tag">{_count(n, "object")}</span>'
        )
        broken = ""
    except Exception as e:  # (any bad file: the card says so, the gallery stays)
        scene_id, room_type = folder.name, ""
        facts = f'<span class="muted">unreadable scene.json ({esc(type(e).__name__)})</span>'
        broken = " broken"
    if (folder / "bev.png").is_file():
        thumb = f'<img src="{href}/bev.png" alt="top view of {esc(scene_id)}" loading="lazy">'
    else:
        thumb = '<span class="none">no bev.png</span>'
    links = []
    if (folder / SCENE_HTML).is_file():
        links.append(f'<a href="{href}/{SCENE_HTML}">3D view</a>')
        main = f"{href}/{SCENE_HTML}"
    else:
        main = f"{href}/scene.glb" if (folder / "scene.glb").is_file() else f"{href}/scene.json"
    if (folder / "scene.glb").is_file():
        links.append(f'<a href="{href}/scene.glb">scene.glb</a>')
    links.append(f'<a href="{href}/scene.json">scene.json</a>')
    card = (
        f'<article class="card{broken}" data-id="{esc(scene_id)}" data-room="{esc(room_type)}">'
        f'<a class="thumb" href="{main}">{thumb}</a>'
        f'<div class="body"><h2>{esc(scene_id)}</h2>{facts}'
        f'<div class="links">{" ".join(links)}</div></div></article>'
    )
    return scene_id, card, room_type


def index_html(out_folder: str | os.PathLike) -> bytes:
    """The gallery page of an output folder: one card per scene folder (a folder not
    starting with ``.`` that holds a ``scene.json``), sorted by scene id."""
    out = Path(out_folder)
    cards = []
    try:
        entries = sorted(os.scandir(out), key=lambda e: e.name)
    except OSError:
        entries = []
    for entry in entries:
        if entry.name.startswith(".") or not entry.is_dir():
            continue
        card = _card(Path(entry.path))
        if card is not None:
            cards.append(card)
    cards.sort(key=lambda c: c[0])
    rooms = Counter(c[2] for c in cards if c[2])
    summary = _count(len(cards), "scene")
    if rooms:
        summary += ": " + ", ".join(f"{n} {html.escape(r)}" for r, n in sorted(rooms.items()))
    title = f"pair2scene \u2014 {out.resolve().name or out}"
    page = _fill(
        _resource("gallery.html"),
        {
            "title": html.escape(title),
            "css": _resource("viewer.css"),
            "summary": summary,
            "cards": "\n".join(c[1] for c in cards),
        },
    )
    return page.encode("utf-8")


def write_index(out_folder: str | os.PathLike) -> Path:
    """Write ``out_folder/index.html`` atomically; returns its path."""
    path = Path(out_folder) / INDEX_HTML
    atomic_write_bytes(path, index_html(out_folder))
    return path
