"""Checks of command-line flags shared by every command (before any work or CAD import).

Numeric flags are checked against :data:`cad.design.bounds.FLAGS` (one place for every
range and its reason); choice flags against their choices; output paths against the file
system, so the error names the flag the user typed (``--out``, ``--report``), never a
temporary file or an errno of an internal step.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from cad.design.bounds import FLAGS, Bound, check_number
from cad.errors import DesignError


def number(flag: str, value: float | int | None, bound: Bound | None = None) -> float | None:
    """Check a numeric flag already converted by typer (``None``: not given)."""
    if value is None:
        return None
    return check_number(flag, value, bound or FLAGS[flag])


def choice(flag: str, value: str | None, choices: Iterable[str]) -> str | None:
    """``value`` when it is one of ``choices`` (``None`` passes), else a DesignError naming the flag."""
    choices = tuple(choices)
    if value is not None and value not in choices:
        raise DesignError(flag, f"must be one of {', '.join(choices)}, got {value!r}")
    return value


def _first_non_folder_ancestor(path: Path) -> Path | None:
    for parent in reversed(path.parents):
        if parent.exists() and not parent.is_dir():
            return parent
    return None


def out_path(flag: str, path: Path | None, *, folder: bool) -> Path | None:
    """Check an output path before anything runs; ``None`` passes.

    ``folder``: the flag names a folder to write into (``--out`` of build, ``--report``),
    else a file (``--out`` of synth / fit / swap). Raises :class:`DesignError` naming the flag
    when a parent is a file (``/dev/null/x``), when a file is expected and a folder exists
    there, or when a folder is expected and a file exists there.
    """
    if path is None:
        return None
    p = Path(path)
    if str(p) == "" or any(c in str(p) for c in "\0"):
        raise DesignError(flag, f"not a usable path: {str(p)!r}")
    try:  # a path or name longer than the system allows (ENAMETOOLONG), a folder not searchable
        bad = _first_non_folder_ancestor(p)
        exists, is_dir = p.exists(), p.is_dir()
    except OSError as exc:
        raise DesignError(flag, f"cannot write {p}: {exc.strerror}") from None
    if bad is not None:
        raise DesignError(flag, f"cannot write {p}: {bad} is not a folder")
    if folder and exists and not is_dir:
        raise DesignError(flag, f"{p} is a file, not a folder")
    if folder:
        _probe_parent(flag, p)
    if not folder and is_dir:
        raise DesignError(flag, f"{p} is a folder; give a file name (e.g. {p / 'new.toml'})")
    return p


def _probe_parent(flag: str, p: Path) -> None:
    """DesignError naming ``flag`` and ``p`` when the existing parent of folder ``p`` takes no
    new folder (a read-only or virtual file system: /proc, /sys): the output is written to a
    temporary sibling first (:func:`cad.io.atomic.atomic_dir`). The probe folder is removed."""
    import tempfile

    parent = p.absolute().parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    try:
        os.rmdir(tempfile.mkdtemp(prefix=".hapticad-probe.", dir=parent))
    except OSError as exc:
        raise DesignError(flag, f"cannot write {p}: {parent} takes no new folder ({exc.strerror})") from None


def design_script(design) -> None:
    """Refuse (DesignError ``parts.handle_script``, naming the opt-in flags) a design whose
    handle script the opt-in does not allow -- at load, before any work; nothing when the
    design has no script (:func:`cad.parts.handle.resolve_script`)."""
    if getattr(getattr(design, "parts", None), "handle_script", None) is not None:
        from cad.parts.handle import resolve_script

        resolve_script(design.parts, design.source)
