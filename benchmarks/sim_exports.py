"""Simulation exports: do generated scenes stand still in MuJoCo as exported?

Run from the repository root::

    python benchmarks/sim_exports.py [--scenes 20] [--beyond 5] [--seconds 2] [--no-write]

For ``--scenes`` fit bedrooms, kitchens and living rooms (seeds 0..n-1) and ``--beyond``
dense bedrooms (``mode="beyond"``, ``max_objects=80``), each scene is exported with
:func:`pair2scene.io.mjcf.write_mjcf` (default ``dynamic="small"``: small objects free,
furniture, fixtures and wall objects fixed), loaded back with
``mujoco.MjModel.from_xml_path`` from another working directory, and:

- the deepest initial penetration is read from the contacts of ``mj_forward``;
- the model is simulated for ``--seconds`` under gravity, and each free object's
  displacement (its box centre) is measured; the target is >= 99 % of free objects
  moving less than 2 cm;
- the export time (the MJCF folder alone: physics, meshes, compile, write) is timed.

Writes the figures into ``docs/benchmarks.md`` under ``## Simulation exports`` (that
section only).
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from _docs import machine, replace_section

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "benchmarks.md"
SECTION = "## Simulation exports"
FIT_ROOMS = ("bedroom", "kitchen", "living_room")
BEYOND_OBJECTS = 80
"""Object budget of the dense (``beyond``) bedrooms."""
STILL_M = 0.02
"""A free object that moved less than this in the simulated time stayed put."""
TARGET_SHARE = 0.99
"""Share of free objects that must stay put."""


@dataclass
class Group:
    """Figures of one room type."""

    name: str
    scenes: int = 0
    objects: int = 0
    free: int = 0
    still: int = 0
    deepest_m: float = 0.0
    export_s: list[float] = field(default_factory=list)
    sim_s: list[float] = field(default_factory=list)
    moved: list[str] = field(default_factory=list)
    """``room/seed: object (cm)`` of every object that moved."""

    def add(self, other: Group) -> None:
        self.scenes += other.scenes
        self.objects += other.objects
        self.free += other.free
        self.still += other.still
        self.deepest_m = max(self.deepest_m, other.deepest_m)
        self.export_s += other.export_s
        self.sim_s += other.sim_s
        self.moved += other.moved


def measure(scene, assets, seconds: float, work: Path, label: str, group: Group) -> None:
    """Export one scene, load it from another folder, simulate; add to ``group``."""
    import mujoco

    from pair2scene.io.mjcf import write_mjcf

    folder = Path(tempfile.mkdtemp(dir=work)) / "mjcf"
    t0 = time.perf_counter()
    path = write_mjcf(scene, assets, folder)
    group.export_s.append(time.perf_counter() - t0)
    here = os.getcwd()
    os.chdir(work)  # relative mesh paths must resolve against the XML's folder
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    finally:
        os.chdir(here)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    if data.ncon:
        group.deepest_m = max(group.deepest_m, -float(data.contact.dist[: data.ncon].min()))
    free = mujoco.mjtJoint.mjJNT_FREE
    bodies = [int(model.jnt_bodyid[j]) for j in range(model.njnt) if model.jnt_type[j] == free]
    start = data.xpos[bodies].copy()
    t0 = time.perf_counter()
    for _ in range(int(round(seconds / model.opt.timestep))):
        mujoco.mj_step(model, data)
    group.sim_s.append(time.perf_counter() - t0)
    moved = np.linalg.norm(data.xpos[bodies] - start, axis=1)
    moved[~np.isfinite(moved)] = np.inf
    group.scenes += 1
    group.objects += len(scene.objects)
    group.free += len(bodies)
    group.still += int((moved < STILL_M).sum())
    for b, d in zip(bodies, moved):
        if d >= STILL_M:
            group.moved.append(f"{label}: {model.body(b).name} ({100 * d:.1f} cm)")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", type=int, default=20, help="fit scenes per room type")
    ap.add_argument("--beyond", type=int, default=5, help="dense beyond bedrooms")
    ap.add_argument("--seconds", type=float, default=2.0, help="simulated time")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()

    from pair2scene import Pair2Scene
    from pair2scene.io import mjcf

    p2s = Pair2Scene.from_pretrained()
    jobs = [(room, room, seed, {}) for room in FIT_ROOMS for seed in range(args.scenes)]
    beyond = f"beyond bedroom ({BEYOND_OBJECTS} objects)"
    jobs += [
        (beyond, "bedroom", seed, {"mode": "beyond", "max_objects": BEYOND_OBJECTS})
        for seed in range(args.beyond)
    ]
    groups: dict[str, Group] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, room, seed, kw in jobs:
            r = p2s.generate(room=room, seed=seed, **kw)
            g = groups.setdefault(name, Group(name))
            measure(r.scene, r.assets, args.seconds, Path(tmp), f"{room}/{seed}", g)
            print(
                f"{name} {seed}: {len(r.scene.objects)} objects, free still "
                f"{g.still}/{g.free}, deepest {1000 * g.deepest_m:.2f} mm",
                file=sys.stderr,
            )
    total = Group("all")
    for g in groups.values():
        total.add(g)

    cmd = "python benchmarks/sim_exports.py"
    if (args.scenes, args.beyond, args.seconds) != (20, 5, 2.0):
        cmd += f" --scenes {args.scenes} --beyond {args.beyond} --seconds {args.seconds:g}"
    lines = [
        SECTION,
        "",
        f"`{cmd}` on {machine()}, {dt.date.today().isoformat()}. MuJoCo export "
        '(`pair2scene.io.mjcf.write_mjcf`, `dynamic="small"`: small objects free, '
        "furniture, fixtures and wall objects fixed), loaded back with "
        "`mujoco.MjModel.from_xml_path` from another working directory; deepest initial "
        f"penetration from `mj_forward`'s contacts; {args.seconds:g} s simulated under "
        f"gravity; a free object stays put if its box centre moved less than "
        f"{100 * STILL_M:g} cm (target >= {100 * TARGET_SHARE:g} %). Settings: "
        f"timestep {1000 * mjcf.TIMESTEP_S:g} ms, {mjcf.INTEGRATOR}, {mjcf.CONE} cones, "
        f"impratio {mjcf.IMPRATIO:g}, solref {mjcf.CONTACT_SOLREF}, solimp "
        f"{mjcf.CONTACT_SOLIMP[:2]}, condim {mjcf.CONDIM_DYNAMIC} on free objects.",
        "",
        "| rooms | scenes | objects | free objects | stayed put | deepest initial "
        "penetration | MJCF export per scene (median / max) | wall time to simulate "
        f"{args.seconds:g} s (median) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for g in [*groups.values(), total]:
        share = g.still / g.free if g.free else 1.0
        name = "**all**" if g is total else g.name.replace("_", " ")
        lines.append(
            f"| {name} | {g.scenes} | {g.objects} | {g.free} | "
            f"{g.still} ({100 * share:.1f} %) | {1000 * g.deepest_m:.2f} mm | "
            f"{statistics.median(g.export_s):.2f} s / {max(g.export_s):.2f} s | "
            f"{statistics.median(g.sim_s):.2f} s |"
        )
    lines.append("")
    if total.moved:
        lines.append("Free objects that moved 2 cm or more: " + "; ".join(total.moved) + ".")
    else:
        lines.append("No free object moved 2 cm or more.")
    share = total.still / total.free if total.free else 1.0
    text = "\n".join(lines)
    print(text)
    if not args.no_write:
        replace_section(DOC, SECTION, text)
        print(f"wrote {DOC.relative_to(ROOT)} ({SECTION})", file=sys.stderr)
    return 0 if share >= TARGET_SHARE else 1


if __name__ == "__main__":
    sys.exit(main())
