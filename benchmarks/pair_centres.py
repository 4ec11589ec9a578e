"""Does the layout model place each dependent on a support where the data does?

Run from the repository root::

    python benchmarks/pair_centres.py --data PAIRS [--model CHECKPOINT]
        [--support bed] [--dependent pillow --dependent book ...] [--split train]

For the ``--split`` tuples whose support is ``--support`` (in the support's frame, one
unit = half the support's size), per dependent category: how many there are, the median
of their stored centre (x across the support, y along it; +y is the support's front), the
median of the model's mixture mean for the same tuples (``sum_k w_k loc_k``, the
mixture's own weights for each tuple), and that median again with the dependent's
category swapped for each other listed one (geometry and size unchanged): a model that
uses what it places moves with the category. Last, how much the head's input (the
dependent's tokens after the last block) varies among these tuples against its norm.
Prints markdown tables. docs/model.md ("The pair table") quotes it, before and after
the table.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, required=True)
    ap.add_argument("--model", type=Path, default=None)
    ap.add_argument("--support", default="bed")
    ap.add_argument("--dependent", action="append", default=None)
    ap.add_argument("--split", default="train")
    args = ap.parse_args()
    dependents = args.dependent or ["pillow", "book", "laptop"]

    import numpy as np
    import torch

    from pair2scene.model import from_pretrained
    from pair2scene.model.api import CloudInputs
    from pair2scene.model.features import (
        build_clouds,
        category_index,
        dataset_features,
        encode_clouds,
    )
    from pair2scene.model.scoring import split_of

    data = split_of(args.data, args.split)
    names = np.asarray(data.categories)
    dep, sup = names[data.dependent.category], names[data.support.category]
    rows = np.flatnonzero((sup == args.support) & np.isin(dep, dependents))
    if len(rows) == 0:
        print(f"no {args.split} tuples of {', '.join(dependents)} on a {args.support}")
        return 2
    model = from_pretrained(args.model)
    feats = dataset_features(data, model.variant, anchor_frames=model.draws_in_frames)
    inputs = CloudInputs()
    if model.checkpoint.config.uses_points:
        tokens, centers = encode_clouds(model.encoder, build_clouds(feats.clouds, model.n_points))
        inputs = CloudInputs(tokens=tokens, centers=centers)
    net = model.predictor.eval()
    seen: dict[str, torch.Tensor] = {}
    hook = net.head.register_forward_hook(lambda m, i, o: seen.__setitem__("h", i[0]))

    def mean_centre(batch) -> np.ndarray:
        params, _ = net(batch)
        w = torch.softmax(params.logits, -1)[..., None]
        return (w * params.loc[..., :2]).sum(-2).numpy()  # (B, 2) x, y

    with torch.no_grad():
        batch = inputs.batch(feats.arrays, rows)
        own = mean_centre(batch)
        head_in = seen["h"].clone()
        swapped = {}
        for name in dependents:
            cats = batch.categories.clone()
            cats[:, 0] = category_index(name)
            swapped[name] = mean_centre(dataclasses.replace(batch, categories=cats))
    hook.remove()
    target = batch.target[:, :2].numpy()

    print(f"{args.split} tuples on a {args.support}: centre medians (x, y) in half sizes\n")
    cols = " | ".join(f"model as {n}" for n in dependents)
    print(f"| dependent | n | data x | data y | model x | model y | {cols} (y) |")
    print("|---|---|---|---|---|---|" + "---|" * len(dependents))
    d = dep[rows]
    for name in dependents:
        sel = d == name
        if not sel.any():
            continue
        med = np.median
        cells = " | ".join(f"{med(swapped[n][sel, 1]):+.2f}" for n in dependents)
        print(
            f"| {name} | {sel.sum()} | {med(target[sel, 0]):+.2f} | {med(target[sel, 1]):+.2f} "
            f"| {med(own[sel, 0]):+.2f} | {med(own[sel, 1]):+.2f} | {cells} |"
        )
    dist = torch.cdist(head_in, head_in)
    print(
        f"\nhead input: norm {float(head_in.norm(dim=1).mean()):.2f}, mean distance between "
        f"two of these tuples {float(dist.mean()):.2f}"
    )
    for a in dependents:
        for b in dependents:
            sa, sb = torch.from_numpy(d == a), torch.from_numpy(d == b)
            if a <= b and sa.any() and sb.any():
                print(f"  {a} - {b}: {float(dist[sa][:, sb].mean()):.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
