"""Layout-model benchmark: training cost of the ``cpu`` preset and inference per tuple.

Run from the repository root::

    python benchmarks/model.py [--checkpoint DIR] [--runs 20] [--steps 30] [--no-write]

Prints its figures and writes them, with the machine they were taken on, into
``docs/benchmarks.md`` under ``## Layout model`` (that section only).

- training step: one AdamW step of the ``cpu`` preset (``full``, batch 64, cached point
  tokens, 10 % functional anchors as in the corpus), forward + backward, median of
  ``--steps`` steps after 3 warm-up steps; peak memory of the process after them.
- full training run: read from the checkpoint's config.json (``pair2scene train`` writes
  the summed epoch times, the whole command's wall time and its peak RSS there).
- inference per tuple: :meth:`LayoutModel.sample` of 256 candidates for one tuple (a mug
  on a desk), one forward pass each; *warm*: the anchors' and the dependent's clouds are
  already encoded (what assembly sees after its first object of an asset); *cold*: the
  token cache is cleared first, so three clouds are built and encoded. Median of
  ``--runs``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from _docs import machine, replace_section

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "benchmarks.md"
SECTION = "## Layout model"


def bench_step(steps: int) -> dict:
    import torch

    from pair2scene.model.layout import LayoutBatch, LayoutPredictor
    from pair2scene.model.presets import preset
    from pair2scene.model.train import peak_rss_mb

    p = preset("cpu")
    g = torch.Generator().manual_seed(0)
    model = LayoutPredictor(p.layout, None, g)
    opt = torch.optim.AdamW([q for q in model.parameters() if q.requires_grad], lr=1e-4)
    b, enc = p.batch_size, p.encoder
    mask = torch.ones(b, 3, dtype=torch.bool)
    mask[:, 2] = torch.rand(b, generator=g) < 0.1
    batch = LayoutBatch(
        categories=torch.randint(0, 100, (b, 3), generator=g),
        scales=torch.rand(b, 3, 3, generator=g) + 0.1,
        anchor_boxes=torch.randn(b, 2, 12, generator=g),
        member_mask=mask,
        point_tokens=torch.randn(b, 3, enc.n_groups, enc.width, generator=g),
        point_centers=torch.randn(b, 3, enc.n_groups, 3, generator=g),
        target=torch.randn(b, 12, generator=g),
    )
    times = []
    for i in range(steps + 3):
        t0 = time.perf_counter()
        _, loss = model(batch)
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()
        if i >= 3:
            times.append(time.perf_counter() - t0)
    return {
        "step_ms": 1000 * statistics.median(times),
        "params": model.num_parameters(),
        "peak_rss_mb": peak_rss_mb(),
        "batch": b,
    }


def bench_inference(checkpoint: Path | None, runs: int) -> dict:
    import torch

    from pair2scene.model import from_pretrained
    from pair2scene.model.api import Anchor, PlacementQuery, _procedural_cloud
    from pair2scene.scene.geometry import OrientedBox

    model = from_pretrained(checkpoint)
    desk = OrientedBox.from_yaw([2.0, 2.0, 0.375], [1.2, 0.6, 0.75], 0.0)
    room = OrientedBox.from_yaw([2.5, 2.0, 1.25], [5.0, 4.0, 2.5])
    dep_cloud = _procedural_cloud("mug", [0.1, 0.1, 0.1], model.n_points)
    desk_cloud = _procedural_cloud("desk", desk.size, model.n_points)
    query = PlacementQuery("mug", [0.1, 0.1, 0.1], Anchor("desk", desk, cloud=desk_cloud),
                           room=room, cloud=dep_cloud)  # fmt: skip
    g = torch.Generator().manual_seed(0)
    model.sample(query, n=256, generator=g)  # warm-up
    warm, cold = [], []
    for _ in range(runs):
        t0 = time.perf_counter()
        model.sample(query, n=256, generator=g)
        warm.append(time.perf_counter() - t0)
    cold_query = PlacementQuery("mug", [0.1, 0.1, 0.1], Anchor("desk", desk), room=room)
    for _ in range(runs):
        model._tokens.clear()
        t0 = time.perf_counter()
        model.sample(cold_query, n=256, generator=g)
        cold.append(time.perf_counter() - t0)
    return {
        "warm_ms": 1000 * statistics.median(warm),
        "cold_ms": 1000 * statistics.median(cold),
        "variant": model.variant.value,
        "checkpoint": str(checkpoint) if checkpoint else "bundled default",
    }


def training_record(checkpoint: Path | None) -> dict | None:
    from pair2scene.model.checkpoint import DEFAULT_DIR

    folder = checkpoint or DEFAULT_DIR
    try:
        doc = json.loads((folder / "config.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return doc.get("training")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--checkpoint", type=Path, default=None, help="default: the bundled model")
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--steps", type=int, default=30)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()

    step = bench_step(args.steps)
    inf = bench_inference(args.checkpoint, args.runs)
    rec = training_record(args.checkpoint)
    print(json.dumps({"step": step, "inference": inf, "training": rec and {
        k: rec.get(k) for k in ("train_seconds", "wall_seconds", "peak_rss_mb", "epochs",
                                "steps", "val_nll", "best_epoch")}}, indent=1))  # fmt: skip
    if args.no_write:
        return 0
    lines = [
        SECTION,
        "",
        f"`python benchmarks/model.py` on {machine()}, {dt.date.today().isoformat()}.",
        "",
        "| what | figure |",
        "|---|---|",
        f"| `cpu` preset training step (batch {step['batch']}, cached point tokens, "
        f"fwd + bwd + AdamW; median of {args.steps}) | {step['step_ms']:.0f} ms |",
        f"| predictor parameters (`cpu`) | {step['params'] / 1e6:.2f} M |",
    ]
    if rec:
        epochs = len(rec.get("history", []))
        lines += [
            f"| full `pair2scene train` of the bundled model ({epochs} epochs, "
            f"{rec.get('steps')} steps), epochs only | "
            f"{rec.get('train_seconds', 0) / 60:.1f} min |",
            f"| the same, whole command (clouds, encoding, validation, checkpoints) | "
            f"{(rec.get('wall_seconds') or 0) / 60:.1f} min |",
            f"| peak memory of that run (RSS) | {(rec.get('peak_rss_mb') or 0) / 1024:.2f} GB |",
        ]
    lines += [
        f"| inference per tuple, warm (one forward + 256 samples; median of {args.runs}) "
        f"| {inf['warm_ms']:.1f} ms |",
        f"| inference per tuple, cold (3 clouds built and encoded first) "
        f"| {inf['cold_ms']:.1f} ms |",
        "",
        f"Inference ran on {inf['checkpoint']} (`{inf['variant']}`). Timings on a shared "
        "2-core machine vary by about 10 %.",
    ]
    replace_section(DOC, SECTION, "\n".join(lines))
    print(f"wrote {DOC.relative_to(ROOT)} ({SECTION})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    np.seterr(all="ignore")
    sys.exit(main())
