"""Shards on disk: making one, checking one, the manifest and the dataset's index.

Layout of a dataset folder ``OUT``::

    OUT/manifest.json                  settings, version, digests of the bundled model and
                                       statistics, the shard plan
    OUT/shards/shard-00000/            --shard-format dir: <id>.scene.json, <id>.scene.glb,
                                       <id>.bev.png (and <id>.scene.html) per scene
    OUT/shards/shard-00000.tar         --shard-format tar: the same members (WebDataset)
    OUT/shards/shard-00000.index.jsonl one line per scene; written last (the shard is done)
    OUT/index.jsonl                    every scene's line, when every shard is done

A shard's files are written under a hidden temporary name and renamed into place, then
its index is written atomically: a shard with an index is whole. Whatever a killed write
left (the hidden temporaries, a shard without its index) is removed before the shard is
made again (:func:`clean_shard`). The same plan entry always gives the same bytes (tar
members carry no time stamps or owners), whichever process makes it.

Filter the index, e.g. bedrooms with at least 30 objects::

    import json
    rows = [json.loads(line) for line in open("OUT/index.jsonl")]
    big = [r for r in rows if r["room"] == "bedroom" and r["objects_placed"] >= 30]

or with pandas: ``df = pd.read_json("OUT/index.jsonl", lines=True);
df.query("room == 'bedroom' and objects_placed >= 30")``.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import re
import shutil
import tarfile
import tempfile
import time
from collections import Counter
from collections.abc import Callable
from pathlib import Path

from pair2scene.dataset.plan import DatasetConfig, PlannedScene, plan_shards
from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_open, atomic_write_text, current_umask, folder_lock

MANIFEST = "manifest.json"
"""The dataset's description, in OUT."""
SHARDS = "shards"
"""The folder of the shards, in OUT."""
INDEX = "index.jsonl"
"""The whole dataset's index, in OUT (one JSON line per scene, in plan order)."""
PARQUET_INDEX = "index.parquet"
"""The same index as Parquet, written beside when pyarrow is importable."""
INDEX_SUFFIX = ".index.jsonl"
"""A shard's index: ``shards/shard-00000.index.jsonl``."""
MANIFEST_VERSION = 1
"""The layout of manifest.json (raised when a change would confuse older readers)."""
MEMBER_NAMES = {"json": "scene.json", "glb": "scene.glb", "png": "bev.png", "html": "scene.html"}
"""Format -> the member name after ``<id>.`` (WebDataset groups members by that prefix)."""
BUFFER = 1 << 20
"""Bytes read at a time when hashing."""
_ID_LIKE = re.compile(r"\b[a-z][a-z0-9_]*_\d+\b")
"""An object id inside a drop reason (``dresser_0``): replaced so reasons can be counted."""


def shard_name(index: int) -> str:
    return f"shard-{index:05d}"


def index_path(out: Path, index: int) -> Path:
    return out / SHARDS / f"{shard_name(index)}{INDEX_SUFFIX}"


def data_path(out: Path, index: int, shard_format: str) -> Path:
    """The shard's folder or tar file."""
    suffix = ".tar" if shard_format == "tar" else ""
    return out / SHARDS / f"{shard_name(index)}{suffix}"


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def file_sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        while chunk := fh.read(BUFFER):
            h.update(chunk)
    return h.hexdigest()


def drop_reason(reason: str) -> str:
    """A drop reason without the object ids in it (``no free surface: * is full``), so
    that reasons can be counted across scenes."""
    return _ID_LIKE.sub("*", reason)


# --- making scenes ---------------------------------------------------------------------


def scene_files(generator, config: DatasetConfig, item: PlannedScene) -> tuple[dict, dict]:
    """Generate one planned scene: (member name -> bytes, its index record without the
    file digests)."""
    from pair2scene.io.bev import bev_png
    from pair2scene.io.glb import glb_bytes
    from pair2scene.io.scene_json import dumps_scene

    t0 = time.perf_counter()
    result = generator.generate(room=item.room, seed=item.seed, mode=config.mode,
                                max_objects=config.max_objects, llm="never",
                                scene_id=item.id)  # fmt: skip
    t1 = time.perf_counter()
    files: dict[str, bytes] = {}
    for name in config.formats:
        scene, assets = result.scene, result.assets
        if name == "json":
            data = dumps_scene(scene).encode("utf-8")
        elif name == "glb":
            data = glb_bytes(scene, assets)
        elif name == "png":
            data = bev_png(scene, assets)
        else:
            from pair2scene.io.viewer import scene_html

            data = scene_html(scene, assets)
        files[f"{item.id}.{MEMBER_NAMES[name]}"] = data
    stats = result.stats
    record = {
        "id": item.id,
        "room": item.room,
        "seed": item.seed,
        "mode": config.mode,
        "objects_placed": stats.objects_placed,
        "objects_requested": stats.assembly.requested,
        "drops": dict(sorted(Counter(drop_reason(d.reason) for d in stats.dropped).items())),
        "seconds": {"generate": round(t1 - t0, 4), "export": round(time.perf_counter() - t1, 4)},
    }
    return files, record


def make_shard(
    out: Path,
    config: DatasetConfig,
    index: int,
    items: list[PlannedScene],
    generator,
    on_scene: Callable[[dict], None] | None = None,
) -> list[dict]:
    """Make shard ``index`` of ``out``: its leftovers removed, its scenes generated and
    written, its index written last. ``on_scene(record)`` after each scene (progress).
    Returns the index records."""
    shards = out / SHARDS
    shards.mkdir(parents=True, exist_ok=True)
    clean_shard(out, index, config.shard_format)
    target = data_path(out, index, config.shard_format)
    records = []
    if config.shard_format == "tar":
        with (
            atomic_open(target, "wb") as fh,
            tarfile.open(fileobj=fh, mode="w", format=tarfile.USTAR_FORMAT) as tar,
        ):
            for item in items:
                files, record = scene_files(generator, config, item)
                for name, data in files.items():
                    tar.addfile(_member(name, len(data)), io.BytesIO(data))
                records.append(_finish(record, files, on_scene))
    else:
        tmp = Path(tempfile.mkdtemp(dir=shards, prefix=f".{target.name}."))
        try:
            for item in items:
                files, record = scene_files(generator, config, item)
                for name, data in files.items():
                    (tmp / name).write_bytes(data)
                records.append(_finish(record, files, on_scene))
            os.chmod(tmp, 0o777 & ~current_umask())  # mkdtemp makes 0700
            tmp.rename(target)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
    text = "".join(json.dumps(r, sort_keys=False) + "\n" for r in records)
    atomic_write_text(index_path(out, index), text)
    return records


def _member(name: str, size: int) -> tarfile.TarInfo:
    """A tar member with no time stamp, owner or group: the same bytes on every run."""
    info = tarfile.TarInfo(name)
    info.size, info.mtime, info.mode = size, 0, 0o644
    info.uid = info.gid = 0
    info.uname = info.gname = ""
    return info


def _finish(record: dict, files: dict[str, bytes], on_scene) -> dict:
    record["files"] = {name: sha256(data) for name, data in files.items()}
    if on_scene is not None:
        on_scene(record)
    return record


def clean_shard(out: Path, index: int, shard_format: str) -> list[str]:
    """Remove shard ``index``'s leftovers: its index, its folder or tar, and the hidden
    temporaries of killed writes (``.shard-00000.<random>``, ``.shard-00000.tar.<random>
    .tmp``, ``.shard-00000.index.jsonl.<random>.tmp``). Returns the names removed."""
    shards = out / SHARDS
    name = shard_name(index)
    removed = []
    try:
        entries = list(os.scandir(shards))
    except OSError:
        return removed
    own = (name, f"{name}.tar", f"{name}{INDEX_SUFFIX}")
    for entry in entries:
        hidden = entry.name.startswith(f".{name}.")
        if not hidden and entry.name not in own:
            continue
        if entry.is_dir(follow_symlinks=False):
            shutil.rmtree(entry.path, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                os.unlink(entry.path)
        removed.append(entry.name)
    return removed


# --- checking shards -------------------------------------------------------------------


def read_shard_index(out: Path, index: int) -> list[dict] | None:
    """The records of shard ``index``'s index; None when it is missing or unreadable."""
    path = index_path(out, index)
    try:
        text = path.read_text(encoding="utf-8")
        return [json.loads(line) for line in text.splitlines() if line.strip()]
    except (OSError, ValueError):
        return None


def shard_problem(
    out: Path, config: DatasetConfig, index: int, items: list[PlannedScene]
) -> str | None:
    """What is wrong with shard ``index`` (``missing``, ``corrupt: <why>``), or None when
    it is whole: its index lists the planned scenes and every file's digest checks out."""
    records = read_shard_index(out, index)
    if records is None:
        return "missing" if not index_path(out, index).exists() else "corrupt: unreadable index"
    if [r.get("id") for r in records] != [it.id for it in items]:
        return "corrupt: its index does not list the planned scenes"
    expected = {name: digest for r in records for name, digest in r.get("files", {}).items()}
    target = data_path(out, index, config.shard_format)
    try:
        found = _digests(target, config.shard_format)
    except (OSError, tarfile.TarError) as e:
        return f"corrupt: {target.name}: {e.__class__.__name__}: {e}"
    for name, digest in expected.items():
        if name not in found:
            return f"corrupt: {name} is missing"
        if found[name] != digest:
            return f"corrupt: {name} does not match its digest"
    return None


def _digests(target: Path, shard_format: str) -> dict[str, str]:
    if shard_format == "tar":
        out = {}
        with tarfile.open(target, "r:") as tar:
            for member in tar:
                fh = tar.extractfile(member)
                if fh is not None:
                    out[member.name] = sha256(fh.read())
        return out
    if not target.is_dir():
        raise FileNotFoundError(f"no folder {target.name}")
    return {p.name: file_sha256(p) for p in target.iterdir() if p.is_file()}


# --- the manifest and the index --------------------------------------------------------


def package_version() -> str:
    try:
        import pair2scene

        return pair2scene.__version__
    except AttributeError:  # pragma: no cover - an installed package has it
        from importlib.metadata import version

        return version("pair2scene")


def bundled_digests() -> dict[str, str]:
    """sha256 of every bundled file that decides the scenes: the model files
    (model/default) and the statistics and tables (resources/*.json), by path in the
    package."""
    root = Path(__file__).resolve().parents[1]
    paths = sorted((root / "model" / "default").rglob("*")) + sorted(
        (root / "resources").glob("*.json")
    )
    return {p.relative_to(root).as_posix(): file_sha256(p) for p in paths if p.is_file()}


def manifest(config: DatasetConfig) -> dict:
    """The contents of manifest.json (no time stamps: every run of the same dataset writes
    the same bytes, so slices running side by side may each write it)."""
    return {
        "manifest_version": MANIFEST_VERSION,
        "pair2scene_version": package_version(),
        "settings": config.to_dict(),
        "bundled_digests": bundled_digests(),
        "shards": {
            shard_name(i): [s.to_list() for s in items]
            for i, items in enumerate(plan_shards(config))
        },
    }


def open_dataset(out: Path, config: DatasetConfig) -> None:
    """Make ``out`` a dataset folder for ``config``, or check that it is one: a folder
    made with other settings (or another package version or bundled model) is refused in
    one line, as is a non-empty folder that is not a dataset."""
    wanted = manifest(config)
    path = out / MANIFEST
    if path.is_file():
        try:
            found = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as e:
            raise UserError(f"{path}: unreadable ({e}); choose another --out") from None
        differ = _differences(found, wanted)
        if differ:
            raise UserError(
                f"{out} holds a dataset made with other settings ({'; '.join(differ[:3])}); "
                "rerun with its settings or choose another --out"
            )
        return
    if out.is_dir() and any(not e.name.startswith(".") for e in os.scandir(out)):
        raise UserError(f"{out}: not empty and not a dataset (no {MANIFEST}); choose another --out")
    out.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, json.dumps(wanted, indent=1) + "\n")


def _differences(found: dict, wanted: dict) -> list[str]:
    out = []
    old, new = found.get("settings", {}), wanted["settings"]
    for key in new:
        if old.get(key) != new[key]:
            out.append(f"{key}: {_short(old.get(key))} there, {_short(new[key])} now")
    if found.get("pair2scene_version") != wanted["pair2scene_version"]:
        out.append(f"pair2scene {found.get('pair2scene_version')} there")
    if found.get("bundled_digests") != wanted["bundled_digests"]:
        out.append("another bundled model or statistics")
    return out


def _short(value: object) -> str:
    text = json.dumps(value)
    return text if len(text) <= 40 else text[:37] + "..."


def read_manifest(out: Path) -> tuple[DatasetConfig, dict]:
    """The config and manifest of the dataset in ``out`` (one-line UserError if none)."""
    path = out / MANIFEST
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        s = data["settings"]
        config = DatasetConfig(
            mix=tuple((k, float(v)) for k, v in s["mix"].items()), num=int(s["num"]),
            mode=s["mode"], max_objects=s["max_objects"], formats=tuple(s["formats"]),
            shard_size=int(s["shard_size"]), shard_format=s["shard_format"],
            seed=int(s["seed"]),
        )  # fmt: skip
    except FileNotFoundError:
        raise UserError(f"{out}: not a dataset (no {MANIFEST})") from None
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as e:
        raise UserError(f"{path}: unreadable ({e.__class__.__name__}: {e})") from None
    return config, data


def write_index(out: Path, config: DatasetConfig) -> Path | None:
    """``OUT/index.jsonl`` (and index.parquet with pyarrow): every scene's record with its
    shard, when every shard has its index; None (nothing written) otherwise."""
    rows = []
    for i in range(config.num_shards):
        records = read_shard_index(out, i)
        if records is None:
            return None
        rows += [{**r, "shard": shard_name(i)} for r in records]
    atomic_write_text(out / INDEX, "".join(json.dumps(r) + "\n" for r in rows))
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return out / INDEX
    flat = [{**{k: v for k, v in r.items() if k not in ("drops", "seconds", "files")},
             "dropped": sum(r["drops"].values()), "drops": json.dumps(r["drops"]),
             "seconds_generate": r["seconds"]["generate"]} for r in rows]  # fmt: skip
    with atomic_open(out / PARQUET_INDEX, "wb") as fh:
        pq.write_table(pa.Table.from_pylist(flat), fh)
    return out / INDEX


def dataset_lock(out: Path, shared: bool):
    """Hold a lock on the folder ``out`` while writing: exclusive for a whole run, shared
    for a ``--shard i/N`` slice (slices of one dataset run side by side, a whole run not
    beside them). A conflicting run is a one-line UserError; without flock, unlocked."""
    busy = "another pair2scene dataset run is writing there; wait for it to end"
    return folder_lock(out, busy, shared)
