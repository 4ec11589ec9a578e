"""A trained layout model, ready to score 3D-Pairs and to sample placements.

>>> from pair2scene.model import from_pretrained
>>> model = from_pretrained()                      # the bundled default (cpu preset, full)
>>> model.score("pairs/", split="val").nll         # mean NLL per tuple (nats)
>>> boxes = model.sample(query, n=256, temperature=0.8, generator=np.random.default_rng(0))

:meth:`LayoutModel.sample` takes a :class:`PlacementQuery` (the dependent's category and
size or asset, its support anchor and optional functional anchor as placed objects or the
floor) and returns ``n`` candidate boxes in world coordinates, drawn from one forward pass.

Sampling runs without torch: the checkpoint's weights go into numpy twins of the encoder
and the predictor (:mod:`~pair2scene.model.np_pointmae`, :mod:`~pair2scene.model.np_layout`,
equal to the torch networks to float32 rounding), so a generating process never imports
torch (3.4 s of every start on a 2-core machine) and a forward pass is a few dozen numpy
calls instead of torch operations at ~50 us each. Scoring (NLL of 3D-Pairs tuples) uses
the torch network, built from the same weights on first use.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Protocol, runtime_checkable

import numpy as np
from threadpoolctl import ThreadpoolController

from pair2scene.assets.mesh import Asset
from pair2scene.assets.pointcloud import cache_key
from pair2scene.curation.dataset import PairsDataset
from pair2scene.curation.frames import FRAME_FUNCTIONAL, FRAME_SUPPORT, frame_choice
from pair2scene.errors import UserError
from pair2scene.model.checkpoint import (
    Checkpoint,
    CheckpointState,
    read_checkpoint,
    torch_checkpoint,
)
from pair2scene.model.config import (
    BOX_DIM,
    FUNCTIONAL,
    SUPPORT,
    InvalidDistribution,
)
from pair2scene.model.config import LayoutVariant as Variant
from pair2scene.model.features import (
    CLOUD_SEED,
    TupleArrays,
    asset_cloud,
    box_of,
    build_clouds,
    category_index,
    dataset_features,
    encode_clouds,
    frame_factor,
    from_bearing,
    from_model_frame,
    room_cloud,
    to_model_frame,
    wall_cloud,
)
from pair2scene.model.np_layout import (
    MixtureArrays,
    NumpyPredictor,
    Window,
    condition,
    sample,
    window_log_mass,
)
from pair2scene.model.np_pointmae import NumpyPointMAE, encoder_state
from pair2scene.model.token_store import TokenStore, encoder_digest
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, WALL

if TYPE_CHECKING:
    from pair2scene.model.layout import LayoutPredictor

EVAL_BATCH = 256
"""Tuples per forward pass when scoring."""
TOKEN_CACHE_ENTRIES = 2048
"""Encoded clouds :class:`LayoutModel` keeps in memory, by cloud and by asset: more than the
asset library a room type draws from (1,551 observed sizes over every category), so a
process making rooms of one type soon encodes nothing (16 kB each)."""
FRAME_CLOUDS = 64
"""Floor and wall clouds kept in memory (24 kB each): a scene's room and walls."""


class CloudInputs:
    """The geometry batches draw from: cached encoder tokens, or raw clouds."""

    def __init__(self, tokens=None, centers=None, points=None) -> None:
        self.tokens, self.centers, self.points = tokens, centers, points

    def batch(self, arrays: TupleArrays, rows: np.ndarray, with_target: bool = True):
        return arrays.batch(rows, self.tokens, self.centers, self.points, with_target)


def stored_log_prob(
    model: LayoutPredictor,
    arrays: TupleArrays,
    inputs: CloudInputs,
    batch_size: int = EVAL_BATCH,
    with_size: bool = False,
):
    """(N,) float64 log density of each tuple's stored canonical vector under ``model``
    (the scoring contract of :mod:`pair2scene.model.scoring`); with ``with_size`` also the
    (N,) log marginal density of the stored size."""
    import torch

    from pair2scene.model.mixture import MixtureParams, log_prob

    was_training = model.training
    model.eval()
    out, size = np.zeros(len(arrays)), np.zeros(len(arrays))
    for s in range(0, len(arrays), batch_size):
        rows = np.arange(s, min(s + batch_size, len(arrays)))
        batch = inputs.batch(arrays, rows)
        with torch.no_grad():
            params, _ = model(batch)
        out[rows] = model.log_prob(params, batch.target).double().numpy()
        if with_size:
            marg = MixtureParams(params.logits, params.loc[..., 3:6], params.log_scale[..., 3:6])
            size[rows] = log_prob(marg, batch.target[:, 3:6]).double().numpy()
    model.train(was_training)
    if with_size:
        return out + arrays.log_jacobian, size + arrays.size_log_jacobian
    return out + arrays.log_jacobian


@dataclass(frozen=True)
class Anchor:
    """An anchor of a placement: a placed object, or the floor (the room)."""

    category: str
    box: OrientedBox
    """World box; for the floor, the room's bounds (z from 0 to the room's height)."""
    cloud: np.ndarray | None = None
    """(N, 3) normalised cloud (:func:`~pair2scene.model.features.asset_cloud`); None:
    built from ``asset``, or for the floor from the box."""
    asset: Asset | None = None

    @classmethod
    def floor(cls, room_bounds: OrientedBox) -> Anchor:
        return cls(FLOOR, room_bounds)

    @classmethod
    def wall(cls, frame: OrientedBox) -> Anchor:
        """A wall as the support of a mounted object; ``frame`` is the wall's frame
        (:meth:`~pair2scene.scene.walls.Wall.frame`)."""
        return cls(WALL, frame)

    @property
    def is_floor(self) -> bool:
        return self.category == FLOOR

    @property
    def is_wall(self) -> bool:
        return self.category == WALL


@dataclass(frozen=True)
class PlacementQuery:
    """What to place and relative to what."""

    category: str
    """The dependent's category."""
    size: Sequence[float]
    """(3,) the dependent's size (m): its asset's, chosen before placement."""
    support: Anchor
    functional: Anchor | None = None
    room: OrientedBox | None = None
    """The room's bounds; needed by ``global`` models when the support is not the floor."""
    asset: Asset | None = None
    """The dependent's asset (its cloud); None: ``cloud`` or a procedural one."""
    cloud: np.ndarray | None = None
    wall: OrientedBox | None = None
    """The frame (:meth:`~pair2scene.scene.walls.Wall.frame`) of the wall a floor object is
    to stand against: a model with anchor frames then draws in that wall's frame."""
    region: OrientedBox | None = None
    """A world box outside whose footprint a candidate's centre would be rejected whatever
    else (a floor object beyond its reach of the room): :meth:`LayoutModel.sample` then
    draws only over it, from its distribution restricted there, exactly; samplers that
    ignore it only waste those draws."""


@runtime_checkable
class PlacementModel(Protocol):
    """Where placement's candidates come from: the learned :class:`LayoutModel` and the
    baselines (:mod:`pair2scene.assembly.baselines`) answer the same call, so the placer
    runs every one of them through the same rejection sampling and gravity."""

    honours_temperature: bool
    """False for a sampler without modes to sharpen (the uniform baseline): the
    temperature then changes nothing, and generation says so in its notes."""
    draws_in_frames: bool
    """True when a query is drawn in its wall's or functional anchor's frame (anchor
    frames), so placement may hold the candidates to that wall and anchor
    (:class:`~pair2scene.assembly.anchors.AnchorRules`, ``off_wall``); False for the
    uniform baseline and models without anchor frames, whose draws those tests would
    nearly all reject."""

    def draw(
        self,
        query: PlacementQuery,
        n: int,
        temperature: float,
        generator: np.random.Generator | None,
    ) -> tuple[np.ndarray, float | None]:
        """``n`` candidate world boxes (n, 12) (centre, size, 6D) for one query, each of
        the query's size, and the model's probability of a candidate over
        ``query.region`` (None for a sampler that ignores the region: its draws beyond
        are simply rejected). Every random number comes from ``generator`` (None: a
        fresh, unseeded one)."""
        ...


class LayoutModel:
    """A loaded checkpoint with scoring and sampling; a :class:`PlacementModel`.

    Built from a checkpoint read without torch (:func:`read_checkpoint`; what
    :meth:`from_pretrained` does) or from a torch :class:`Checkpoint` (a network in memory,
    as training has it). Sampling always runs on the numpy twins of its weights; the torch
    network (:attr:`checkpoint`) is built when scoring first asks for it. ``token_store``:
    keep assets' encoder tokens under the cache folder for later processes
    (:attr:`token_store`); False: in memory only."""

    honours_temperature = True
    draws_in_frames = True
    """Whether this checkpoint has anchor frames (set per checkpoint when loaded)."""

    def __init__(
        self,
        checkpoint: Checkpoint | CheckpointState,
        device: str = "cpu",
        token_store: bool = True,
    ) -> None:
        self._device = device  # (where scoring builds the torch network from a read one)
        if isinstance(checkpoint, CheckpointState):
            self._read: CheckpointState | None = checkpoint
            self._checkpoint: Checkpoint | None = None
            spec = checkpoint.spec
            self.config, encoder = spec.layout, spec.encoder
            self._n_points, self.path = spec.n_points, checkpoint.path
            state = checkpoint.state
        else:
            self._read, self._checkpoint = None, checkpoint
            self.config, encoder = checkpoint.config, checkpoint.encoder_config
            self._n_points, self.path = checkpoint.n_points, checkpoint.path
            checkpoint.predictor.eval()
            state = {
                k: v.detach().cpu().float().numpy()
                for k, v in checkpoint.predictor.state_dict().items()
            }
        self.net = NumpyPredictor(self.config, state)
        self.point_net = (
            NumpyPointMAE(encoder, encoder_state(state)) if self.config.uses_points else None
        )
        self.draws_in_frames = self.config.uses_frames
        self._tokens: OrderedDict[bytes, tuple[np.ndarray, np.ndarray]] = OrderedDict()
        self._last_scores: tuple[PairsDataset, tuple[np.ndarray, np.ndarray]] | None = None
        self._asset_tokens: OrderedDict[int, tuple[Asset, tuple]] = OrderedDict()
        self._store: TokenStore | bool = token_store and self.point_net is not None
        self._computed = 0  # assets encoded, not read from the store
        self._state = state  # (hashed for the token store's folder when first needed)

    @classmethod
    def from_pretrained(cls, path: str | Path | None = None, device: str = "cpu") -> LayoutModel:
        """The checkpoint folder ``path``; None: the bundled default model. Read without
        torch; ``device`` is where the torch network goes when scoring builds it."""
        return cls(read_checkpoint(path), device)

    @property
    def checkpoint(self) -> Checkpoint:
        """The torch network and what config.json says (built on first use)."""
        if self._checkpoint is None:
            assert self._read is not None
            self._checkpoint = torch_checkpoint(self._read, self._device)
        return self._checkpoint

    @property
    def predictor(self) -> LayoutPredictor:
        """The torch predictor (eval mode), for scoring."""
        return self.checkpoint.predictor

    @property
    def variant(self) -> Variant:
        return self.config.variant

    @property
    def n_points(self) -> int:
        return self._n_points

    @property
    def encoder(self):
        """The torch point encoder, for scoring."""
        return self.predictor.point_encoder

    # -- scoring -----------------------------------------------------------------------

    def log_prob(self, data: PairsDataset, progress: bool = False) -> np.ndarray:
        """(N,) float64 log density of every tuple's stored canonical vector (the
        :class:`~pair2scene.model.scoring.Scorer` protocol)."""
        return self._scores(data, progress)[0]

    def log_prob_size(self, data: PairsDataset) -> np.ndarray:
        """(N,) float64 log marginal density of every tuple's stored canonical size."""
        return self._scores(data)[1]

    def _scores(self, data: PairsDataset, progress: bool = False):
        # Both densities come from one forward pass; the last dataset's are kept, since
        # scoring asks for one and then the other.
        if self._last_scores is not None and self._last_scores[0] is data:
            return self._last_scores[1]
        features = dataset_features(data, self.variant, anchor_frames=self.config.anchor_frames)
        inputs = CloudInputs()
        if self.config.uses_points:
            clouds = build_clouds(features.clouds, self.n_points, progress=progress)
            tokens, centers = encode_clouds(self.encoder, clouds, progress=progress)
            inputs = CloudInputs(tokens=tokens, centers=centers)
        result = stored_log_prob(self.predictor, features.arrays, inputs, with_size=True)
        self._last_scores = (data, result)
        return result

    def score(self, data, split: str | None = "val"):
        """:func:`pair2scene.model.scoring.score` of this model."""
        from pair2scene.model.scoring import score

        return score(self, data, split)

    # -- sampling ------------------------------------------------------------------------

    def _encode(self, cloud: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Tokens (G, D) and centres (G, 3) of one normalised cloud, cached by content.

        One cloud per encoder call, never batched with others: a BLAS may round a row of
        a product differently with the matrix's height, and a cloud's tokens must not
        depend on which clouds a process met before it (same seed, same scene, however
        many scenes a process made first). Batching would gain little: each cloud is
        already thousands of rows."""
        key = hashlib.sha1(np.ascontiguousarray(cloud, np.float32).tobytes()).digest()
        hit = self._tokens.get(key)
        if hit is not None:
            self._tokens.move_to_end(key)
            return hit
        with one_blas_thread():
            tokens, centers = self.point_net(np.asarray(cloud, np.float32)[None])
        hit = self._tokens[key] = (tokens[0], centers[0])
        if len(self._tokens) > TOKEN_CACHE_ENTRIES:
            self._tokens.popitem(last=False)
        return hit

    def _anchor_cloud(self, anchor: Anchor) -> np.ndarray | Asset:
        """An anchor's cloud, or its asset (:meth:`_asset_encoded` encodes it)."""
        if anchor.cloud is not None:
            return anchor.cloud
        if anchor.is_floor or anchor.is_wall:
            size = tuple(float(v) for v in anchor.box.size)
            return _frame_cloud(anchor.is_floor, size, self.n_points)
        if anchor.asset is not None:
            return anchor.asset
        return _procedural_cloud(anchor.category, anchor.box.size, self.n_points)

    @property
    def token_store(self) -> TokenStore | None:
        """Where assets' tokens are kept between processes
        (:mod:`~pair2scene.model.token_store`, under the cache folder); None: nowhere (the
        model was built with ``token_store=False``, or has no point encoder)."""
        if self._store is True:
            self._store = TokenStore(encoder_digest(encoder_state(self._state), self._n_points))
        return self._store or None

    def store_tokens(
        self, assets, progress: bool = False, total: int | None = None
    ) -> tuple[int, int]:
        """Encode ``assets`` (an iterable of :class:`Asset`, about ``total`` of them, for
        the progress bar) into :attr:`token_store`, those not there already: (assets, of
        them newly encoded). What ``pair2scene assets tokens`` does with the asset library,
        once, so that a machine's first rooms encode nothing."""
        from pair2scene.progress import track

        if self.token_store is None:
            raise UserError("this model keeps no tokens (no point encoder, or no store)")
        before, count = self._computed, 0
        for asset in track(assets, "encoding the asset library", progress, total):
            self._asset_encoded(asset)
            count += 1
        return count, self._computed - before

    def _asset_encoded(self, asset: Asset) -> tuple[np.ndarray, np.ndarray]:
        """Tokens and centres of an asset's cloud: kept in memory while the asset is,
        read from :attr:`token_store` when a process encoded it before, else encoded
        (:meth:`_encode`) and stored. The asset's cloud is only built to encode it."""
        hit = self._asset_tokens.get(id(asset))
        if hit is not None and hit[0] is asset:
            self._asset_tokens.move_to_end(id(asset))
            return hit[1]
        found = key = None
        store = self.token_store
        if store is not None:
            enc = self.point_net.config
            key = cache_key(asset, self.n_points, CLOUD_SEED)
            found = store.get(key, (enc.n_groups, enc.width))
        if found is None:
            found = self._encode(asset_cloud(asset, self.n_points))
            self._computed += 1
            if store is not None:
                store.put(key, *found)
        self._asset_tokens[id(asset)] = (asset, found)
        if len(self._asset_tokens) > TOKEN_CACHE_ENTRIES:
            self._asset_tokens.popitem(last=False)
        return found

    def frame(self, query: PlacementQuery) -> tuple[int, OrientedBox]:
        """(frame kind, frame box) ``query`` is drawn in: its governing anchor's frame
        (:func:`~pair2scene.curation.frames.frame_choice`) for a model with anchor frames,
        else its support's box."""
        sup = query.support
        if not self.draws_in_frames:
            return FRAME_SUPPORT, sup.box
        func = None if query.functional is None else query.functional.box
        return frame_choice(sup.box, sup.is_floor, query.wall, func)

    def _query_batch(self, queries: Sequence[PlacementQuery]) -> tuple[dict, np.ndarray]:
        """The network's inputs for ``queries`` (:meth:`NumpyPredictor.forward`'s keyword
        arguments) and each query's model-frame factor (B, 3)."""
        b = len(queries)
        is_global = self.variant is Variant.GLOBAL
        frame_kinds = np.zeros(b, dtype=np.int64)
        frame_sizes = np.ones((b, 3), np.float32)
        cats = np.zeros((b, 3), dtype=np.int64)
        scales = np.ones((b, 3, 3), np.float32)
        boxes = np.zeros((b, 2, BOX_DIM), np.float32)
        mask = np.zeros((b, 3), dtype=bool)
        factors = np.ones((b, 3))
        clouds: list[list[np.ndarray | Asset | None]] = []
        uses_points = self.config.uses_points
        for i, q in enumerate(queries):
            sup = q.support
            members: list[Anchor | None] = [None, sup, q.functional]
            if is_global:
                room = sup.box if sup.is_floor else q.room
                if room is None:
                    raise ValueError("a global model needs the room's bounds (query.room)")
                members = [None, Anchor.floor(room), None]
                boxes[i, 0] = room.to_vector()
            else:
                kind, frame = self.frame(q)
                factors[i] = frame_factor(frame.size)
                frame_kinds[i] = kind
                frame_sizes[i] = frame.size
                own = sup.box.in_frame_of(frame).to_vector()
                if kind == FRAME_SUPPORT:
                    own = np.array([0, 0, 0, 2, 2, 2, 1, 0, 0, 0, 1, 0], dtype=np.float64)
                boxes[i, 0] = to_model_frame(own, factors[i])
                if q.functional is not None:
                    rel = q.functional.box.in_frame_of(frame).to_vector()
                    boxes[i, 1] = to_model_frame(rel, factors[i])
            cats[i, 0] = category_index(q.category)
            scales[i, 0] = np.asarray(q.size, dtype=np.float32)
            mask[i, 0] = True
            row_clouds: list[np.ndarray | Asset | None] = [None, None, None]
            for m in (SUPPORT, FUNCTIONAL):
                a = members[m]
                if a is None:
                    continue
                cats[i, m] = category_index(a.category)
                scales[i, m] = a.box.size
                mask[i, m] = True
                if uses_points:
                    row_clouds[m] = self._anchor_cloud(a)
            if uses_points:
                if q.cloud is not None:
                    row_clouds[0] = q.cloud
                elif q.asset is not None:
                    row_clouds[0] = q.asset
                else:
                    row_clouds[0] = _procedural_cloud(q.category, q.size, self.n_points)
            clouds.append(row_clouds)
        inputs: dict = {
            "categories": cats, "scales": scales, "anchor_boxes": boxes, "member_mask": mask,
        }  # fmt: skip
        if self.draws_in_frames:
            inputs["frames"], inputs["frame_sizes"] = frame_kinds, frame_sizes
        if uses_points:
            enc = self.point_net.config
            tokens = np.zeros((b, 3, enc.n_groups, enc.width), np.float32)
            centers = np.zeros((b, 3, enc.n_groups, 3), np.float32)
            for i, row in enumerate(clouds):
                for m, cloud in enumerate(row):
                    if isinstance(cloud, Asset):
                        tokens[i, m], centers[i, m] = self._asset_encoded(cloud)
                    elif cloud is not None:
                        tokens[i, m], centers[i, m] = self._encode(cloud)
            inputs["point_tokens"], inputs["point_centers"] = tokens, centers
        return inputs, factors

    def distribution(self, queries: Sequence[PlacementQuery]) -> tuple[MixtureArrays, np.ndarray]:
        """One forward pass: the mixture over each query's model-frame target (float32
        arrays), and the model-frame factors (B, 3) that map its samples back (see
        :meth:`to_world`)."""
        inputs, factors = self._query_batch(queries)
        with one_blas_thread():
            return self.net.forward(**inputs), factors

    def to_world(self, samples: np.ndarray, query: PlacementQuery, factor: np.ndarray):
        """Model-frame samples (..., 12) of ``query`` -> world box vectors (..., 12)
        (centre, size, 6D; the 6D part orthonormalised)."""
        vec = box_of(samples)
        if self.variant is not Variant.GLOBAL:
            kind, frame = self.frame(query)
            canonical = from_model_frame(vec, factor)
            if kind == FRAME_FUNCTIONAL:
                canonical = from_bearing(canonical, frame.half_size)
            return canonical_to_world(canonical, frame)
        return _orthonormal_6d(vec)

    def sample(
        self,
        query: PlacementQuery,
        n: int = 256,
        temperature: float = 1.0,
        generator: np.random.Generator | None = None,
        keep_size: bool = True,
    ) -> np.ndarray:
        """``n`` candidate world boxes (n, 12) (centre, size, 6D) for one query.

        keep_size : condition the mixture on the query's size (exact for a diagonal
        mixture: the components are reweighted by how well they explain it), so every
        candidate has the asset's size; False samples the size too.
        """
        return self.draw(query, n, temperature, generator, keep_size)[0]

    def draw(
        self,
        query: PlacementQuery,
        n: int = 256,
        temperature: float = 1.0,
        generator: np.random.Generator | None = None,
        keep_size: bool = True,
    ) -> tuple[np.ndarray, float]:
        """:meth:`sample`'s candidates, and the probability that the model (at this
        temperature) puts a candidate's centre over ``query.region`` (1.0 without one):
        its draws are confined there (:class:`~pair2scene.model.np_layout.Window`), so
        ``1 - p`` is the share it would have spent where the placer rejects them. The
        draws come from ``generator`` (None: a fresh, unseeded one).

        A checkpoint whose distributions cannot be drawn from (finite but extreme
        weights) raises :class:`~pair2scene.model.mixture.InvalidDistribution`, a one-line
        :class:`~pair2scene.errors.UserError` naming its folder."""
        rng = np.random.default_rng() if generator is None else generator
        with np.errstate(over="ignore", invalid="ignore"):  # (check_params tells of those)
            params, factors = self.distribution([query])
            if keep_size:
                params = self.condition_on_size(params, [query], factors)
        try:
            window, mass = None, 1.0
            if query.region is not None and temperature > 0:
                window = self._window(query, factors[0], params.loc.dtype)
                mass = float(np.exp(window_log_mass(params, window, temperature)[0]))
            y = sample(params, n, temperature, rng, window)[0]  # (n, 12) mixture space
            x = self.net.from_mixture_space(y).astype(np.float64)
            with np.errstate(over="ignore", invalid="ignore"):
                boxes = self.to_world(x, query, factors[0])
            if not np.isfinite(boxes).all():
                raise InvalidDistribution("non-finite boxes")
        except InvalidDistribution as e:
            raise e.named(self.path or "the loaded checkpoint") from None
        return boxes, mass

    def _window(self, query: PlacementQuery, factor: np.ndarray, dtype) -> Window:
        """``query.region``'s footprint as bounds on the mixture's centre x and y: the
        interval its corners span in the support's model frame (the world's, ``global``),
        a box that holds it whatever the two frames' angle."""
        region = query.region
        corners = np.array([[sx, sy, 0.0] for sx in (-1, 1) for sy in (-1, 1)])
        world = (corners * region.half_size) @ region.rotation.T + region.center  # (4, 3)
        if self.variant is not Variant.GLOBAL:
            sup = self.frame(query)[1]
            local = (world - sup.center) @ sup.rotation / np.maximum(sup.half_size, 1e-9)
            world = local * factor
        low, high = world[:, :2].min(0), world[:, :2].max(0)
        return Window([0, 1], low[None].astype(dtype), high[None].astype(dtype))

    def condition_on_size(
        self, params: MixtureArrays, queries: Sequence[PlacementQuery], factors: np.ndarray
    ) -> MixtureArrays:
        """``params`` conditioned on each query's known size (in the model frame)."""
        sizes = np.stack([np.asarray(q.size, dtype=np.float64) for q in queries])  # (B, 3)
        if self.variant is not Variant.GLOBAL:
            half = np.stack([np.maximum(self.frame(q)[1].half_size, 1e-9) for q in queries])
            sizes = sizes / half * factors
        log_size = np.log(np.maximum(sizes, 1e-6)).astype(params.loc.dtype)
        return condition(params, [3, 4, 5], log_size)


_blas: ThreadpoolController | None = None


def one_blas_thread():
    """A context in which numpy's BLAS runs on one thread: the layout model's forward
    passes run in one, whatever the machine or ``--threads``. A BLAS splits a product's
    sums differently with its thread count (OpenBLAS: a (12, 128) @ (128, 384) product on
    one thread and on two differ in the last bit), which would make a scene's bytes
    depend on the machine's cores; a second thread gains ~5 % on these small products on
    an idle machine and loses far more on a busy one."""
    global _blas
    if _blas is None:  # (after numpy has loaded its BLAS, so that the controller sees it)
        _blas = ThreadpoolController().select(user_api="blas")
    if all(lib.num_threads == 1 for lib in _blas.lib_controllers):
        return contextlib.nullcontext()  # (as generation has it: set_threads' default)
    return _blas.limit(limits=1, user_api="blas")


@functools.lru_cache(maxsize=FRAME_CLOUDS)
def _frame_cloud(floor: bool, size: tuple[float, float, float], n: int) -> np.ndarray:
    """The cloud (read-only) of a room's floor (``floor``) or of a wall, of frame ``size``:
    a scene's queries on the floor or a wall ask for the same few, each many times."""
    cloud = room_cloud(size, n) if floor else wall_cloud(size, n)
    cloud.setflags(write=False)
    return cloud


def _procedural_cloud(category: str, size, n: int) -> np.ndarray:
    from pair2scene.assets.registry import generate

    asset = generate(category, np.asarray(size, dtype=float), np.random.default_rng(0))
    return asset_cloud(asset, n)


def canonical_to_world(canonical: np.ndarray, support: OrientedBox) -> np.ndarray:
    """Canonical box vectors (..., 12) in ``support``'s frame (as 3D-Pairs stores them,
    :meth:`OrientedBox.in_frame_of`) -> world vectors (..., 12), the 6D part
    orthonormalised."""
    x = np.asarray(canonical, dtype=np.float64)
    rot = support.rotation
    half = np.maximum(support.half_size, 1e-9)
    center = (x[..., 0:3] * half) @ rot.T + support.center
    size = x[..., 3:6] * half
    c0 = x[..., 6:9] @ rot.T
    c1 = x[..., 9:12] @ rot.T
    return _orthonormal_6d(np.concatenate([center, size, c0, c1], axis=-1))


def _orthonormal_6d(vec: np.ndarray) -> np.ndarray:
    """Gram-Schmidt the 6D part of box vectors (..., 12)."""
    out = np.array(vec, dtype=np.float64)
    a, b = out[..., 6:9], out[..., 9:12]
    c0 = a / np.maximum(np.linalg.norm(a, axis=-1, keepdims=True), 1e-9)
    b = b - (c0 * b).sum(-1, keepdims=True) * c0
    c1 = b / np.maximum(np.linalg.norm(b, axis=-1, keepdims=True), 1e-9)
    out[..., 6:9], out[..., 9:12] = c0, c1
    return out


def from_pretrained(path: str | Path | None = None, device: str = "cpu") -> LayoutModel:
    """The layout model in checkpoint folder ``path``; None: the bundled default."""
    return LayoutModel.from_pretrained(path, device)
