"""``manifest.json``: every exported file with its sha256 and size."""

from __future__ import annotations

import hashlib
import json
import os
import stat
from pathlib import Path

from cad.io.atomic import write_text_atomic

MANIFEST_NAME = "manifest.json"


def sha256_file(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def manifest_entries(out_dir: Path) -> list[dict]:
    """``[{"path", "sha256", "bytes"}]`` of every file under ``out_dir`` (sorted, POSIX paths),
    the manifest itself and hidden files excluded."""
    out_dir = Path(out_dir)
    rows = []
    for p in sorted(out_dir.rglob("*")):
        rel = p.relative_to(out_dir)
        if (
            not p.is_file()
            or rel.as_posix() == MANIFEST_NAME
            or any(s.startswith(".") for s in rel.parts)
        ):
            continue
        rows.append({"path": rel.as_posix(), "sha256": sha256_file(p), "bytes": p.stat().st_size})
    return rows


def write_manifest(out_dir: Path, extra: dict | None = None) -> Path:
    """Write ``out_dir/manifest.json`` = ``{"files": [...], **extra}`` atomically."""
    doc = {"files": manifest_entries(Path(out_dir))}
    if extra:
        doc.update(extra)
    return write_text_atomic(
        Path(out_dir) / MANIFEST_NAME, json.dumps(doc, indent=2, sort_keys=True) + "\n"
    )


def _inside(out_dir: Path, rel) -> Path | None:
    """``out_dir/rel`` when ``rel`` is a relative path staying in ``out_dir`` and names a
    regular file (never a link, FIFO or device: ``/dev/zero`` listed was read for ever)."""
    if not isinstance(rel, str) or Path(rel).is_absolute() or ".." in Path(rel).parts:
        return None
    p = out_dir / rel
    try:
        return p if stat.S_ISREG(os.lstat(p).st_mode) else None
    except OSError:
        return None


def verify_manifest(out_dir: Path) -> dict | None:
    """The manifest of ``out_dir`` if every listed file exists with its sha256, else None."""
    path = Path(out_dir) / MANIFEST_NAME
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        for row in doc["files"]:
            p = _inside(Path(out_dir), row["path"])
            if p is None or p.stat().st_size != row["bytes"] or sha256_file(p) != row["sha256"]:
                return None
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return doc
