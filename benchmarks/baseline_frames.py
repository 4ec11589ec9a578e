"""The Gaussian baseline with and without anchor frames (issue 18), on one 3D-Pairs folder.

Run from the repository root::

    python benchmarks/baseline_frames.py --data PAIRS [--split val] [--json]
        [--model NAME=CHECKPOINT ...]

Fits :class:`~pair2scene.model.baseline.GaussianBaseline` on the train split of ``PAIRS``
twice (``anchor_frames`` True and False, everything else default) and scores the
``--split`` tuples as :func:`pair2scene.model.scoring.score` does: the mean NLL (nats per
tuple) of the stored canonical box and the NLL given its size (``log p - log p_size``),
overall, per relation kind and per frame kind (the frame the learned model predicts a
tuple in: support, wall, functional; the same tuples for both fits). Prints a markdown
table (``--json``: the rows as JSON). Each ``--model`` (a learned checkpoint) is scored on
the same groups, for a second table: NLL given size of the Gaussian in anchor frames next
to the learned models (how docs/model.md decides the frames).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, required=True)
    ap.add_argument("--split", default="val")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--model", action="append", default=[], help="NAME=CHECKPOINT_DIR")
    args = ap.parse_args()

    import numpy as np

    from pair2scene.curation.dataset import load_pairs
    from pair2scene.model.baseline import (
        FRAME_NAMES,
        GaussianBaseline,
        GaussianConfig,
        tuple_frames,
    )
    from pair2scene.model.scoring import score, split_of

    data = load_pairs(args.data)
    subset = split_of(data, args.split)
    relation = np.array([subset.kinds[k] for k in subset.kind.tolist()], dtype=object)
    frames = np.array([FRAME_NAMES[k] for k in tuple_frames(subset)[0].tolist()], dtype=object)
    groups = [("all", np.ones(len(subset), bool))]
    groups += [(f"kind {k}", relation == k) for k in sorted(set(relation.tolist()))]
    groups += [(f"frame {f}", frames == f) for f in FRAME_NAMES if (frames == f).any()]

    rows = []
    for anchor_frames in (False, True):
        t0 = time.perf_counter()
        model = GaussianBaseline.fit(data, "train", GaussianConfig(anchor_frames=anchor_frames))
        fit_s = time.perf_counter() - t0
        lp, lps = model.log_prob(subset), model.log_prob_size(subset)
        result = score(model, subset, None)  # the harness's numbers, as a cross-check
        assert np.isclose(result.nll, -lp.mean()) and np.isclose(
            result.nll_given_size, -(lp - lps).mean()
        )
        for name, mask in groups:
            rows.append(
                {
                    "anchor_frames": anchor_frames,
                    "group": name,
                    "n": int(mask.sum()),
                    "nll": float(-lp[mask].mean()),
                    "median": float(np.median(-lp[mask])),
                    "given_size": float(-(lp - lps)[mask].mean()),
                    "size": float(-lps[mask].mean()),
                    "fit_seconds": round(fit_s, 1),
                    "levels": model.level_counts(subset) if name == "all" else None,
                }
            )
        print(json.dumps(rows[-len(groups)]), file=sys.stderr)
    learned = {}
    for spec in args.model:
        from pair2scene.model.api import LayoutModel

        name, _, path = spec.partition("=")
        m = LayoutModel.from_pretrained(path)
        lp, lps = m.log_prob(subset), m.log_prob_size(subset)
        learned[name] = {g: (float(-lp[k].mean()), float(-(lp - lps)[k].mean()))
                         for g, k in groups}  # fmt: skip
    if args.json:
        print(json.dumps({"gaussian": rows, "learned": learned}, indent=1))
        return 0
    by = {(r["anchor_frames"], r["group"]): r for r in rows}
    print(f"Gaussian baseline on {args.data} ({args.split}), nats per tuple, lower is better\n")
    print("| tuples | n | NLL off | NLL on | given size off | given size on | size off | size on |")
    print("|---|---|---|---|---|---|---|---|")
    for name, _ in groups:
        off, on = by[(False, name)], by[(True, name)]
        print(
            f"| {name} | {on['n']} | {off['nll']:.2f} | {on['nll']:.2f} | "
            f"{off['given_size']:.2f} | {on['given_size']:.2f} | "
            f"{off['size']:.2f} | {on['size']:.2f} |"
        )
    if learned:
        names = list(learned)
        print("\n| tuples | n | Gaussian (frames) | " + " | ".join(names) + " |")
        print("|---|---|---|" + "---|" * len(names))
        print("| NLL given size |  |  |" + " |" * len(names))
        for name, _ in groups:
            on = by[(True, name)]
            cells = " | ".join(f"{learned[m][name][1]:.2f}" for m in names)
            print(f"| {name} | {on['n']} | {on['given_size']:.2f} | {cells} |")
    for flag in (False, True):
        r = by[(flag, "all")]
        print(f"\nanchor_frames={flag}: fit {r['fit_seconds']} s, levels {r['levels']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
