"""One guard for every file hapticad reads: checked before a byte of it is parsed.

Every reader (a design's TOML, a ``--prices`` CSV, a STEP or STL given to ``massprops``, an
output folder's ``manifest.json``, a build's ``report.json``, a cache entry, a sweep's
Parquet table) goes through this module, which refuses, with :class:`FileRefused` (one line, exit 2, naming
the field, the file and the reason):

* anything that is not a regular file once symbolic links are resolved: a FIFO (reading it
  would block forever), a device (``/dev/zero`` never ends), a socket, a folder, a dangling
  link or a link loop. The file is opened with ``O_NONBLOCK`` and checked again on the open
  descriptor (``fstat``), so a FIFO swapped in after the first check cannot block either;
* a file larger than its kind's limit (:data:`cad.tolerances.READ_MAX_BYTES`, each with
  its reason); at most the limit is ever read, even from a file that grows meanwhile;
* TOML or JSON nested deeper than :data:`cad.tolerances.NESTING_MAX_DEPTH` (a scan of the
  brackets outside strings and comments, before ``tomllib``/``json`` recurse into it; TOML's
  dotted keys, which nest without brackets, measured on the parsed tables), and
  STEP files whose parentheses nest deeper (OCCT's reader crashes on them).

``kind`` is a key of ``READ_MAX_BYTES``; ``field`` is what the error line names first (the
flag or design key the file came from, e.g. ``--out``, ``design``, ``FILE``). Callers that
treat an unreadable file as a miss (caches) catch :class:`FileRefused`.
"""

from __future__ import annotations

import errno
import json
import os
import re
import stat
from pathlib import Path
from typing import Any

from cad.errors import FileDamaged, FileRefused
from cad.tolerances import NESTING_MAX_DEPTH, READ_MAX_BYTES, STEP_ENTITY_ID_MAX_DIGITS

_WHAT = (
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
    (stat.S_ISDIR, "a folder"),
)


def not_regular(mode: int) -> str | None:
    """What a non-regular file is ("a FIFO (named pipe)", ...), None for a regular file."""
    if stat.S_ISREG(mode):
        return None
    return next((what for test, what in _WHAT if test(mode)), "not a regular file")


def limit_bytes(kind: str) -> int:
    """The size limit of ``kind`` (bytes); KeyError names an unknown kind."""
    return READ_MAX_BYTES[kind]


def _size_text(n: int) -> str:
    return f"{n / (1 << 20):.4g} MiB" if n >= 1 << 20 else f"{n} bytes"


def _check_stat(p: Path, st: os.stat_result, kind: str, field: str) -> None:
    what = not_regular(st.st_mode)
    if what is not None:
        via = f" (a symbolic link to {os.path.realpath(p)})" if os.path.islink(p) else ""
        raise FileRefused(field, p, f"is {what}{via}, not a regular file; hapticad reads only regular files")
    limit = limit_bytes(kind)
    if st.st_size > limit:
        raise FileRefused(field, p, f"is {st.st_size} bytes, over the limit of {limit} bytes "
                          f"({_size_text(limit)}) for a {kind} file (cad/tolerances.py READ_MAX_BYTES)")


def check_file(path: str | os.PathLike, kind: str, field: str) -> int:
    """Refuse ``path`` unless it is a regular file (links resolved) within ``kind``'s size
    limit; its size in bytes. Use before handing the path to a library that opens it itself
    (OCCT, mujoco, pyarrow)."""
    p = Path(path)
    try:
        st = os.stat(p)
    except FileNotFoundError:
        why = "is a symbolic link to a missing file" if os.path.islink(p) else "does not exist"
        raise FileRefused(field, p, why) from None
    except OSError as exc:
        why = "is a symbolic link loop" if exc.errno == errno.ELOOP else f"cannot be read ({exc.strerror})"
        raise FileRefused(field, p, why) from None
    _check_stat(p, st, kind, field)
    return st.st_size


def read_bytes(path: str | os.PathLike, kind: str, field: str) -> bytes:
    """The bytes of ``path`` after :func:`check_file`, read through a descriptor checked
    again with ``fstat`` (never more than the limit, never blocking on a FIFO)."""
    p = Path(path)
    check_file(p, kind, field)
    try:
        fd = os.open(p, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        raise FileRefused(field, p, f"cannot be read ({exc.strerror})") from None
    try:
        _check_stat(p, os.fstat(fd), kind, field)
        limit = limit_bytes(kind)
        chunks, n = [], 0
        while n <= limit:
            b = os.read(fd, min(1 << 20, limit + 1 - n))
            if not b:
                break
            chunks.append(b)
            n += len(b)
    except OSError as exc:
        raise FileRefused(field, p, f"cannot be read ({exc.strerror})") from None
    finally:
        os.close(fd)
    if n > limit:
        raise FileRefused(field, p, f"grew past the {_size_text(limit)} limit for a {kind} file while read")
    return b"".join(chunks)


def read_text(path: str | os.PathLike, kind: str, field: str, encoding: str = "utf-8") -> str:
    """:func:`read_bytes` decoded; text that is not ``encoding`` is refused."""
    data = read_bytes(path, kind, field)
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as exc:
        raise FileDamaged(field, Path(path), f"is not {encoding.upper()} text (byte {exc.start})") from None


# Strings and comments, whose brackets do not nest. Each pattern is an unrolled loop
# (``normal* (special normal*)*``) whose parts cannot match the same text two ways, with an
# end-of-text alternative everywhere: the loop stops only where its end matches, so nothing
# backtracks and an unterminated string or a trailing backslash is consumed once, in linear
# time (a backtracking pattern took seconds on 24 characters). No possessive quantifiers:
# Python 3.11.2 (Debian 12's python3) mis-scans with them.
_SKIP = {
    "json": re.compile(rb'"[^"\\]*(?:\\(?:.|\Z)[^"\\]*)*(?:"|\Z)', re.S),
    "toml": re.compile(
        rb'(?s:"""[^"\\]*(?:(?:\\(?:.|\Z)|"(?!""))[^"\\]*)*(?:"""|\Z))'
        rb"|(?s:'''[^']*(?:'(?!'')[^']*)*(?:'''|\Z))"
        rb'|"[^"\\\n]*(?:\\(?:[^\n]|(?=\n)|\Z)[^"\\\n]*)*(?:"|(?=\n)|\Z)'
        rb"|'[^'\n]*(?:'|(?=\n)|\Z)|#[^\n]*"
    ),
    "step": re.compile(rb"'[^']*(?:''[^']*)*(?:'|\Z)|(?s:/\*[^*]*(?:\*(?!/)[^*]*)*(?:\*/|\Z))"),
}
_BRACKETS = {"json": (b"[{", b"]}"), "toml": (b"[{", b"]}"), "step": (b"(", b")")}


def nesting_depth(data: bytes, syntax: str) -> int:
    """Deepest bracket nesting of ``data`` outside strings and comments.

    ``syntax``: ``"json"``, ``"toml"`` (``[``/``{``) or ``"step"`` (``(``, ISO 10303-21
    strings ``'...'`` and comments ``/* */``). Unbalanced closers count as depth 0 (the
    parser refuses them anyway). Linear time, memory ~3x ``data`` (numpy, in 4 MiB blocks).
    """
    return _depth(_SKIP[syntax].sub(b"", data), syntax)


def _depth(bare: bytes, syntax: str) -> int:
    """:func:`nesting_depth` of text whose strings and comments are already removed."""
    import numpy as np

    opens, closes = _BRACKETS[syntax]
    step = np.zeros(256, np.int8)
    step[list(opens)] = 1
    step[list(closes)] = -1
    depth = deepest = 0
    block = 4 << 20
    for i in range(0, len(bare), block):
        d = np.cumsum(step[np.frombuffer(bare, np.uint8, min(block, len(bare) - i), i)],
                      dtype=np.int64) + depth
        if d.size:
            deepest = max(deepest, int(d.max()))
            depth = max(int(d[-1]), 0)
    return deepest


def check_nesting(data: bytes, syntax: str, path: str | os.PathLike, field: str,
                  bare: bytes | None = None) -> None:
    """Refuse ``data`` (the bytes of ``path``) when it nests deeper than the limit (``bare``:
    the same text with strings and comments removed, when the caller has it)."""
    depth = nesting_depth(data, syntax) if bare is None else _depth(bare, syntax)
    if depth > NESTING_MAX_DEPTH:
        raise FileRefused(field, Path(path), f"is not valid {syntax.upper()} for hapticad (nesting too deep: "
                          f"{depth} levels, the limit is {NESTING_MAX_DEPTH}; "
                          "cad/tolerances.py NESTING_MAX_DEPTH)")


def load_json(path: str | os.PathLike, kind: str, field: str) -> Any:
    """The JSON document of ``path``: :func:`read_bytes`, :func:`check_nesting`, then
    ``json.loads``; text that is not UTF-8 or not valid JSON raises :class:`FileDamaged`
    (a :class:`FileRefused`)."""
    data = read_bytes(path, kind, field)
    check_nesting(data, "json", path, field)
    try:
        return json.loads(data.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise FileDamaged(field, Path(path), f"is not UTF-8 text (byte {exc.start})") from None
    except RecursionError:  # the scan above makes this unreachable; kept as a second wall
        raise FileRefused(field, Path(path), "is not valid JSON (nesting too deep)") from None
    except ValueError as exc:
        raise FileDamaged(field, Path(path), f"is not valid JSON ({exc})") from None


def load_toml(path: str | os.PathLike, kind: str, field: str) -> dict[str, Any]:
    """The TOML document of ``path``, guarded like :func:`load_json`."""
    import tomllib

    data = read_bytes(path, kind, field)
    check_nesting(data, "toml", path, field)
    try:
        doc = tomllib.loads(data.decode("utf-8"))
    except UnicodeDecodeError:
        raise FileDamaged(field, Path(path), "is not UTF-8 text") from None
    except RecursionError:  # unreachable after the scan; a second wall
        raise FileRefused(field, Path(path), "is not valid TOML (nesting too deep)") from None
    except tomllib.TOMLDecodeError as exc:
        raise FileDamaged(field, Path(path), f"is not valid TOML ({exc})") from None
    depth = value_depth(doc)
    if depth > NESTING_MAX_DEPTH:  # dotted keys (a.b.c = 1, [a.b.c]) nest without brackets
        raise FileRefused(field, Path(path), f"is not valid TOML for hapticad (tables nested {depth} "
                          f"levels deep through dotted keys, the limit is {NESTING_MAX_DEPTH}; "
                          "cad/tolerances.py NESTING_MAX_DEPTH)")
    return doc


def value_depth(doc: Any) -> int:
    """How deep tables and arrays nest in a parsed document (a scalar is 0, ``{"a": 1}`` is 1);
    iterative, so a document nested past Python's recursion limit is measured too."""
    deepest, stack = 0, [(doc, 0)]
    while stack:
        v, d = stack.pop()
        if isinstance(v, dict):
            v = list(v.values())
        elif not isinstance(v, list):
            continue
        deepest = max(deepest, d + 1)
        stack.extend((x, d + 1) for x in v)
    return deepest


def check_step(path: str | os.PathLike, field: str) -> None:
    """Refuse a STEP file that is not a regular file within the ``step`` limit, whose
    parentheses nest too deep or that has an entity id of more than
    :data:`cad.tolerances.STEP_ENTITY_ID_MAX_DIGITS` digits (each a segmentation fault in
    OCCT's reader), before OCCT opens it."""
    data = read_bytes(path, "step", field)
    bare = _SKIP["step"].sub(b"", data)
    check_nesting(data, "step", path, field, bare)
    m = re.search(rb"#(\d{%d,})" % (STEP_ENTITY_ID_MAX_DIGITS + 1), bare)
    if m:
        raise FileRefused(field, Path(path), f"is not valid STEP for hapticad (an entity id of "
                          f"{len(m.group(1))} digits, the limit is {STEP_ENTITY_ID_MAX_DIGITS}; "
                          "cad/tolerances.py STEP_ENTITY_ID_MAX_DIGITS)")


#: MJCF elements whose ``file`` is resolved against a ``<compiler>`` folder attribute (mujoco's
#: rules: ``meshdir`` / ``texturedir``, else ``assetdir``, else the model's own folder).
_MJCF_DIRS = {"mesh": "meshdir", "skin": "meshdir", "texture": "texturedir", "hfield": "texturedir"}


def check_mjcf(path: str | os.PathLike, field: str) -> None:
    """Refuse an MJCF model unless it and every file it names (meshes, textures, includes:
    mujoco opens them itself, and blocked forever on a mesh that is a FIFO) are regular files
    within their limits (``mjcf`` for the model, ``stl`` for what it names). XML that does not
    parse names no file: it is left to mujoco's loader, which reports it before opening any."""
    import xml.etree.ElementTree as ET

    p = Path(path)
    text = read_text(p, "mjcf", field)
    try:
        root = ET.fromstring(text)
    except ET.ParseError:
        return
    comp = {k: v for c in root.iter("compiler") for k, v in c.attrib.items()}
    for el in root.iter():
        name = el.get("file")
        if name is None:
            continue
        sub = comp.get(_MJCF_DIRS.get(el.tag, ""), comp.get("assetdir", "")) if el.tag in _MJCF_DIRS else ""
        target = Path(name) if os.path.isabs(name) else p.parent / sub / name
        check_file(target, "stl", field)


def sha256_of_output(path: str | os.PathLike) -> str | None:
    """sha256 (hex) of a regular file an output folder's manifest lists, or None when it is
    over ``READ_MAX_BYTES["output"]`` (larger than any file hapticad writes: never read).
    The size is taken from the open descriptor, so a file swapped in cannot be read past it."""
    import hashlib

    limit = limit_bytes("output")
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        if os.fstat(fh.fileno()).st_size > limit:
            return None
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()
