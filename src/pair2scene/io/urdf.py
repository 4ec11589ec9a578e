"""A placed scene as URDF files: the format robot-learning simulators load objects from
(PyBullet, SAPIEN / ManiSkill, MuJoCo, Drake, Isaac Sim's importer, Genesis).

URDF describes one robot, a tree of links, and has no notion of a scene of separate
bodies; so the folder holds one URDF per object and a scene file that places them::

    folder/
      scene_urdf.json     every object's URDF, pose, fixed or free, mass, friction
      scene.urdf          everything in one file: a link per object under a ``world`` link
      room.urdf           the floor and walls, one static link ``room``
      objects/<name>.urdf one link per object (its name: the id made a portable name)
      meshes/<name>_visual.obj, meshes/<name>_part_<i>.obj, meshes/room_<piece>.obj

Each object's link has an ``<inertial>`` (:mod:`pair2scene.io.physical`: mass, origin at
the centre of mass, the full inertia tensor in the link's axes), one ``<visual>`` (the
whole asset, its semantic colour) and one ``<collision>`` per convex part: loaders make
a convex hull of each collision mesh, so the parts stay separate files. Mesh paths are
relative to the URDF that names them. Friction is PyBullet's ``<contact>`` extension in
each link (other loaders ignore it and take it from ``scene_urdf.json``).

What to load where:

- **PyBullet**: each entry of ``scene_urdf.json`` with ``loadURDF(urdf, position,
  quat_xyzw, useFixedBase=fixed)``, and ``room.urdf`` with ``useFixedBase=True``.
  PyBullet does not simulate ``floating`` joints (it makes them fixed), so not
  ``scene.urdf``.
- **SAPIEN 3 / ManiSkill 3**: ``scene.urdf`` with ``URDFLoader.load_multiple`` (SAPIEN)
  or the builders of ``URDFLoader.parse`` (ManiSkill's loader): the ``world`` link with
  the room and the fixed objects becomes one fixed articulation, each ``floating`` child
  of ``world`` a free actor at its joint's pose. Or each entry of ``scene_urdf.json``
  (``fix_root_link = fixed``, ``sapien.Pose(position, quat_wxyz)``). SAPIEN reads no
  friction from URDF: set it per link (``set_link_material``) from ``scene_urdf.json``.
- **MuJoCo** (and viewers like yourdfpy): ``scene.urdf`` as it is; MuJoCo turns each
  ``floating`` joint into a free joint and welds the ``fixed`` ones to the world. The
  file carries MuJoCo's ``<mujoco><compiler strippath="false"/></mujoco>`` extension so
  MuJoCo keeps the ``meshes/`` folder of the paths (it drops folders by default); other
  parsers ignore it.

The folder is written into a temporary folder beside it and renamed into place: it
appears whole, or the previous one stays.
"""

from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from pair2scene.assets.mesh import Asset, Mesh
from pair2scene.io.atomic import replace_folder
from pair2scene.io.names import safe_name
from pair2scene.io.physical import MATERIAL_FRICTION, BodyPhysics, scene_physics
from pair2scene.io.scene_json import dumps_json
from pair2scene.io.scene_meshes import room_color, room_meshes, semantic_color
from pair2scene.scene.geometry import orthonormalize
from pair2scene.scene.model import Scene

FORMAT = "pair2scene.scene_urdf"
"""``format`` of ``scene_urdf.json``."""
VERSION = 1
"""``version`` of ``scene_urdf.json``."""
SCENE_FILE, COMBINED_FILE, ROOM_FILE = "scene_urdf.json", "scene.urdf", "room.urdf"
"""The folder's top-level files."""
OBJECTS_DIR, MESHES_DIR = "objects", "meshes"
"""Sub-folders: one URDF per object; every OBJ mesh."""
WORLD_LINK, ROOM_LINK = "world", "room"
"""Reserved link names of ``scene.urdf``: the fixed root and the room."""
GRAVITY_M_S2 = 9.81
"""Gravity along -z, written to ``scene_urdf.json`` for loaders that set it themselves."""
ROOM_MATERIAL = "wood"
"""Material of the floor and walls (a wooden floor); its friction is
:data:`pair2scene.io.physical.MATERIAL_FRICTION`'s."""
DIGITS = 9
"""Significant digits of the numbers in URDF and OBJ files (float64 would need 17; nine
keep a vertex to a nanometre and an inertia of 1e-10 kg m^2 to its rounding)."""
INERTIA_ENTRIES = {
    "ixx": (0, 0), "ixy": (0, 1), "ixz": (0, 2), "iyy": (1, 1), "iyz": (1, 2), "izz": (2, 2)
}  # fmt: skip
"""URDF's ``<inertia>`` attributes and the tensor entries they hold."""
ZERO_BELOW = 1e-12
"""Numbers smaller than this in magnitude are written as 0: rounding noise (a centre of
mass at 1e-17 m, a product of inertia of 1e-20 kg m^2), far below any real quantity and
below :data:`pair2scene.io.physical.MIN_INERTIA`."""


def write_urdf(
    scene: Scene, assets: dict[str, Asset], folder: str | os.PathLike, dynamic: str = "small"
) -> Path:
    """Write ``scene`` (posed ``assets``, by object id) as URDF files into ``folder``
    (see the module docstring for the layout); ``dynamic`` picks the free bodies
    (:data:`pair2scene.io.physical.DYNAMIC_CHOICES`). Objects without an asset are left
    out. The folder appears whole or not at all; one already there is replaced."""
    bodies = scene_physics(scene, assets, dynamic=dynamic)
    return replace_folder(folder, lambda tmp: _write_tree(tmp, scene, assets, bodies, dynamic))


def _write_tree(root: Path, scene: Scene, assets: dict, bodies: dict, dynamic: str) -> None:
    """Every file of the folder, into ``root``."""
    (root / OBJECTS_DIR).mkdir()
    (root / MESHES_DIR).mkdir()
    names = _LinkNames()
    combined = _robot(safe_name(scene.id))
    ET.SubElement(combined, "link", name=WORLD_LINK)
    room = _room_link(root, scene)
    _write_xml(root / ROOM_FILE, _robot(ROOM_LINK, room, mujoco=True))
    combined.append(_with_paths(room, ""))
    combined.append(_joint(f"{ROOM_LINK}_joint", "fixed", ROOM_LINK, np.zeros(3), np.eye(3)))

    entries = []
    for obj in scene.objects:
        body = bodies.get(obj.id)
        asset = assets.get(obj.id)
        if body is None or asset is None:
            continue
        name = names.take(obj.id)
        link = _object_link(root, name, obj.category, asset, body)
        urdf = f"{OBJECTS_DIR}/{name}.urdf"
        _write_xml(root / urdf, _robot(name, _with_paths(link, "../"), mujoco=True))
        rotation = orthonormalize(obj.box.rotation)
        position = np.asarray(obj.box.center, dtype=float)
        kind = "floating" if body.dynamic else "fixed"
        combined.append(_with_paths(link, ""))
        combined.append(_joint(f"{name}_joint", kind, name, position, rotation))
        xyzw = quat_xyzw(rotation)
        entries.append(
            {
                "id": obj.id,
                "name": name,
                "category": obj.category,
                "support": obj.support,
                "urdf": urdf,
                "fixed": not body.dynamic,
                "position": position,
                "quat_xyzw": xyzw,
                "quat_wxyz": np.roll(xyzw, 1),
                "rpy": rpy(rotation),
                "mass": body.mass,
                "friction": body.friction,
                "material": body.material,
            }
        )
    _add_mujoco_compiler(combined)
    _write_xml(root / COMBINED_FILE, combined)
    doc = {
        "format": FORMAT,
        "version": VERSION,
        "scene_id": scene.id,
        "units": {"length": "m", "mass": "kg"},
        "up_axis": "z",
        "gravity": [0.0, 0.0, -GRAVITY_M_S2],
        "dynamic": dynamic,
        "combined": COMBINED_FILE,
        "room": {
            "urdf": ROOM_FILE,
            "fixed": True,
            "position": [0.0, 0.0, 0.0],
            "quat_xyzw": [0.0, 0.0, 0.0, 1.0],
            "quat_wxyz": [1.0, 0.0, 0.0, 0.0],
            "rpy": [0.0, 0.0, 0.0],
            "friction": MATERIAL_FRICTION[ROOM_MATERIAL],
            "material": ROOM_MATERIAL,
        },
        "objects": entries,
    }
    _write_text(root / SCENE_FILE, dumps_json(_plain(doc)))


# -- links -----------------------------------------------------------------------------
def _room_link(root: Path, scene: Scene) -> ET.Element:
    """The static ``room`` link: a visual and a collision per floor and wall piece, and
    a mass of 0 (PyBullet's mark of a static link; others fix it by its joint or root)."""
    link = ET.Element("link", name=ROOM_LINK)
    _inertial(link, 0.0, np.zeros(3), np.zeros((3, 3)))
    for piece, mesh in room_meshes(scene.room):
        file = f"{MESHES_DIR}/{ROOM_LINK}_{piece}.obj"
        _write_obj(root / file, mesh, piece)
        color = room_color(piece)
        label = f"{ROOM_LINK}_{piece}"
        _geometry(link, "visual", label, file, (f"{ROOM_LINK}_{_color_name(color)}", color))
        _geometry(link, "collision", label, file)
    _friction(link, MATERIAL_FRICTION[ROOM_MATERIAL])
    return link


def _object_link(root: Path, name: str, category: str, asset: Asset, body: BodyPhysics):
    """An object's link: inertial, visual (the whole asset), a collision per convex part;
    mesh paths relative to the folder (:func:`_with_paths` moves them)."""
    link = ET.Element("link", name=name)
    _inertial(link, body.mass, body.com, body.inertia)
    visual = f"{MESHES_DIR}/{name}_visual.obj"
    _write_obj(root / visual, asset.mesh, name)
    _geometry(link, "visual", f"{name}_visual", visual, (category, semantic_color(category)))
    width = max(3, len(str(len(body.parts) - 1)))
    for k, part in enumerate(body.parts):
        label = f"{name}_part_{k:0{width}d}"
        file = f"{MESHES_DIR}/{label}.obj"
        _write_obj(root / file, part, label)
        _geometry(link, "collision", label, file)
    _friction(link, body.friction)
    return link


def _inertial(link, mass: float, com: np.ndarray, inertia: np.ndarray) -> None:
    """``<inertial>``: ``mass`` (kg) at ``com`` (3,), the full (3, 3) tensor about it in
    the link's axes (URDF's ``ixy`` is the tensor's entry, minus the product integral)."""
    el = ET.SubElement(link, "inertial")
    ET.SubElement(el, "origin", xyz=_vec(com), rpy="0 0 0")
    ET.SubElement(el, "mass", value=_num(mass))
    i = np.asarray(inertia, dtype=float)
    i = (i + i.T) / 2
    ET.SubElement(el, "inertia", {key: _num(i[a, b]) for key, (a, b) in INERTIA_ENTRIES.items()})


def _geometry(link, kind: str, name: str, file: str, material=None) -> None:
    """A ``<visual>`` or ``<collision>`` named ``name`` (unique in the scene: MuJoCo names
    a geom by it) of mesh ``file`` (relative to the folder) at the link's origin;
    ``material`` (name, sRGB 0-255) colours a visual."""
    el = ET.SubElement(link, kind, name=name)
    ET.SubElement(el, "origin", xyz="0 0 0", rpy="0 0 0")
    geometry = ET.SubElement(el, "geometry")
    ET.SubElement(geometry, "mesh", filename=file)
    if material is not None:
        label, rgb = material
        mat = ET.SubElement(el, "material", name=label)
        ET.SubElement(mat, "color", rgba=_vec([*(np.asarray(rgb) / 255.0), 1.0]))


def _friction(link, friction: float) -> None:
    """PyBullet's friction extension: ``<contact><lateral_friction value=.../></contact>``."""
    contact = ET.SubElement(link, "contact")
    ET.SubElement(contact, "lateral_friction", value=_num(friction))


def _with_paths(link: ET.Element, prefix: str) -> ET.Element:
    """A copy of ``link`` whose mesh file names start with ``prefix`` (``../`` from
    ``objects/``)."""
    out = ET.fromstring(ET.tostring(link))
    for mesh in out.iter("mesh"):
        mesh.set("filename", prefix + mesh.get("filename"))
    return out


def _joint(name: str, kind: str, child: str, xyz: np.ndarray, rotation: np.ndarray):
    """A joint from the ``world`` link to ``child`` at pose (xyz, rotation)."""
    joint = ET.Element("joint", name=name, type=kind)
    ET.SubElement(joint, "origin", xyz=_vec(xyz), rpy=_vec(rpy(rotation)))
    ET.SubElement(joint, "parent", link=WORLD_LINK)
    ET.SubElement(joint, "child", link=child)
    return joint


def _robot(name: str, link: ET.Element | None = None, mujoco: bool = False) -> ET.Element:
    robot = ET.Element("robot", name=name)
    if link is not None:
        robot.append(link)
    if mujoco:
        _add_mujoco_compiler(robot)
    return robot


def _add_mujoco_compiler(robot: ET.Element) -> None:
    """MuJoCo's URDF extension: keep mesh paths' folders (``strippath`` is on for URDF)."""
    mujoco = ET.SubElement(robot, "mujoco")
    ET.SubElement(mujoco, "compiler", strippath="false")


# -- rotations ---------------------------------------------------------------------------
def rpy(rotation: np.ndarray) -> np.ndarray:
    """URDF's roll, pitch, yaw (3,) of a rotation (3, 3): ``R = Rz(yaw) Ry(pitch) Rx(roll)``
    (fixed axes x, then y, then z). At pitch +-90 degrees roll is taken as 0."""
    r = np.asarray(rotation, dtype=float)
    cos_pitch = math.hypot(r[0, 0], r[1, 0])
    pitch = math.atan2(-r[2, 0], cos_pitch)
    if cos_pitch > 1e-9:
        roll = math.atan2(r[2, 1], r[2, 2])
        yaw = math.atan2(r[1, 0], r[0, 0])
    else:  # gimbal lock: only roll - yaw (pitch +90) or roll + yaw (-90) is defined
        roll = 0.0
        yaw = math.atan2(-r[0, 1], r[1, 1])
    return np.array([roll, pitch, yaw])


def quat_xyzw(rotation: np.ndarray) -> np.ndarray:
    """The unit quaternion (x, y, z, w) of a rotation (3, 3), w >= 0."""
    r = np.asarray(rotation, dtype=float)
    # the largest of 4w^2, 4x^2, 4y^2, 4z^2 gives the best-conditioned formula
    t = np.array(
        [
            1 + r[0, 0] - r[1, 1] - r[2, 2],
            1 - r[0, 0] + r[1, 1] - r[2, 2],
            1 - r[0, 0] - r[1, 1] + r[2, 2],
            1 + r[0, 0] + r[1, 1] + r[2, 2],
        ]
    )
    k = int(np.argmax(t))
    s = 0.5 / math.sqrt(t[k])
    if k == 0:
        q = [t[0], r[0, 1] + r[1, 0], r[0, 2] + r[2, 0], r[2, 1] - r[1, 2]]
    elif k == 1:
        q = [r[0, 1] + r[1, 0], t[1], r[1, 2] + r[2, 1], r[0, 2] - r[2, 0]]
    elif k == 2:
        q = [r[0, 2] + r[2, 0], r[1, 2] + r[2, 1], t[2], r[1, 0] - r[0, 1]]
    else:
        q = [r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1], t[3]]
    q = np.array(q) * s
    q /= np.linalg.norm(q)
    return -q if q[3] < 0 else q


# -- files -------------------------------------------------------------------------------
class _LinkNames:
    """Portable, unique link and file names for object ids: :func:`safe_name`, then a
    suffix where two ids would share a name (case-insensitively: macOS and Windows file
    systems) or an id would take a reserved link name."""

    def __init__(self) -> None:
        self.used = {WORLD_LINK, ROOM_LINK}

    def take(self, object_id: str) -> str:
        base = safe_name(object_id)
        name, n = base, 1
        while name.lower() in self.used:
            name, n = f"{base}_{n}", n + 1
        self.used.add(name.lower())
        return name


def _write_obj(path: Path, mesh: Mesh, name: str) -> None:
    """A Wavefront OBJ of ``mesh``: vertices in metres, triangles counter-clockwise."""
    fmt = f"%.{DIGITS}g"
    lines = [f"# pair2scene: {name}, metres, z up", f"o {name}"]
    lines += ["v " + " ".join(fmt % x for x in v) for v in mesh.vertices.tolist()]
    lines += [f"f {a} {b} {c}" for a, b, c in (mesh.faces + 1).tolist()]
    _write_text(path, "\n".join(lines) + "\n")


def _write_xml(path: Path, robot: ET.Element) -> None:
    tree = ET.ElementTree(robot)
    ET.indent(tree, space="  ")
    text = ET.tostring(robot, encoding="unicode")
    _write_text(path, '<?xml version="1.0" encoding="utf-8"?>\n' + text + "\n")


def _write_text(path: Path, text: str) -> None:
    """A file of the temporary folder (the folder's rename makes the write atomic)."""
    path.write_text(text, encoding="utf-8")


def _plain(x):
    """JSON-ready copy: numpy to Python, floats to :data:`DIGITS` significant digits."""
    if isinstance(x, dict):
        return {k: _plain(v) for k, v in x.items()}
    if isinstance(x, np.ndarray):
        x = x.tolist()
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (float, np.floating)):
        return float(_num(x))
    return x


def _num(x: float) -> str:
    x = float(x)
    return "0" if abs(x) < ZERO_BELOW else f"{x:.{DIGITS}g}"


def _vec(values) -> str:
    return " ".join(_num(v) for v in np.asarray(values, dtype=float).reshape(-1))


def _color_name(rgb) -> str:
    return "rgb_" + "_".join(str(int(c)) for c in rgb)
