"""``manifest.json``: every exported file with its sha256 and size."""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

from cad.errors import FileRefused
from cad.io import guard
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


def verify_manifest(out_dir: Path) -> dict | None:
    """The manifest of ``out_dir`` if every listed file exists with its sha256, else None.

    The manifest is read through :mod:`cad.io.guard` (a FIFO, a device or an oversized one is
    a mismatch, never read); a listed path must stay inside ``out_dir`` (relative, no ``..``)
    and name a regular file of the listed size before it is hashed (``/dev/zero`` never ends).
    """
    path = Path(out_dir) / MANIFEST_NAME
    try:
        doc = guard.load_json(path, "manifest", "--out")
        for row in doc["files"]:
            rel = Path(str(row["path"]))
            if rel.is_absolute() or ".." in rel.parts:
                return None
            st = os.lstat(Path(out_dir) / rel)
            if guard.not_regular(st.st_mode) or st.st_size != row["bytes"]:
                return None
            if guard.sha256_of_output(Path(out_dir) / rel) != row["sha256"]:  # None: too large
                return None
    except (FileRefused, OSError, KeyError, TypeError, AttributeError):
        return None
    return doc
