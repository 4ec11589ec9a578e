"""Where the learned model loses to the Gaussian on objects resting on furniture.

Run from the repository root::

    python benchmarks/support_nats.py --data PAIRS [--model CHECKPOINT] [--split val]

On the ``--split`` tuples that rest on furniture and are modelled in their support's
frame (every such tuple: anchor frames change only floor tuples), splits the NLL given
the size, for the learned model (the bundled one, or ``--model``) and the per-pair
Gaussian in anchor frames (fitted on the train split), into

- centre | size: ``log p(centre, size) - log p(size)``;
- rotation | centre, size: ``log p(all) - log p(centre, size)``;

and gives each 6D rotation dimension's marginal NLL (nats per tuple; the learned
model's dims 9 and 10 are those of its upright-rotation base, second column minus
``e_z x`` the first). Both models' marginals are exact: the learned mixture is diagonal,
and so is the Gaussian's default. In the support's frame the stored vector's Jacobian has
no rotation part, so the centre part of the learned model's Jacobian is its full one
less the size part. Prints a markdown table.
"""

from __future__ import annotations

import argparse
from pathlib import Path


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, required=True)
    ap.add_argument("--model", type=Path, default=None)
    ap.add_argument("--split", default="val")
    args = ap.parse_args()

    import numpy as np
    import torch

    from pair2scene.curation.dataset import load_pairs
    from pair2scene.curation.frames import FRAME_SUPPORT
    from pair2scene.model import from_pretrained
    from pair2scene.model.api import CloudInputs
    from pair2scene.model.baseline import GaussianBaseline
    from pair2scene.model.features import build_clouds, dataset_features, encode_clouds
    from pair2scene.model.mixture import MixtureParams, log_prob
    from pair2scene.model.scoring import split_of
    from pair2scene.scene.model import FLOOR

    data = load_pairs(args.data)
    subset = split_of(data, args.split)
    model = from_pretrained(args.model)
    feats = dataset_features(subset, model.variant, anchor_frames=model.draws_in_frames)
    arrays = feats.arrays
    inputs = CloudInputs()
    if model.checkpoint.config.uses_points:
        tokens, centers = encode_clouds(model.encoder, build_clouds(feats.clouds, model.n_points))
        inputs = CloudInputs(tokens=tokens, centers=centers)
    groups = {"all": slice(0, 12), "centre_size": slice(0, 6), "size": slice(3, 6)}
    groups.update({f"dim {d}": slice(d, d + 1) for d in range(6, 12)})
    learned = {k: np.zeros(len(arrays)) for k in groups}
    predictor = model.predictor.eval()
    with torch.no_grad():
        for start in range(0, len(arrays), 256):
            rows = np.arange(start, min(start + 256, len(arrays)))
            batch = inputs.batch(arrays, rows)
            params, _ = predictor(batch)
            y = predictor.to_mixture_space(batch.target)
            for key, dims in groups.items():
                marginal = MixtureParams(params.logits, params.loc[..., dims],
                                         params.log_scale[..., dims])  # fmt: skip
                learned[key][rows] = log_prob(marginal, y[:, dims]).double().numpy()
    frames = arrays.frames if arrays.frames is not None else np.zeros(len(arrays), int)
    rows = np.flatnonzero((frames == FRAME_SUPPORT) & (subset.support.id != FLOOR))
    centre_jac = arrays.log_jacobian - arrays.size_log_jacobian

    gauss = GaussianBaseline.fit(data, "train")
    framed = gauss.framed(subset)

    def g(dims):
        return gauss.log_prob_arrays(framed.x, framed.dependent, framed.support,
                                     framed.functional, dims=dims)  # fmt: skip

    g_all, g_cs, g_s = g(None), g(list(range(6))), g([3, 4, 5])
    table = [
        ("given size", learned["all"] - learned["size"] + centre_jac, g_all - g_s),
        ("centre given size", learned["centre_size"] - learned["size"] + centre_jac, g_cs - g_s),
        ("rotation given centre and size", learned["all"] - learned["centre_size"], g_all - g_cs),
    ]
    table += [(f"rotation dim {d}", learned[f"dim {d}"], g([d])) for d in range(6, 12)]
    print(f"{len(rows)} {args.split} tuples on furniture, in their support's frame\n")
    print("| NLL (nats per tuple) | learned | Gaussian (anchor frames) |")
    print("|---|---|---|")
    for name, lp_learned, lp_gauss in table:
        print(f"| {name} | {-lp_learned[rows].mean():.2f} | {-lp_gauss[rows].mean():.2f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
