"""3D-Pairs on disk: relation tuples in sharded numpy arrays plus a manifest.

Layout of a dataset folder::

    manifest.json              format, version, vocabularies, shards (file, key, count,
                               sha256, counts, pipeline meta), totals
    shards/shard-<key>.npz     one shard per curation chunk, numeric arrays only

A shard holds, for N tuples (names as stored)::

    kind                          (N,) int8     index into manifest "kinds"
    {dep,sup,func}_cat            (N,) int32    index into manifest "categories" (-1: none)
    {dep,sup,func}_box            (N, 12) f32   world box: centre, size, 6D rotation (NaN: none)
    canonical                     (N, 12) f32   dependent in the support anchor's frame
    canonical_functional          (N, 12) f32   dependent in the functional anchor's frame
    wall_box                      (N, 12) f32   the frame of the wall a floor object stands
                                                against (NaN: none; version 2)
    wall_index                    (N,) int32    that wall's edge of the floor polygon (-1)
    canonical_wall                (N, 12) f32   dependent in that wall's frame (NaN: none)
    {dep,sup,func}_id             (N,) int32    index into ``strings`` (-1: none)
    {dep,sup,func}_asset_source   (N,) int32    index into ``strings`` (-1: no asset)
    {dep,sup,func}_asset_id       (N,) int32    index into ``strings`` (-1: none)
    {dep,sup,func}_asset_style    (N,) int32    style variant (-1: none)
    source, scene_id, split, room_type  (N,) int32  index into ``strings`` (-1: none)
    strings                       (M,) <U       the shard's string table

Shards are written atomically and byte-for-byte deterministically (fixed zip entry
times), then recorded in the manifest (also rewritten atomically), so an interrupted
run loses at most the shard in progress. A shard counts as finished only when the
manifest names it with its key and the file's sha256 matches. Nothing is pickled:
files are read with ``np.load(allow_pickle=False)``.
"""

from __future__ import annotations

import hashlib
import io
import json
import re
import zipfile
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pair2scene.categories import CATEGORIES, UNKNOWN
from pair2scene.curation.tuples import RELATION_KINDS, Member, PairTuple, RelationKind
from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_bytes, atomic_write_text
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import AssetRef

PAIRS_FORMAT = "pair2scene.pairs"
PAIRS_VERSION = 3
"""2: the wall anchor (``wall_box``, ``wall_index``, ``canonical_wall``) of issue 18.
3: tuples of objects mounted on a wall, whose support member is that wall (id
``wall_<i>``, category ``wall``, box the wall's frame, no asset) of issue 19."""
READABLE_VERSIONS = (2, 3)
"""Versions :func:`read_pairs` reads: a version 2 dataset is a version 3 one without
mounted objects."""
MANIFEST = "manifest.json"
SHARD_DIR = "shards"
SHARD_SIZE = 4096
"""Tuples per shard for :func:`write_pairs` (the pipeline writes one shard per chunk)."""
CATEGORY_VOCAB: tuple[str, ...] = (*(c.name for c in CATEGORIES), UNKNOWN)
"""Category index -> name. Fixed by pair2scene.categories, so indices are stable
across runs and shards written by an earlier run stay valid."""
MEMBERS = ("dep", "sup", "func")
STRING_COLUMNS = ("source", "scene_id", "split", "room_type")
_ZIP_TIME = (1980, 1, 1, 0, 0, 0)
"""Zip entry time of every shard member: fixed, so equal tuples give equal bytes."""
_KEY = re.compile(r"^[A-Za-z0-9_-]{1,64}$")
_CAT_INDEX = {c: i for i, c in enumerate(CATEGORY_VOCAB)}
_KIND_INDEX = {k: i for i, k in enumerate(RELATION_KINDS)}


# -- encoding -----------------------------------------------------------------------


class _Strings:
    """Interns strings into a table; None -> -1."""

    def __init__(self) -> None:
        self.index: dict[str, int] = {}

    def __call__(self, s: str | None) -> int:
        if s is None:
            return -1
        return self.index.setdefault(s, len(self.index))

    def table(self) -> np.ndarray:
        return np.array(list(self.index), dtype=np.str_) if self.index else np.zeros(0, "<U1")


def _category_index(name: str) -> int:
    try:
        return _CAT_INDEX[name]
    except KeyError:
        raise ValueError(f"category {name!r} is not in the canonical vocabulary") from None


def encode_tuples(tuples: Sequence[PairTuple]) -> dict[str, np.ndarray]:
    """The shard arrays (see the module docstring) of ``tuples``."""
    n = len(tuples)
    strings = _Strings()
    arrays: dict[str, np.ndarray] = {"kind": np.zeros(n, np.int8)}
    for m in MEMBERS:
        arrays[f"{m}_cat"] = np.full(n, -1, np.int32)
        arrays[f"{m}_box"] = np.full((n, 12), np.nan, np.float32)
        for col in ("id", "asset_source", "asset_id", "asset_style"):
            arrays[f"{m}_{col}"] = np.full(n, -1, np.int32)
    arrays["canonical"] = np.zeros((n, 12), np.float32)
    arrays["canonical_functional"] = np.full((n, 12), np.nan, np.float32)
    arrays["wall_box"] = np.full((n, 12), np.nan, np.float32)
    arrays["wall_index"] = np.full(n, -1, np.int32)
    arrays["canonical_wall"] = np.full((n, 12), np.nan, np.float32)
    for col in STRING_COLUMNS:
        arrays[col] = np.full(n, -1, np.int32)
    for i, t in enumerate(tuples):
        arrays["kind"][i] = _KIND_INDEX[RelationKind(t.kind).value]
        for m, member in zip(MEMBERS, (t.dependent, t.support, t.functional)):
            if member is None:
                continue
            arrays[f"{m}_cat"][i] = _category_index(member.category)
            arrays[f"{m}_box"][i] = member.box.to_vector()
            arrays[f"{m}_id"][i] = strings(member.id)
            if member.asset is not None:
                arrays[f"{m}_asset_source"][i] = strings(member.asset.source)
                arrays[f"{m}_asset_id"][i] = strings(member.asset.id)
                if member.asset.style is not None:
                    arrays[f"{m}_asset_style"][i] = member.asset.style
        arrays["canonical"][i] = t.canonical.to_vector()
        if t.canonical_functional is not None:
            arrays["canonical_functional"][i] = t.canonical_functional.to_vector()
        if t.wall is not None:
            arrays["wall_box"][i] = t.wall.box.to_vector()
            arrays["wall_index"][i] = int(t.wall.id.rsplit("_", 1)[1])
            arrays["canonical_wall"][i] = t.canonical_wall.to_vector()
        for col in STRING_COLUMNS:
            arrays[col][i] = strings(getattr(t, col))
    arrays["strings"] = strings.table()
    return arrays


def npz_bytes(arrays: dict[str, np.ndarray]) -> bytes:
    """An uncompressed .npz of ``arrays`` whose bytes depend on the arrays alone."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_STORED) as zf:
        for name, arr in arrays.items():
            member = io.BytesIO()
            np.lib.format.write_array(member, np.ascontiguousarray(arr), allow_pickle=False)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=_ZIP_TIME)
            info.external_attr = 0o644 << 16
            zf.writestr(info, member.getvalue())
    return buf.getvalue()


def shard_counts(tuples: Sequence[PairTuple]) -> dict:
    """Counts of one shard: per source, per relation kind, per source and kind, and per
    category pair (``support``: anchor -> dependent over all tuples, the floor included;
    ``functional``: functional anchor -> dependent)."""
    sources: Counter[str] = Counter()
    kinds: Counter[str] = Counter()
    source_kinds: dict[str, Counter[str]] = {}
    support: dict[str, Counter[str]] = {}
    functional: dict[str, Counter[str]] = {}
    for t in tuples:
        kind = RelationKind(t.kind).value
        sources[t.source] += 1
        kinds[kind] += 1
        source_kinds.setdefault(t.source, Counter())[kind] += 1
        support.setdefault(t.support.category, Counter())[t.dependent.category] += 1
        if t.functional is not None:
            functional.setdefault(t.functional.category, Counter())[t.dependent.category] += 1
    return {
        "tuples": len(tuples),
        "per_source": dict(sorted(sources.items())),
        "per_kind": dict(sorted(kinds.items())),
        "per_source_kind": {s: dict(sorted(c.items())) for s, c in sorted(source_kinds.items())},
        "per_pair": {
            "support": {a: dict(sorted(c.items())) for a, c in sorted(support.items())},
            "functional": {a: dict(sorted(c.items())) for a, c in sorted(functional.items())},
        },
    }


def _merge_counts(parts: Sequence[dict]) -> dict:
    total = 0
    sources: Counter[str] = Counter()
    kinds: Counter[str] = Counter()
    source_kinds: dict[str, Counter[str]] = {}
    pairs: dict[str, dict[str, Counter[str]]] = {"support": {}, "functional": {}}
    for c in parts:
        total += c["tuples"]
        sources.update(c["per_source"])
        kinds.update(c["per_kind"])
        for s, ks in c["per_source_kind"].items():
            source_kinds.setdefault(s, Counter()).update(ks)
        for rel in pairs:
            for a, deps in c["per_pair"][rel].items():
                pairs[rel].setdefault(a, Counter()).update(deps)
    return {
        "tuples": total,
        "per_source": dict(sorted(sources.items())),
        "per_kind": dict(sorted(kinds.items())),
        "per_source_kind": {s: dict(sorted(c.items())) for s, c in sorted(source_kinds.items())},
        "per_pair": {
            rel: {a: dict(sorted(c.items())) for a, c in sorted(p.items())}
            for rel, p in pairs.items()
        },
    }


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _file_sha256(path: Path) -> str | None:
    try:
        return _sha256(path.read_bytes())
    except OSError:
        return None


# -- writing ------------------------------------------------------------------------


class PairsWriter:
    """Writes shards into a dataset folder, resuming what an earlier run finished.

    Each shard is identified by a caller-chosen ``key`` (the pipeline hashes a chunk's
    scenes and settings into it). :meth:`finished` tells whether a shard with that key
    is already on disk, intact; :meth:`write` adds one; :meth:`finalize` keeps exactly
    the given keys, in that order, and marks the dataset complete.
    """

    def __init__(self, root: str | Path, fresh: bool = False) -> None:
        self.root = Path(root)
        self.entries: dict[str, dict] = {}
        manifest = self.root / MANIFEST
        if manifest.exists() and not fresh:
            doc = _read_manifest(manifest)
            compatible = (
                doc.get("version") == PAIRS_VERSION
                and doc.get("categories") == list(CATEGORY_VOCAB)
                and doc.get("kinds") == list(RELATION_KINDS)
            )
            if compatible:
                self.entries = {e["key"]: e for e in doc.get("shards", [])}
        elif manifest.exists():
            _read_manifest(manifest)  # refuse to overwrite a folder that is something else

    def finished(self, key: str) -> dict | None:
        """The manifest entry of shard ``key`` when its file is present and intact."""
        entry = self.entries.get(key)
        if entry is None:
            return None
        if _file_sha256(self.root / entry["file"]) != entry["sha256"]:
            return None
        return entry

    def write(self, key: str, tuples: Sequence[PairTuple], meta: dict | None = None) -> dict:
        """Write one shard atomically and record it (with ``meta``) in the manifest."""
        if not _KEY.match(key):
            raise ValueError(f"shard key {key!r}: use 1-64 letters, digits, '-' or '_'")
        data = npz_bytes(encode_tuples(tuples))
        rel = f"{SHARD_DIR}/shard-{key}.npz"
        atomic_write_bytes(self.root / rel, data)
        entry = {
            "key": key,
            "file": rel,
            "count": len(tuples),
            "sha256": _sha256(data),
            "counts": shard_counts(tuples),
            "meta": meta or {},
        }
        self.entries.pop(key, None)
        self.entries[key] = entry
        self._write_manifest(list(self.entries.values()), complete=False)
        return entry

    def finalize(self, keys: Sequence[str], extra: dict | None = None) -> dict:
        """Keep the shards ``keys`` in that order, delete every other shard file, mark
        the dataset complete and return the manifest. ``extra`` is stored as is."""
        missing = [k for k in keys if k not in self.entries]
        if missing:
            raise ValueError(f"finalize: shards never written: {missing[:3]}")
        entries = [self.entries[k] for k in keys]
        doc = self._write_manifest(entries, complete=True, extra=extra)
        keep = {e["file"] for e in entries}
        shard_dir = self.root / SHARD_DIR
        if shard_dir.is_dir():
            for p in shard_dir.iterdir():
                if p.name.startswith("shard-") and f"{SHARD_DIR}/{p.name}" not in keep:
                    p.unlink()
        self.entries = {e["key"]: e for e in entries}
        return doc

    def _write_manifest(
        self, entries: list[dict], complete: bool, extra: dict | None = None
    ) -> dict:
        doc = {
            "format": PAIRS_FORMAT,
            "version": PAIRS_VERSION,
            "complete": complete,
            "count": sum(e["count"] for e in entries),
            "categories": list(CATEGORY_VOCAB),
            "kinds": list(RELATION_KINDS),
            "counts": _merge_counts([e["counts"] for e in entries]),
            "shards": entries,
        }
        if extra:
            doc["extra"] = extra
        atomic_write_text(self.root / MANIFEST, json.dumps(doc, indent=1) + "\n")
        return doc


def write_pairs(
    tuples: Sequence[PairTuple], root: str | Path, shard_size: int = SHARD_SIZE
) -> dict:
    """Write ``tuples`` as a fresh dataset in shards of ``shard_size``; returns the manifest."""
    writer = PairsWriter(root, fresh=True)
    keys = []
    for i, start in enumerate(range(0, max(len(tuples), 1), shard_size)):
        key = f"{i:05d}"
        writer.write(key, tuples[start : start + shard_size])
        keys.append(key)
    return writer.finalize(keys)


# -- reading ------------------------------------------------------------------------


def _read_manifest(path: Path) -> dict:
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UserError(f"{path}: no such file (not a 3D-Pairs folder)") from None
    except (OSError, ValueError) as e:
        raise UserError(f"{path}: not a readable manifest ({e})") from None
    if not isinstance(doc, dict) or doc.get("format") != PAIRS_FORMAT:
        raise UserError(f"{path}: not a {PAIRS_FORMAT} manifest")
    return doc


@dataclass
class MemberArrays:
    """One member (dependent, support or functional anchor) of every tuple."""

    id: np.ndarray
    """(N,) str; "" where the tuple has no such member."""
    category: np.ndarray
    """(N,) int32 index into PairsDataset.categories; -1 where absent."""
    box: np.ndarray
    """(N, 12) float32 world box (centre, size, 6D rotation); NaN where absent."""
    asset_source: np.ndarray
    """(N,) str; "" where the member has no asset (the floor)."""
    asset_id: np.ndarray
    """(N,) str; "" where none."""
    asset_style: np.ndarray
    """(N,) int32; -1 where none."""

    @property
    def present(self) -> np.ndarray:
        """(N,) bool."""
        return self.category >= 0


@dataclass
class PairsDataset:
    """Every tuple of a 3D-Pairs folder as numpy arrays (N tuples)."""

    categories: tuple[str, ...]
    kinds: tuple[str, ...]
    kind: np.ndarray
    """(N,) int8 index into ``kinds``."""
    dependent: MemberArrays
    support: MemberArrays
    functional: MemberArrays
    canonical: np.ndarray
    """(N, 12) float32: the dependent's box in the support anchor's canonical frame."""
    canonical_functional: np.ndarray
    """(N, 12) float32: ... in the functional anchor's frame; NaN without one."""
    wall_box: np.ndarray
    """(N, 12) float32: the frame of the wall the dependent stands against; NaN without."""
    wall_index: np.ndarray
    """(N,) int32: that wall's edge index in the room's floor polygon; -1 without."""
    canonical_wall: np.ndarray
    """(N, 12) float32: the dependent's box in the wall's frame; NaN without."""
    source: np.ndarray
    """(N,) str."""
    scene_id: np.ndarray
    split: np.ndarray
    """(N,) str; "" where unknown."""
    room_type: np.ndarray
    manifest: dict = field(repr=False, default_factory=dict)

    def __len__(self) -> int:
        return len(self.kind)

    def kind_mask(self, kind: RelationKind | str) -> np.ndarray:
        """(N,) bool: tuples of relation ``kind``."""
        return self.kind == self.kinds.index(RelationKind(kind).value)

    def tuple(self, i: int) -> PairTuple:
        """Tuple ``i`` rebuilt (boxes from the stored float32 vectors)."""

        def member(m: MemberArrays) -> Member | None:
            if m.category[i] < 0:
                return None
            asset = None
            if m.asset_source[i]:
                style = int(m.asset_style[i])
                asset = AssetRef(
                    str(m.asset_source[i]), str(m.asset_id[i]) or None, None if style < 0 else style
                )
            box = OrientedBox.from_vector(m.box[i])
            return Member(str(m.id[i]), self.categories[m.category[i]], asset, box)

        dep, sup, func = member(self.dependent), member(self.support), member(self.functional)
        assert dep is not None and sup is not None
        wall = None
        if self.wall_index[i] >= 0:
            wall_box = OrientedBox.from_vector(self.wall_box[i])
            wall = Member(f"wall_{int(self.wall_index[i])}", "wall", None, wall_box)
        return PairTuple(
            source=str(self.source[i]),
            scene_id=str(self.scene_id[i]),
            split=str(self.split[i]) or None,
            room_type=str(self.room_type[i]),
            kind=RelationKind(self.kinds[self.kind[i]]),
            dependent=dep,
            support=sup,
            functional=func,
            canonical=OrientedBox.from_vector(self.canonical[i]),
            canonical_functional=(
                None if func is None else OrientedBox.from_vector(self.canonical_functional[i])
            ),
            wall=wall,
            canonical_wall=(
                None if wall is None else OrientedBox.from_vector(self.canonical_wall[i])
            ),
        )

    def to_tuples(self) -> list[PairTuple]:
        return [self.tuple(i) for i in range(len(self))]


def load_pairs(
    root: str | Path, verify: bool = True, allow_incomplete: bool = False
) -> PairsDataset:
    """Load every shard of a 3D-Pairs folder, in manifest order.

    verify : check each shard's sha256 against the manifest (a mismatch is a UserError
    naming the shard: rerun ``pair2scene curate`` to rebuild it).
    allow_incomplete : accept a dataset whose curation run has not finished.
    """
    root = Path(root)
    doc = _read_manifest(root / MANIFEST)
    if doc.get("version") not in READABLE_VERSIONS:
        raise UserError(f"{root / MANIFEST}: version {doc.get('version')!r} not supported")
    if not doc.get("complete") and not allow_incomplete:
        raise UserError(f"{root}: curation did not finish (rerun the same curate command)")
    shards = []
    for entry in doc["shards"]:
        path = root / entry["file"]
        try:
            data = path.read_bytes()
        except OSError as e:
            raise UserError(f"{path}: cannot read shard ({e.strerror})") from None
        if verify and _sha256(data) != entry["sha256"]:
            raise UserError(f"{path}: corrupt shard (sha256 mismatch); rerun curate to rebuild")
        try:
            with np.load(io.BytesIO(data), allow_pickle=False) as z:
                shards.append({k: z[k] for k in z.files})
        except (ValueError, OSError, zipfile.BadZipFile) as e:
            raise UserError(f"{path}: not a readable shard ({e})") from None
    return _assemble(shards, doc)


def _assemble(shards: list[dict[str, np.ndarray]], doc: dict) -> PairsDataset:
    # Per-shard string tables are concatenated; codes are shifted by each table's offset,
    # and -1 (none) points at a trailing "".
    tables = [s["strings"] for s in shards]
    offsets = np.cumsum([0] + [len(t) for t in tables])
    table = np.concatenate([*(t.astype(np.str_) for t in tables), np.array([""])])
    none = len(table) - 1

    def cat(name: str, dtype, shape=()) -> np.ndarray:
        if not shards:
            return np.zeros((0, *shape), dtype)
        return np.concatenate([s[name] for s in shards]).astype(dtype, copy=False)

    def strings(name: str) -> np.ndarray:
        if not shards:
            return np.zeros(0, "<U1")
        codes = np.concatenate(
            [np.where(s[name] >= 0, s[name] + off, none) for s, off in zip(shards, offsets)]
        )
        return table[codes]

    def member(m: str) -> MemberArrays:
        return MemberArrays(
            id=strings(f"{m}_id"),
            category=cat(f"{m}_cat", np.int32),
            box=cat(f"{m}_box", np.float32, (12,)),
            asset_source=strings(f"{m}_asset_source"),
            asset_id=strings(f"{m}_asset_id"),
            asset_style=cat(f"{m}_asset_style", np.int32),
        )

    return PairsDataset(
        categories=tuple(doc["categories"]),
        kinds=tuple(doc["kinds"]),
        kind=cat("kind", np.int8),
        dependent=member("dep"),
        support=member("sup"),
        functional=member("func"),
        canonical=cat("canonical", np.float32, (12,)),
        canonical_functional=cat("canonical_functional", np.float32, (12,)),
        source=strings("source"),
        scene_id=strings("scene_id"),
        split=strings("split"),
        room_type=strings("room_type"),
        wall_box=cat("wall_box", np.float32, (12,)),
        wall_index=cat("wall_index", np.int32),
        canonical_wall=cat("canonical_wall", np.float32, (12,)),
        manifest=doc,
    )
