"""Scene classification accuracy (SCA): can a small CNN tell generated top views from real?

0.5 is ideal (indistinguishable), 1.0 means the two are told apart trivially. Unlike
FID it needs no pretrained network, and it looks at the very pixels the top views
hold (layout and category colours), which ImageNet features may not weigh.

Protocol (fixed, so numbers are comparable between runs and methods):

1. Balance: n = min(#real, #generated) images of each class; the larger set is
   subsampled without replacement by ``seed``.
2. Downsample to 64x64 by area averaging, scale to [-1, 1].
3. Stratified k-fold (k = 5) cross-validation: the reference sets can be as small as
   ~30 images a class, where a single 80/20 split tests on a dozen images. From
   ``full_cv_below`` images a class on, only the first fold runs: an 80/20 split.
4. Per fold a fresh CNN (4 conv 3x3 + BN + ReLU, max-pool after the first three,
   global average pool, linear; the first conv has stride 2), Adam (lr 1e-3),
   ``epochs`` epochs of mini-batches of 16.
   Training batches get random 90-degree rotations and mirror flips: both classes
   get them alike, so they teach only that a room's orientation in the image is
   arbitrary (which also makes SCA blind to a global orientation bias).
5. Repeat steps 1, 3 and 4 ``repeats`` times (default 5), each repeat with its own
   subsample of the larger set, its own folds and its own initial weights (repeated
   k-fold cross-validation), and report the test accuracy averaged over every fold of
   every repeat, and the spread of the repeats' accuracies. On 30 generated against 38
   real living rooms one 5-fold run's accuracy moved by a standard deviation of 0.04-0.05
   with the seed alone (0.53-0.72 over 8 seeds, the same images); the mean of 5 repeats
   moves by about 0.02.

Weights are seeded from ``seed`` and the fold inside :func:`torch.random.fork_rng`
(the caller's global RNG is untouched); shuffling and augmentation use a
``torch.Generator``: the same inputs, seed and thread count give the same accuracy.
"""

from __future__ import annotations

import numpy as np

from pair2scene.errors import UserError

SIDE = 64
FOLDS = 5
REPEATS = 5
"""Repeats of the k-fold cross-validation (step 5 of the protocol)."""
MAX_REPEATS = 100
"""Most repeats a caller may ask for (each trains ``folds`` networks)."""


def _prepare(images, what: str):
    """uint8 (N, H, W, 3) -> float32 (N, 3, 64, 64) in [-1, 1]."""
    import torch
    import torch.nn.functional as F

    images = np.asarray(images)
    if images.ndim != 4 or images.shape[-1] != 3 or images.dtype != np.uint8:
        raise UserError(
            f"SCA {what} images must be a uint8 (N, H, W, 3) array, "
            f"got {images.dtype} {images.shape}"
        )
    x = torch.from_numpy(np.ascontiguousarray(images)).permute(0, 3, 1, 2).float()
    if x.shape[-2:] != (SIDE, SIDE):
        x = F.interpolate(x, size=(SIDE, SIDE), mode="area")
    return x / 127.5 - 1.0


def _network():
    """A small CNN: the first conv strides (64 -> 32) to keep CPU training at seconds."""
    from torch import nn

    def block(cin: int, cout: int, stride: int = 1, pool: bool = True) -> list:
        conv = nn.Conv2d(cin, cout, 3, stride=stride, padding=1, bias=False)
        layers = [conv, nn.BatchNorm2d(cout), nn.ReLU()]
        return layers + [nn.MaxPool2d(2)] if pool else layers

    return nn.Sequential(
        *block(3, 16, stride=2),
        *block(16, 32),
        *block(32, 64),
        *block(64, 64, pool=False),
        nn.AdaptiveAvgPool2d(1),
        nn.Flatten(),
        nn.Linear(64, 1),
    )


def _augment(x, gen):
    """Each image turned by a random multiple of 90 degrees, half of them mirrored."""
    import torch

    variants = [torch.rot90(x, k, dims=(2, 3)) for k in range(4)]
    variants = torch.stack(variants + [torch.flip(v, dims=(3,)) for v in variants])
    pick = torch.randint(0, 8, (len(x),), generator=gen)
    return variants[pick, torch.arange(len(x))]


def _fit_and_test(x_train, y_train, x_test, y_test, seed, epochs, batch_size, lr) -> float:
    import torch

    fast = torch.channels_last  # ~1.5x faster convolutions on CPU
    with torch.random.fork_rng(devices=[]):
        torch.manual_seed(seed)
        net = _network().to(memory_format=fast)
    gen = torch.Generator().manual_seed(seed)
    opt = torch.optim.Adam(net.parameters(), lr=lr)
    loss_fn = torch.nn.BCEWithLogitsLoss()
    net.train()
    for _ in range(epochs):
        order = torch.randperm(len(x_train), generator=gen)
        for start in range(0, len(order), batch_size):
            idx = order[start : start + batch_size]
            if len(idx) < 2:  # BatchNorm needs two samples to normalise
                continue
            opt.zero_grad()
            batch = _augment(x_train[idx], gen).contiguous(memory_format=fast)
            loss = loss_fn(net(batch).squeeze(1), y_train[idx])
            loss.backward()
            opt.step()
    net.eval()
    with torch.inference_mode():
        pred = net(x_test.contiguous(memory_format=fast)).squeeze(1) > 0
    return float((pred == (y_test > 0.5)).float().mean())


def sca(
    real_images,
    generated_images,
    seed: int = 0,
    epochs: int = 20,
    folds: int = FOLDS,
    full_cv_below: int = 500,
    batch_size: int = 16,
    lr: float = 1e-3,
    threads: int | None = 1,
    repeats: int = REPEATS,
) -> dict:
    """Accuracy of a CNN telling real from generated top views; see the module docstring.

    Returns ``accuracy`` (mean test accuracy over every fold run), ``std`` (the spread of
    the repeats' mean accuracies; of the folds' when there is one repeat), ``folds`` (how
    many ran per repeat), ``repeats``, ``n_per_class``, and ``n_train`` / ``n_test``
    (images of both classes in one fold). The first repeat is the protocol's single
    k-fold run of ``seed`` (``repeats=1`` gives it alone). ``threads``: torch's CPU
    threads while training (restored after); the net is too small to gain from more, and
    on busy cores OpenMP threads mostly wait for each other (10x slower seen). None
    leaves the setting alone. Results can differ in the last digit between settings.
    """
    import torch

    if folds < 2:
        raise UserError(f"SCA needs at least 2 folds, got {folds}")
    if not 1 <= repeats <= MAX_REPEATS:
        raise UserError(f"SCA repeats must be 1 .. {MAX_REPEATS}, got {repeats}")
    real_all = _prepare(real_images, "real")
    fake_all = _prepare(generated_images, "generated")
    n = min(len(real_all), len(fake_all))
    if n < folds:
        raise UserError(
            f"SCA needs at least {folds} images of each class, "
            f"got {len(real_all)} real and {len(fake_all)} generated"
        )
    runs = folds if n < full_cv_below else 1
    repeats = repeats if n < full_cv_below else 1  # (a large set's one split is enough)
    per_repeat, n_train, n_test = [], 0, 0
    before = torch.get_num_threads()
    if threads is not None:
        torch.set_num_threads(threads)
    try:
        for r in range(repeats):
            rng = np.random.default_rng(seed if r == 0 else [seed, r])
            real = real_all[np.sort(rng.choice(len(real_all), n, replace=False))]
            fake = fake_all[np.sort(rng.choice(len(fake_all), n, replace=False))]
            # stratified folds: each class's images shuffled, then cut into k chunks
            chunks = [np.array_split(rng.permutation(n), folds) for _ in range(2)]
            x_all = torch.cat([real, fake])
            y_all = torch.cat([torch.ones(n), torch.zeros(n)])
            accuracies = []
            for k in range(runs):
                test = np.concatenate([chunks[0][k], n + chunks[1][k]])
                train = np.setdiff1d(np.arange(2 * n), test)
                n_train, n_test = len(train), len(test)
                acc = _fit_and_test(
                    x_all[train],
                    y_all[train],
                    x_all[test],
                    y_all[test],
                    seed=(seed * 1000 + k) if r == 0 else int(rng.integers(2**31)),
                    epochs=epochs,
                    batch_size=batch_size,
                    lr=lr,
                )
                accuracies.append(acc)
            per_repeat.append(accuracies)
    finally:
        torch.set_num_threads(before)
    means = [float(np.mean(a)) for a in per_repeat]
    return {
        "accuracy": float(np.mean(per_repeat)),
        "std": float(np.std(means) if repeats > 1 else np.std(per_repeat[0])),
        "folds": runs,
        "repeats": repeats,
        "n_per_class": n,
        "n_train": n_train,
        "n_test": n_test,
    }
