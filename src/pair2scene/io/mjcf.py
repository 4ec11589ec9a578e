"""MuJoCo export: a placed scene as an MJCF model (``scene.xml``) with its meshes.

The model is built with MuJoCo's own :class:`mujoco.MjSpec` API (never an XML template),
compiled once to check it, and written by ``MjSpec.to_xml``. The physical facts (who
moves, masses, inertia, friction, collision parts) come from
:mod:`pair2scene.io.physical`, shared with the other simulator exports, so the scene
behaves the same everywhere.

What ``scene.xml`` holds:

- the floor: a plane at z = 0 (``floor``), and the room's walls, door lintels, the wall
  under and above each window and its pane from
  :func:`~pair2scene.io.scene_meshes.room_meshes`, as static box geoms named as there
  (doors stay open gaps);
- one body per object, named by its id: a visual mesh geom (``<id>/visual``, the whole
  asset, group 2, no contacts) and one collision geom per convex part
  (``<id>/collision/<k>``, group 3): a box primitive where the part is an axis-aligned
  box (exact, and MuJoCo's box-box contacts are its most stable), else a convex mesh;
- its mass, centre of mass and full inertia tensor (``fullinertia``, which MuJoCo stores
  as principal moments and a frame), the friction of its material, and a free joint if
  it is dynamic; a fixed object has no joint (it is welded to the world);
- the object's category, support, material and whether it is free, as custom text
  elements ``category:<id>``, ``support:<id>``, ``material:<id>``, ``dynamic:<id>``
  (read back with :func:`model_text`).

Meshes are Wavefront OBJ files in ``meshes/`` beside ``scene.xml`` (``meshdir`` is
relative, so the folder loads from any working directory and can be moved).

Contact and solver settings (the figures of ``benchmarks/sim_exports.py`` in
docs/benchmarks.md were measured with them): see :data:`TIMESTEP_S` and the constants
after it.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from pair2scene.assets.mesh import Asset, Mesh, axis_aligned_box
from pair2scene.curation.physics import quat_wxyz
from pair2scene.io.atomic import atomic_write_bytes, current_umask, replace_folder
from pair2scene.io.names import safe_name
from pair2scene.io.physical import BodyPhysics, rolling_friction, scene_physics
from pair2scene.io.scene_meshes import room_meshes, semantic_color
from pair2scene.scene.model import Scene, SceneObject

__all__ = ["MESH_DIR", "SCENE_XML", "build_spec", "mjcf_files", "model_text", "write_mjcf"]

SCENE_XML = "scene.xml"
"""The model's file name in the export folder."""
MESH_DIR = "meshes"
"""The folder of mesh files, relative to :data:`SCENE_XML` (MJCF ``meshdir``)."""

ROOM_MESH_PREFIX = "_room_"
"""File-name prefix of a room piece written as a mesh (never an object's: those start
with a letter or digit, :func:`~pair2scene.io.names.safe_name`)."""

TIMESTEP_S = 0.002
"""s; MuJoCo's default: ten steps per contact time constant (:data:`CONTACT_SOLREF`), so
resting contacts are resolved smoothly even for 5 g objects."""
INTEGRATOR = "implicitfast"
"""Implicit in velocity for the damping terms: unconditionally stable for the contact
damping of light bodies, MuJoCo's recommended integrator for contact-rich scenes."""
CONE = "elliptic"
"""Elliptic friction cones: the exact Coulomb cone (a pyramidal cone lets resting objects
creep sideways under small tangential forces)."""
IMPRATIO = 10.0
"""Ratio of frictional to normal constraint impedance: above 1 makes friction 'harder'
than the normal contact, which stops the slow slip of soft contacts on objects that
should stick (MuJoCo's documentation recommends it with elliptic cones)."""
SOLVER_ITERATIONS = 100
"""Newton iterations per step (MuJoCo's default); resting scenes converge in a few."""
CONTACT_SOLREF = (0.02, 1.0)
"""(time constant s, damping ratio) of every contact: MuJoCo's default, critically
damped, so an object placed 2 mm into its support (the placement tolerance) is pushed
out in ~0.05 s without a bounce."""
CONTACT_SOLIMP = (0.95, 0.99, 0.001, 0.5, 2.0)
"""Impedance rising from 0.95 to 0.99 over the first millimetre of penetration: stiffer
than the default (0.9, 0.95), so a resting object sinks a fraction of a millimetre, not
several, into its support. With the default, a 2 kg desk lamp whose centre of mass is
7 mm inside the front edge of its base rocked on the soft contact, crept and fell off
its desk within 2 s (benchmarks/sim_exports.py, bedroom seed 5)."""
TORSIONAL_FRICTION = 0.005
"""m; MuJoCo's default torsional friction (used by condim >= 4)."""
ROLLING_FRICTION = 0.0001
"""m; MuJoCo's default rolling friction, for the room and fixed objects (a free object
has its own, :func:`~pair2scene.io.physical.rolling_friction`; MuJoCo uses the larger)."""
CONDIM_DYNAMIC = 6
"""Contact dimension of free objects' collision geoms: sliding, torsional and rolling
friction, so that a pen does not spin about the contact normal and a soft object with a
rounded procedural bottom (a lettuce, a filled bag) does not rock away: without rolling
friction 9 of 1076 free objects of the benchmark's scenes (lettuces, a garbage bag)
rolled 2-11 cm in 2 s."""
FLOOR_MATERIAL_FRICTION = 0.5
"""Floor and walls: wood / laminate on the usual materials (MuJoCo uses the larger
coefficient of a pair, so an object keeps its own when that is higher)."""
GRAVITY = (0.0, 0.0, -9.81)
"""m/s^2, z up."""
BOX_TOL_M = 1e-9
"""A part whose 8 vertices lie on its bounds (within this) is an axis-aligned box and is
exported as a box primitive."""
FLAT_M = 1e-3
"""A mesh part thinner than this along an axis has no proper 3D convex hull for MuJoCo's
qhull; it collides as the box of its extents (it is a slab anyway)."""
VISUAL_GROUP = 2
"""Geom group of visual meshes (shown by default in MuJoCo's viewer)."""
COLLISION_GROUP = 3
"""Geom group of collision geoms (hidden by default; toggle with '3' in the viewer)."""
COLLISION_RGBA = (0.6, 0.6, 0.9, 0.5)
"""Colour of collision geoms when shown."""
ROOM_RGBA = (0.6, 0.6, 0.6, 1.0)
"""Walls and lintels."""
PANE_RGBA = (0.55, 0.75, 0.92, 0.35)
"""Window glass."""
FLOOR_RGBA = (0.91, 0.89, 0.86, 1.0)
"""The floor plane."""


# -- meshes ------------------------------------------------------------------------------
def obj_bytes(mesh: Mesh) -> bytes:
    """``mesh`` as a Wavefront OBJ file (vertices and triangles, 1-based indices)."""
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in mesh.vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in mesh.faces.tolist()]
    return ("\n".join(lines) + "\n").encode("ascii")


def _oriented_box(mesh: Mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centre (3,), half size (3,) and rotation (3, 3) of the box of ``mesh``'s extents
    along its principal directions (for flat parts)."""
    v = mesh.vertices
    ref = v.mean(0)
    _, axes = np.linalg.eigh((v - ref).T @ (v - ref))
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    local = (v - ref) @ axes
    lo, hi = local.min(0), local.max(0)
    return ref + axes @ ((lo + hi) / 2), np.maximum((hi - lo) / 2, FLAT_M / 4), axes


def _box_of_room_piece(mesh: Mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Centre, half size and rotation of a :func:`room_meshes` piece (a rotated box built
    by :func:`~pair2scene.assets.mesh.box`: corners 1, 3 and 4 are one edge from corner 0
    along local x, y and z), or None if its vertices are not such a box."""
    v = mesh.vertices
    if len(v) != 8:
        return None
    edges = np.stack([v[1] - v[0], v[3] - v[0], v[4] - v[0]], axis=1)  # columns x, y, z
    length = np.linalg.norm(edges, axis=0)
    if np.any(length < 1e-9):
        return None
    rot = edges / length
    if not np.allclose(rot.T @ rot, np.eye(3), atol=1e-6) or np.linalg.det(rot) < 0:
        return None
    centre = v.mean(0)
    unit = np.array(
        [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
         [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float
    )  # fmt: skip
    corners = centre + (unit * (length / 2)) @ rot.T
    if not np.allclose(corners, v, atol=1e-6):
        return None
    return centre, length / 2, rot


# -- the model ---------------------------------------------------------------------------
def _configure(spec, scene: Scene) -> None:
    import mujoco

    spec.modelname = safe_name(scene.id)
    spec.meshdir = MESH_DIR
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.compiler.fusestatic = False  # fixed objects keep their bodies and names
    spec.compiler.degree = False
    opt = spec.option
    opt.timestep = TIMESTEP_S
    opt.gravity = list(GRAVITY)
    opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{INTEGRATOR.upper()}")
    opt.cone = getattr(mujoco.mjtCone, f"mjCONE_{CONE.upper()}")
    opt.impratio = IMPRATIO
    opt.iterations = SOLVER_ITERATIONS
    spec.default.geom.solref = list(CONTACT_SOLREF)
    spec.default.geom.solimp = list(CONTACT_SOLIMP)
    spec.default.geom.friction = [FLOOR_MATERIAL_FRICTION, TORSIONAL_FRICTION, ROLLING_FRICTION]
    spec.stat.extent = max(float(np.ptp(scene.room.floor_polygon, axis=0).max()), 1.0)
    spec.stat.center = [*scene.room.floor_polygon.mean(0), scene.room.height / 2]


def _add_room(spec, scene: Scene, files: dict) -> None:
    """The floor plane and every wall piece of :func:`room_meshes` as static geoms (mesh
    files, if any, go to ``files``)."""
    import mujoco

    poly = np.asarray(scene.room.floor_polygon, dtype=float)
    lo, hi = poly.min(0), poly.max(0)
    spec.worldbody.add_geom(
        name="floor",
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        pos=[*((lo + hi) / 2), 0.0],
        size=[*((hi - lo) / 2 + 0.5), 0.25],  # rendering extent; it collides everywhere
        rgba=list(FLOOR_RGBA),
    )
    spec.worldbody.add_light(
        name="sun", pos=[*((lo + hi) / 2), scene.room.height + 3.0], dir=[0.3, 0.2, -1.0]
    ).type = mujoco.mjtLightType.mjLIGHT_DIRECTIONAL
    for name, mesh in room_meshes(scene.room):
        if name == "floor":
            continue
        rgba = list(PANE_RGBA if name.endswith("_pane") else ROOM_RGBA)
        box = _box_of_room_piece(mesh)
        if box is None:  # not a box (room_meshes makes boxes today): its convex hull
            file = f"{ROOM_MESH_PREFIX}{name}.obj"
            files[file] = obj_bytes(mesh)
            spec.add_mesh(name=name, file=file)
            spec.worldbody.add_geom(
                name=name, type=mujoco.mjtGeom.mjGEOM_MESH, meshname=name, rgba=rgba
            )
            continue
        centre, half, rot = box
        spec.worldbody.add_geom(
            name=name,
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=centre,
            quat=quat_wxyz(rot),
            size=half,
            rgba=rgba,
        )


def _add_object(spec, o: SceneObject, phys: BodyPhysics, asset: Asset, files: dict) -> None:
    """Object ``o``'s body (named by its id) with its geoms; its mesh files go to
    ``files`` (file name in :data:`MESH_DIR` -> bytes)."""
    import mujoco

    stem = safe_name(o.id)
    body = spec.worldbody.add_body(name=o.id, pos=o.box.center, quat=quat_wxyz(o.box.rotation))
    body.mass = phys.mass
    body.ipos = phys.com
    i = phys.inertia
    body.fullinertia = [i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]
    body.explicitinertial = True
    if phys.dynamic:
        body.add_freejoint(name=f"{o.id}/free")

    visual = f"{stem}_visual.obj"
    files[visual] = obj_bytes(asset.mesh)
    # (shell inertia: defined for any triangle soup; the body's inertia is explicit)
    spec.add_mesh(
        name=f"{o.id}/visual", file=visual, inertia=mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL
    )
    r, g, b = semantic_color(o.category)
    body.add_geom(
        name=f"{o.id}/visual",
        type=mujoco.mjtGeom.mjGEOM_MESH,
        meshname=f"{o.id}/visual",
        contype=0,
        conaffinity=0,
        group=VISUAL_GROUP,
        rgba=[r / 255, g / 255, b / 255, 1.0],
    )
    rolling = rolling_friction(o.category, o.box.size) if phys.dynamic else ROLLING_FRICTION
    friction = [phys.friction, TORSIONAL_FRICTION, rolling]
    common = dict(
        group=COLLISION_GROUP,
        rgba=list(COLLISION_RGBA),
        friction=friction,
        condim=CONDIM_DYNAMIC if phys.dynamic else 3,
    )
    for k, part in enumerate(phys.parts):
        name = f"{o.id}/collision/{k}"
        as_box = axis_aligned_box(part, BOX_TOL_M)
        if as_box is not None:
            centre, half = as_box
            body.add_geom(
                name=name,
                type=mujoco.mjtGeom.mjGEOM_BOX,
                pos=centre,
                size=np.maximum(half, FLAT_M / 4),
                **common,
            )
            continue
        centre, half, rot = _oriented_box(part)
        if 2 * half.min() < FLAT_M:
            body.add_geom(
                name=name,
                type=mujoco.mjtGeom.mjGEOM_BOX,
                pos=centre,
                quat=quat_wxyz(rot),
                size=half,
                **common,
            )
            continue
        file = f"{stem}_part{k}.obj"
        files[file] = obj_bytes(part)
        spec.add_mesh(name=name, file=file, inertia=mujoco.mjtMeshInertia.mjMESH_INERTIA_CONVEX)
        body.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_MESH, meshname=name, **common)

    spec.add_text(name=f"category:{o.id}", data=o.category)
    spec.add_text(name=f"support:{o.id}", data=o.support or "unknown")
    spec.add_text(name=f"material:{o.id}", data=phys.material)
    spec.add_text(name=f"dynamic:{o.id}", data="free" if phys.dynamic else "fixed")


def build_spec(scene: Scene, assets: dict[str, Asset], dynamic: str = "small"):
    """The :class:`mujoco.MjSpec` of ``scene`` (not compiled) and its mesh files
    (file name in :data:`MESH_DIR` -> OBJ bytes); ``spec.assets`` holds them too, so the
    spec compiles in memory."""
    import mujoco

    physics = scene_physics(scene, assets, dynamic)
    spec = mujoco.MjSpec()
    _configure(spec, scene)
    files: dict[str, bytes] = {}
    _add_room(spec, scene, files)
    by_id = scene.by_id()
    for oid, phys in physics.items():
        _add_object(spec, by_id[oid], phys, assets[oid], files)
    spec.assets = dict(files)
    return spec, files


def mjcf_files(scene: Scene, assets: dict[str, Asset], dynamic: str = "small") -> dict[str, bytes]:
    """Every file of the export, relative path -> bytes: :data:`SCENE_XML` and
    ``meshes/<file>.obj``. The model is compiled once (a model MuJoCo cannot load is
    never written)."""
    spec, files = build_spec(scene, assets, dynamic)
    spec.compile()
    xml = spec.to_xml()
    out = {SCENE_XML: xml.encode("utf-8")}
    out.update({f"{MESH_DIR}/{name}": data for name, data in files.items()})
    return out


# -- writing -----------------------------------------------------------------------------
def write_mjcf(
    scene: Scene, assets: dict[str, Asset], folder: str | Path, dynamic: str = "small"
) -> Path:
    """Write :func:`mjcf_files` into ``folder`` (``scene.xml`` and ``meshes/``); returns
    the path of ``scene.xml``.

    A new folder is written beside its place and renamed into it (it appears whole or
    not at all). Into an existing folder (a scene folder with other files), the meshes
    are written to a hidden temporary folder, swapped for ``meshes/`` by two renames,
    and ``scene.xml`` is replaced last, atomically; other files are left alone."""
    folder = Path(folder)
    files = mjcf_files(scene, assets, dynamic)
    folder.parent.mkdir(parents=True, exist_ok=True)
    if not folder.exists():
        replace_folder(folder, lambda tmp: _write_tree(tmp, files))
        return folder / SCENE_XML

    staged = Path(tempfile.mkdtemp(dir=folder, prefix=f".{MESH_DIR}."))
    old: Path | None = None
    meshes = folder / MESH_DIR
    try:
        meshes_only = {k[len(MESH_DIR) + 1 :]: v for k, v in files.items() if k != SCENE_XML}
        _write_tree(staged, meshes_only)
        os.chmod(staged, 0o777 & ~current_umask())
        if meshes.exists():
            old = Path(tempfile.mkdtemp(dir=folder, prefix=f".{MESH_DIR}.old."))
            meshes.rename(old / MESH_DIR)
        staged.rename(meshes)
        atomic_write_bytes(folder / SCENE_XML, files[SCENE_XML])
    except BaseException:
        if old is not None and (old / MESH_DIR).exists():
            with contextlib.suppress(OSError):
                if meshes.exists():
                    shutil.rmtree(meshes)
                (old / MESH_DIR).rename(meshes)  # the previous meshes go back
        shutil.rmtree(staged, ignore_errors=True)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
    return folder / SCENE_XML


def _write_tree(root: Path, files: dict[str, bytes]) -> None:
    for rel, data in files.items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)


def model_text(model, name: str) -> str | None:
    """The data of the custom text element ``name`` of a loaded :class:`mujoco.MjModel`
    (e.g. ``category:<id>``), or None if it has none."""
    import mujoco

    i = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TEXT, name)
    if i < 0:
        return None
    adr, size = int(model.text_adr[i]), int(model.text_size[i])
    return bytes(model.text_data[adr : adr + size]).split(b"\0", 1)[0].decode("utf-8")
