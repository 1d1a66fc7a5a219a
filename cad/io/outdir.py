"""Output folders and files a command may replace: only what hapticad wrote.

Folders (``build --out DIR``, ``exports/<name>/``, ``bench --out DIR``): a command
replaces a folder whole, so it must own every entry in it. A folder is owned when it
does not exist, is empty, or everything in it is listed in its ``manifest.json`` with
the same sha256 (a file edited since it was written counts as the user's). Anything
else -- a foreign or hidden file, an empty sub-folder, a symbolic link, a changed
file, the design file itself -- makes the command refuse with exit 2 naming the
folder and one such entry; nothing is touched. ``--out`` naming a file, a symbolic
link, the current folder or one of its parents is refused the same way.

Shared folders (``render --out DIR``): the command adds files beside the user's and
replaces one only when ``DIR/manifest.json`` lists it with the same sha256 (hapticad
wrote it and nobody changed it since); it then records what it wrote there
(:func:`check_shared_files`, :func:`record_shared_files`).

Files (``swap``/``synth``/``fit --out FILE``): never the input design (same path,
symbolic or hard link), never a folder; an existing file is replaced atomically and
the command says so.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from cad.errors import DesignError, FileDamaged, FileRefused
from cad.io import guard
from cad.io.atomic import write_text_atomic
from cad.io.guard import sha256_of_output

MANIFEST_NAME = "manifest.json"


def _manifest_doc(folder: Path, field: str = "--out") -> Any:
    """The parsed ``folder/manifest.json`` through :func:`cad.io.guard.load_json`; None when
    it is absent or damaged (not JSON). A FIFO, a device, a link to one, an oversized or a too
    deeply nested manifest raises :class:`cad.errors.FileRefused` (never read: issue 22 §2)."""
    path = folder / MANIFEST_NAME
    if not os.path.lexists(path):
        return None
    try:
        return guard.load_json(path, "manifest", field)
    except FileDamaged:
        return None


def _listed(folder: Path, field: str = "--out") -> dict[str, dict]:
    """``{relative POSIX path: {"sha256", "bytes"}}`` from ``folder/manifest.json`` ({} when
    absent or damaged; FileRefused when hostile: :func:`_manifest_doc`)."""
    doc = _manifest_doc(folder, field)
    try:
        return {str(r["path"]): {"sha256": str(r["sha256"]), "bytes": r.get("bytes")}
                for r in doc["files"]}
    except (KeyError, TypeError, AttributeError):
        return {}


def _changed(p: Path, row: dict) -> str | None:
    """Why the file ``p`` differs from its manifest ``row``, or None. A FIFO or device is never
    opened (it would block or never end); the size is compared before the file is hashed."""
    st = os.lstat(p)
    what = guard.not_regular(st.st_mode)
    if what is not None:
        return f"{what}, not a regular file"
    if isinstance(row.get("bytes"), int) and row["bytes"] != st.st_size:
        return "changed since hapticad wrote it"
    digest = guard.sha256_of_output(p)
    if digest is None:
        return f"{st.st_size} bytes, larger than any file hapticad writes (not read)"
    return "changed since hapticad wrote it" if digest != row["sha256"] else None


def foreign_entry(folder: Path) -> tuple[str, str] | None:
    """The first entry of ``folder`` hapticad did not write, as ``(relative path, why)``,
    or None when the folder is absent or owned (module docstring)."""
    folder = Path(folder)
    if not os.path.lexists(folder):
        return None
    try:
        listed = _listed(folder)
    except FileRefused as exc:
        return MANIFEST_NAME, exc.why
    parents = {p.rsplit("/", 1)[0] for p in listed if "/" in p}
    parents |= {"/".join(p.split("/")[:i]) for p in parents for i in range(1, p.count("/") + 1)}
    for root, dirs, files in os.walk(folder):
        dirs.sort()
        rel_root = Path(root).relative_to(folder)
        for name in sorted(files) + [d for d in dirs if os.path.islink(os.path.join(root, d))]:
            rel = (rel_root / name).as_posix()
            p = Path(root, name)
            if p.is_symlink():
                return rel, "a symbolic link"
            what = guard.not_regular(os.lstat(p).st_mode)
            if what is not None:  # never opened: a FIFO waits for a writer for ever
                return rel, f"{what}, not a regular file"
            if rel == MANIFEST_NAME and listed:
                continue
            if rel not in listed:
                return rel, "not listed in its manifest.json"
            why = _changed(p, listed[rel])
            if why:
                return rel, why
        for d in dirs:
            rel = (rel_root / d).as_posix()
            if not os.path.islink(os.path.join(root, d)) and rel not in parents:
                return rel + "/", "a folder hapticad did not write"
    return None


def check_out_dir(folder: Path, design_source: str | None = None, flag: str = "--out") -> None:
    """Raise :class:`DesignError` (field ``flag``) unless ``folder`` may be replaced
    whole by a command's output (module docstring)."""
    folder = Path(folder)
    shown = str(folder)
    if os.path.islink(folder):
        raise DesignError(flag, f"{shown} is a symbolic link; name a folder")
    if os.path.lexists(folder) and not folder.is_dir():
        raise DesignError(flag, f"{shown} is a file, not a folder; name a folder")
    here = Path.cwd().resolve()
    real = folder.resolve()
    if real == here or real in here.parents:
        raise DesignError(
            flag,
            f"{shown} is the current folder or one of its parents; the output folder is "
            "replaced whole, so name a folder of its own (e.g. --out exports/NAME)",
        )
    if design_source:
        src = Path(design_source).resolve()
        if real in src.parents:
            raise DesignError(
                flag, f"{shown} holds the design file {src.name}; name another folder"
            )
    bad = foreign_entry(folder)
    if bad is not None:
        raise DesignError(
            flag,
            f"{shown} holds {bad[0]} ({bad[1]}); hapticad replaces only folders it wrote "
            "entirely: move it away or name another folder",
        )


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return a.resolve() == b.resolve()


def check_out_file(target: Path, design: Path, flag: str = "--out") -> bool:
    """Raise :class:`DesignError` when ``target`` is the input ``design`` (any link to it)
    or a folder; return True when an existing file will be replaced."""
    target = Path(target)
    if os.path.lexists(target) and _same_file(target, Path(design)):
        raise DesignError(flag, f"{target} is the input design {design}; name another file")
    if target.is_dir():
        raise DesignError(flag, f"{target} is a folder; name a .toml file")
    return os.path.lexists(target)


def check_shared_files(folder: Path, names: list[str], flag: str = "--out") -> None:
    """Raise :class:`DesignError` (field ``flag``) when ``folder/name`` exists for a name in
    ``names`` and is not listed with its sha256 in ``folder/manifest.json`` (module
    docstring: shared folders), or when ``folder`` is a file or a symbolic link."""
    folder = Path(folder)
    if os.path.islink(folder) or (os.path.lexists(folder) and not folder.is_dir()):
        raise DesignError(flag, f"{folder} is not a folder; name a folder")
    why = _foreign_manifest(folder / MANIFEST_NAME)
    if why:  # render would rewrite it: never a file hapticad did not write
        raise DesignError(
            flag, f"{folder / MANIFEST_NAME} exists and is {why}; move it away or name another folder"
        )
    listed = _listed(folder, flag)
    for name in names:
        p = folder / name
        if not os.path.lexists(p):
            continue
        why = None
        if p.is_symlink() or not p.is_file():
            why = "not a plain file"
        elif name not in listed:
            why = "not written by hapticad (not in its manifest.json)"
        else:
            why = _changed(p, listed[name])
        if why:
            raise DesignError(
                flag, f"{p} exists and is {why}; move it away or name another folder"
            )


def _foreign_manifest(path: Path) -> str | None:
    """Why ``path`` (an existing ``manifest.json``) is not one hapticad writes -- a JSON
    object whose ``files`` is a list of ``{"path": str, "sha256": str, ...}`` -- or None
    (also None when it does not exist)."""
    if not os.path.lexists(path):
        return None
    if path.is_symlink():
        return "not a plain file (a symbolic link)"
    try:
        doc = guard.load_json(path, "manifest", "--out")
    except FileDamaged:
        return "not a hapticad manifest (not readable JSON)"
    except FileRefused as exc:
        return f"not a plain file: it {exc.why}"
    rows = doc.get("files") if isinstance(doc, dict) else None
    if not isinstance(rows, list) or not all(
        isinstance(r, dict) and isinstance(r.get("path"), str) and isinstance(r.get("sha256"), str)
        for r in rows
    ):
        return 'not a hapticad manifest (no "files" list of path and sha256)'
    return None


def record_shared_files(folder: Path, names: list[str]) -> None:
    """Add ``names`` (files just written into ``folder``) with their sha256 and size to
    ``folder/manifest.json``, keeping the entries already there; atomic."""
    folder = Path(folder)
    doc = _manifest_doc(folder)  # check_shared_files refused a hostile one before the writes
    try:
        rows = {str(r["path"]): r for r in doc["files"]}
    except (KeyError, TypeError, AttributeError):
        doc, rows = {}, {}

    for name in names:
        p = folder / name
        rows[name] = {"path": name, "sha256": sha256_of_output(p), "bytes": p.stat().st_size}
    doc["files"] = [rows[k] for k in sorted(rows)]
    write_text_atomic(folder / MANIFEST_NAME, json.dumps(doc, indent=2, sort_keys=True) + "\n")
