"""Small validators used by every design schema.

Each raises :class:`cad.errors.DesignError` with the dotted path of the field
and the reason, quoting the value received.
"""

from __future__ import annotations

import math
import os
import unicodedata
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from cad.errors import DesignError
from cad.io import guard


def _path(prefix: str, key: str) -> str:
    return f"{prefix}.{key}" if prefix else key


def load_toml(path: str | Path) -> dict[str, Any]:
    """Read a design's TOML through :func:`cad.io.guard.load_toml` (a regular file of at most
    1 MiB, nested at most 64 levels); a missing file, a folder, a FIFO or device, or bad
    syntax is a DesignError (field ``design``) naming the file and the reason."""
    p = Path(path)
    if p.is_dir():
        raise DesignError("design", f"{p} is a folder, not a design file (give the .toml file)")
    if not os.path.lexists(p):
        raise DesignError("design", f"file not found: {p}")
    return guard.load_toml(p, "design", "design")


def check_unknown(table: dict[str, Any], allowed: Iterable[str], prefix: str) -> None:
    """Reject keys not in ``allowed`` (catches typos such as ``l1mm``)."""
    import difflib

    allowed = set(allowed)
    for key in table:
        if key not in allowed:
            hint = ", ".join(sorted(allowed))
            close = difflib.get_close_matches(str(key), sorted(allowed), n=1, cutoff=0.6)
            guess = f"did you mean {close[0]!r}? " if close else ""
            guess = _process_hint(table, str(key), prefix) or guess
            raise DesignError(_path(prefix, key), f"unknown key ({guess}allowed: {hint})")


def _process_hint(table: dict[str, Any], key: str, prefix: str) -> str:
    """Why ``key`` is unknown when it is a four-bar process key (:mod:`cad.design.parts`:
    ``process``, ``laser_sheet_mm``, ``print_*``) in another family's ``[parts]``, or a
    ``[parts]`` table holding one where the family has none; else ``""``."""
    def fourbar(k) -> bool:
        return k in ("process", "laser_sheet_mm") or str(k).startswith("print_")

    sub = table[key] if not prefix and key == "parts" and isinstance(table[key], dict) else {}
    named = key if prefix.endswith("parts") and fourbar(key) else next(filter(fourbar, sub), None)
    if named is None:
        return ""
    from cad.kinematics.families import FAMILIES  # numpy: a design loads without it

    return (f"{named} is a four-bar [parts] key (families {', '.join([*FAMILIES, 'custom'])}: "
            f"parts.process = \"printed\" or \"laser\"); this family's parts are machined; ")


def require_table(raw: dict[str, Any], key: str, prefix: str) -> dict[str, Any]:
    """Return ``raw[key]`` which must be a TOML table."""
    if key not in raw:
        raise DesignError(_path(prefix, key), "missing table")
    val = raw[key]
    if not isinstance(val, dict):
        raise DesignError(_path(prefix, key), f"must be a table, got {val!r}")
    return val


def optional_table(raw: dict[str, Any], key: str, prefix: str) -> dict[str, Any]:
    """Return ``raw[key]`` if present (must be a table), else an empty dict."""
    if key not in raw:
        return {}
    return require_table(raw, key, prefix)


def require_str(table: dict[str, Any], key: str, prefix: str) -> str:
    if key not in table:
        raise DesignError(_path(prefix, key), "missing")
    val = table[key]
    if not isinstance(val, str) or not val:
        raise DesignError(_path(prefix, key), f"must be a non-empty string, got {val!r}")
    return val


def _number(val: Any, field: str) -> float:
    if isinstance(val, bool) or not isinstance(val, (int, float)):
        raise DesignError(field, f"must be a number, got {val!r}")
    x = float(val)
    if not math.isfinite(x):
        raise DesignError(field, f"must be finite, got {val!r}")
    return x


def require_number(table: dict[str, Any], key: str, prefix: str) -> float:
    if key not in table:
        raise DesignError(_path(prefix, key), "missing")
    return _number(table[key], _path(prefix, key))


def optional_number(table: dict[str, Any], key: str, prefix: str, default: float | None) -> float | None:
    if key not in table:
        return default
    return _number(table[key], _path(prefix, key))


def require_positive(table: dict[str, Any], key: str, prefix: str) -> float:
    x = require_number(table, key, prefix)
    if x <= 0:
        raise DesignError(_path(prefix, key), f"must be > 0, got {table[key]!r}")
    return x


def optional_positive(table: dict[str, Any], key: str, prefix: str, default: float | None) -> float | None:
    if key not in table:
        return default
    return require_positive(table, key, prefix)


def require_nonnegative(table: dict[str, Any], key: str, prefix: str) -> float:
    x = require_number(table, key, prefix)
    if x < 0:
        raise DesignError(_path(prefix, key), f"must be >= 0, got {table[key]!r}")
    return x


def optional_int(table: dict[str, Any], key: str, prefix: str, default: int, minimum: int | None = None) -> int:
    if key not in table:
        return default
    val = table[key]
    if isinstance(val, bool) or not isinstance(val, int):
        raise DesignError(_path(prefix, key), f"must be an integer, got {val!r}")
    if minimum is not None and val < minimum:
        raise DesignError(_path(prefix, key), f"must be >= {minimum}, got {val!r}")
    return val


def number_list(table: dict[str, Any], key: str, prefix: str, length: int | None = None) -> list[float]:
    if key not in table:
        raise DesignError(_path(prefix, key), "missing")
    val = table[key]
    field = _path(prefix, key)
    if not isinstance(val, list):
        raise DesignError(field, f"must be a list of numbers, got {val!r}")
    if length is not None and len(val) != length:
        raise DesignError(field, f"must have {length} numbers, got {len(val)}")
    return [_number(v, field) for v in val]


#: Longest design ``name`` in UTF-8 bytes: the output folder ``exports/<name>/`` and its
#: temporary siblings (``.<name>.tmp.<pid>.<8 chars>``) must fit the usual 255-byte limit
#: on one file name, with room to spare.
NAME_MAX_BYTES = 100
_NAME_FORBIDDEN = set('/\\<>:"|?*')
_WINDOWS_DEVICES = {"con", "prn", "aux", "nul"} | {f"{p}{i}" for p in ("com", "lpt") for i in range(1, 10)}


#: A free text of a design (a motor's name or source, a price key or currency) is at most this
#: many characters: one line of a report, not a document.
TEXT_MAX_CHARS = 500


#: Unicode categories no design string may hold: controls (Cc: C0, DEL, C1), format characters
#: (Cf: the bidirectional overrides and isolates U+202A..U+202E, U+2066..U+2069 that reorder
#: what a reader sees -- Trojan Source, CVE-2021-42574 -- and zero-width characters), line
#: and paragraph separators (Zl, Zp: U+2028, U+2029 end a line in many readers) and lone
#: surrogates (Cs).
HIDDEN_CATEGORIES = ("Cc", "Cf", "Zl", "Zp", "Cs")


def check_text(value: Any, field: str, where: str = "") -> str:
    """Validate a free one-line text of a design (``[motor]`` name and source, ``[prices]``
    keys and currency, cells of a ``--prices`` file) and return it: a string of at most
    :data:`TEXT_MAX_CHARS` characters with no character of :data:`HIDDEN_CATEGORIES` (controls,
    bidirectional and zero-width format characters, line or paragraph separators). Writers escape the rest per format (:mod:`cad.io.escape`).
    Raises :class:`DesignError` naming ``field`` (and ``where`` in it, e.g. a file's row)."""
    at = f"{where}: " if where else ""
    if not isinstance(value, str):
        raise DesignError(field, f"{at}must be a string, got {value!r}")
    bad = next((c for c in value if unicodedata.category(c) in HIDDEN_CATEGORIES), None)
    if bad is not None:
        raise DesignError(field, f"{at}must be one line of text (no control character, format "
                                 f"character or line break: "
                                 f"U+{ord(bad):04X}), got {value[:80]!r}")
    if len(value) > TEXT_MAX_CHARS:
        raise DesignError(field, f"{at}must be at most {TEXT_MAX_CHARS} characters, got {len(value)}")
    return value


def check_name(name: Any, field: str = "name") -> str:
    """Validate a design ``name`` (one validator for every family) and return it.

    The name becomes the output folder ``exports/<name>/``, so it must be one plain
    folder name: a non-empty string of at most :data:`NAME_MAX_BYTES` UTF-8 bytes, no
    ``/``, ``\\``, NUL or other character of :data:`HIDDEN_CATEGORIES`, none of ``<>:"|?*``, not starting
    with ``.`` or ``-`` (``.``, ``..``, hidden folders, options), no leading or trailing
    space, not a Windows device name. Raises :class:`DesignError` naming ``field``.
    """
    def bad(why: str) -> DesignError:
        return DesignError(field, f"must be a plain folder name ({why}), got {name!r}")

    if not isinstance(name, str):
        raise DesignError(field, f"must be a string, got {name!r}")
    if not name:
        raise bad("empty")
    hidden = next((c for c in name if unicodedata.category(c) in HIDDEN_CATEGORIES), None)
    if hidden is not None:  # C0, DEL, C1, bidi/zero-width format characters, U+2028/2029
        raise bad(f"control character, format character or line break: U+{ord(hidden):04X}")
    if _NAME_FORBIDDEN & set(name):
        raise bad('no / \\ < > : " | ? *')
    if name[0] in ".-":
        raise bad("must not start with '.' or '-'")
    if name != name.strip():
        raise bad("leading or trailing space")
    if name.endswith("."):
        raise bad("must not end with '.': not a folder name on Windows")
    if name.split(".")[0].lower() in _WINDOWS_DEVICES:
        raise bad("a reserved device name")
    if len(name.encode("utf-8", "surrogatepass")) > NAME_MAX_BYTES:
        raise bad(f"at most {NAME_MAX_BYTES} bytes")
    return name
