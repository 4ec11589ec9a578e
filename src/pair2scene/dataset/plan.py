"""The plan of a dataset: which scene (room type, seed, id) goes into which shard.

The plan is a pure function of :class:`DatasetConfig`, so that any worker on any machine
can make any scene and a rerun finds the same shards: scene ``k`` of the dataset
(``0 <= k < num``) has the seed ``seed + k`` and a room type drawn from the mix by
largest-remainder quotas over the whole dataset (the counts match the mix as closely as
whole numbers can), in an order shuffled by a generator seeded with ``seed`` (so every
shard holds a blend of room types, not one type after the other). Its id is
``<room>_<mode>_<seed:08d>``; the same id always gives the same scene.json bytes.

Shard ``i`` holds scenes ``i * shard_size .. (i + 1) * shard_size - 1``; ``--shard i/N``
(a SLURM array task) takes the shards ``j`` with ``j % N == i``.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from pair2scene.errors import UserError

SHARD_FORMATS = ("dir", "tar")
"""How a shard is stored: a folder ``shards/shard-00000/`` or a WebDataset-style tar
``shards/shard-00000.tar``."""
DATASET_FORMATS = ("json", "glb", "png", "html")
"""The formats a dataset can hold (one file per scene each; the simulator formats are
folders and are not offered: ``pair2scene export`` adds them to a scene.json)."""
DEFAULT_DATASET_FORMATS = "json,glb,png"
"""What each scene of a dataset holds unless ``--formats`` says otherwise."""
DEFAULT_SHARD_SIZE = 100
"""Scenes per shard unless ``--shard-size`` says otherwise."""
MAX_SHARD_SIZE = 100_000
"""The most scenes one shard may hold."""
SHUFFLE_STREAM = 0xDA7A5E7
"""Mixed with the seed for the generator that orders the room types (a stream of its own,
apart from every scene's)."""
SEED_SPAN = 2**32
"""Scene seeds are below this (numpy, torch and the asset seeds all take them)."""


@dataclass(frozen=True)
class DatasetConfig:
    """What a dataset is: everything that decides its scenes and files (not how it is
    made: executor, jobs and slices may change between runs of one dataset)."""

    mix: tuple[tuple[str, float], ...]
    """(room type, share) pairs, shares summing to 1, in the order given."""
    num: int
    """Scenes in the dataset."""
    mode: str = "fit"
    """fit (training-like counts) or beyond (denser)."""
    max_objects: int | None = None
    """beyond: objects to reach; fit: a cap; None: the mode's default."""
    formats: tuple[str, ...] = ("json", "glb", "png")
    """Files per scene (names of :data:`DATASET_FORMATS`, json always first)."""
    shard_size: int = DEFAULT_SHARD_SIZE
    """Scenes per shard (the last one may hold fewer)."""
    shard_format: str = "dir"
    """dir or tar (:data:`SHARD_FORMATS`)."""
    seed: int = 0
    """The first scene's seed; scene k has seed + k."""

    def to_dict(self) -> dict:
        """The JSON record of the settings in manifest.json (what a rerun must match)."""
        out = asdict(self)
        out["mix"] = {room: share for room, share in self.mix}
        out["formats"] = list(self.formats)
        return out

    @property
    def rooms(self) -> tuple[str, ...]:
        return tuple(room for room, _ in self.mix)

    @property
    def num_shards(self) -> int:
        return -(-self.num // self.shard_size)


@dataclass(frozen=True)
class PlannedScene:
    """One scene of the plan."""

    id: str
    room: str
    seed: int

    def to_list(self) -> list:
        return [self.id, self.room, self.seed]


def scene_id(room: str, mode: str, seed: int) -> str:
    """The id of a scene: ``<room>_<mode>_<seed:08d>``."""
    return f"{room}_{mode}_{seed:08d}"


def parse_mix(
    text: str | None, rooms: list[str] | tuple[str, ...]
) -> tuple[tuple[str, float], ...]:
    """The mix of room types: ``--mix bedroom=0.4,kitchen=0.3,...`` (weights, scaled to sum
    to 1) or, without it, equal shares of the ``--room`` types. Room names are normalised
    (``Living room`` -> ``living_room``); with both, every ``--room`` must be in the mix.
    Bad input is a one-line UserError."""
    from pair2scene.hierarchy.build import room_key

    keys = list(dict.fromkeys(room_key(r) for r in rooms))
    if text is None:
        if not keys:
            raise UserError("give the room types: --room bedroom --room kitchen ... or --mix")
        return tuple((room, 1.0 / len(keys)) for room in keys)
    weights = mix_weights(text)
    total = sum(weights.values())
    if not weights or total <= 0:
        raise UserError("--mix: give at least one room type with a share > 0")
    missing = [r for r in keys if r not in weights]
    if missing:
        raise UserError(f"--room {', '.join(missing)}: not in --mix (give its share there)")
    return tuple((room, share / total) for room, share in weights.items() if share > 0)


def mix_weights(text: str) -> dict[str, float]:
    """Room type (normalised) -> share of a ``--mix`` text as written, a share of 0 too;
    bad input is a one-line UserError."""
    from pair2scene.hierarchy.build import room_key

    weights: dict[str, float] = {}
    for part in text.split(","):
        if not part.strip():
            continue
        name, eq, value = part.partition("=")
        if not eq or not name.strip():
            raise UserError(f"--mix: {part.strip()!r} is not room=share (bedroom=0.4,...)")
        try:
            share = float(value)
        except ValueError:
            raise UserError(f"--mix: {part.strip()!r}: the share is not a number") from None
        if not np.isfinite(share) or share < 0:
            raise UserError(f"--mix: {part.strip()!r}: the share must be a number >= 0")
        room = room_key(name.strip())
        if room in weights:
            raise UserError(f"--mix: {room} is given twice")
        weights[room] = share
    return weights


def room_counts(mix: tuple[tuple[str, float], ...], num: int) -> list[int]:
    """Scenes per room type: largest-remainder quotas of ``num`` (ties to the earlier
    room type), summing to ``num``."""
    quotas = [share * num for _, share in mix]
    counts = [int(np.floor(q)) for q in quotas]
    order = sorted(range(len(mix)), key=lambda i: (-(quotas[i] - counts[i]), i))
    for i in order[: num - sum(counts)]:
        counts[i] += 1
    return counts


def plan_scenes(config: DatasetConfig) -> list[PlannedScene]:
    """Every scene of the dataset, in dataset order (scene k has seed ``seed + k``)."""
    rooms = [room for (room, _), n in zip(config.mix, room_counts(config.mix, config.num))
             for _ in range(n)]  # fmt: skip
    order = np.random.default_rng([SHUFFLE_STREAM, config.seed]).permutation(len(rooms))
    return [
        PlannedScene(scene_id(rooms[j], config.mode, config.seed + k), rooms[j], config.seed + k)
        for k, j in enumerate(order.tolist())
    ]


def plan_shards(config: DatasetConfig) -> list[list[PlannedScene]]:
    """The scenes of each shard, shard by shard."""
    scenes = plan_scenes(config)
    size = config.shard_size
    return [scenes[i : i + size] for i in range(0, len(scenes), size)]


def parse_slice(text: str | None) -> tuple[int, int]:
    """``--shard i/N`` -> (i, N) with ``0 <= i < N``; None: the whole plan, (0, 1)."""
    if text is None:
        return 0, 1
    i, slash, n = text.partition("/")
    try:
        index, count = int(i), int(n)
    except ValueError:
        index = count = -1
    if not slash or count < 1 or not 0 <= index < count:
        raise UserError(f"--shard {text!r}: give i/N with 0 <= i < N (e.g. 0/8)")
    return index, count


def slice_shards(num_shards: int, part: tuple[int, int]) -> list[int]:
    """The shard indices of slice ``part`` = (i, N): every N-th from i."""
    index, count = part
    return list(range(index, num_shards, count))


def check_config(config: DatasetConfig) -> None:
    """The settings are in range (one-line UserError otherwise); room types are checked
    against the statistics by :func:`check_rooms`."""
    from pair2scene.cli.checks import check_choice, check_count, check_max_objects, check_seed
    from pair2scene.hierarchy.synthesis import MODES

    check_count(config.num, "--num", 1_000_000)
    check_seed(config.seed, count=config.num)
    check_max_objects(config.max_objects)
    check_choice(config.mode, "--mode", MODES)
    check_choice(config.shard_format, "--shard-format", SHARD_FORMATS)
    check_count(config.shard_size, "--shard-size", MAX_SHARD_SIZE)
    bad = [f for f in config.formats if f not in DATASET_FORMATS]
    if bad:
        raise UserError(
            f"--formats: {', '.join(bad)} cannot go into a dataset (choose from "
            f"{', '.join(DATASET_FORMATS)}; pair2scene export adds simulator formats later)"
        )


def parse_formats(text: str) -> tuple[str, ...]:
    """``--formats`` -> the format names in :data:`DATASET_FORMATS` order, json always."""
    names = {f.strip() for f in text.split(",") if f.strip()}
    bad = sorted(names - set(DATASET_FORMATS))
    if bad:
        raise UserError(
            f"--formats: {', '.join(bad)} cannot go into a dataset (choose from "
            f"{', '.join(DATASET_FORMATS)})"
        )
    return tuple(f for f in DATASET_FORMATS if f in names or f == "json")


def check_rooms(config: DatasetConfig, mix: str | None = None) -> None:
    """Every room type of the mix is one the bundled statistics can make (a hierarchy of
    the first seed is drawn for each: an unknown type is a one-line UserError), and so is
    every room the ``--mix`` text ``mix`` names, a share of 0 too (``garage=0`` is a typo
    or a type that does not exist, not a type left out)."""
    from pair2scene.hierarchy.build import build_hierarchy
    from pair2scene.hierarchy.room_types import composable, unknown_message
    from pair2scene.hierarchy.synthesis import load_stats

    stats = load_stats()
    known = set(stats.room_types) | set(composable(stats))
    for name in mix_weights(mix) if mix is not None else ():
        if name not in known:
            raise UserError(f"--mix: {unknown_message(stats, name)}")
    for room in config.rooms:
        build_hierarchy(room, None, config.mode, config.max_objects, config.seed, stats, "never")
