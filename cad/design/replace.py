"""``design.replace(**changes)``: a changed copy of a design, validated exactly as loading
its TOML file is (``dataclasses.replace`` skips every check: a bar width of -5 mm gave an
M11 of 65 g and no error, issue 23).

One implementation for every family: the change is made to the design's TOML mapping
(``design.raw``), the mapping goes through TOML text and back (so only what a file can hold
is accepted, with the types a file gives) and is parsed by :func:`cad.design.parse_design`
with the design's own ``source`` (relative paths keep resolving beside the original file).
Every problem is the :class:`cad.errors.DesignError` loading that file would raise, naming
the dotted field (``parts.bar_width_mm``), the value and the reason.

A change is given in one of three forms (they mix freely; a key set twice to two values is
refused):

* a dotted key, for any key of the file: ``design.replace({"parts.bar_width_mm": 8})``;
* a table name and a mapping of the keys to change in it (merged into the table, nested
  mappings merged likewise): ``design.replace(parts={"bar_width_mm": 8})``;
* a table name and the design's own nested object changed with its ``replace``:
  ``design.replace(parts=design.parts.replace(bar_width_mm=8))`` (the fields that differ
  from the design's are written to the table under their names).

A top-level key takes its value (``design.replace(name="hoeken_wide")``). ``None`` removes a
key (its default applies again). No CAD import.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Mapping
from typing import Any

from cad.design import bounds, parse_design
from cad.errors import DesignError


class ValidatedReplace:
    """Mixin of the design classes: :meth:`replace` validates like loading the file."""

    def replace(self, changes: Mapping[str, Any] | None = None, /, **kw: Any):
        """A copy of this design with ``changes`` (dotted keys) and ``kw`` (table or top-level
        keys) applied, validated as :func:`cad.design.load_design` validates a file
        (module docstring). Raises DesignError naming the dotted field."""
        if changes is not None and not isinstance(changes, Mapping):
            raise DesignError("changes", f"must be a mapping of dotted keys such as "
                              f"{{'parts.bar_width_mm': 24}}, got {changes!r}")
        both = sorted(set(changes or {}) & set(kw))
        if both:
            raise DesignError(both[0], "given twice (in the mapping and as a keyword): give it once")
        return with_slip_hint(replace_design, self, {**(changes or {}), **kw})


class TableReplace:
    """Mixin of a design's nested tables (``design.parts``, ``design.actuator`` ...)."""

    def replace(self, **kw: Any):
        """A copy with the fields in ``kw`` changed, **not yet validated**: give it to the
        design's :meth:`ValidatedReplace.replace` (``design.replace(parts=...)``), which
        checks it as a file's table. Raises DesignError for a name that is not a field."""
        names = {f.name for f in dataclasses.fields(self)}
        unknown = sorted(set(kw) - names)
        if unknown:
            import difflib

            close = difflib.get_close_matches(unknown[0], sorted(names), n=1)
            hint = f"; did you mean {close[0]!r}" if close else ""
            raise DesignError(unknown[0], f"unknown key of {type(self).__name__}{hint}")
        return dataclasses.replace(self, **kw)


def with_slip_hint(load, *args):
    """``load(*args)`` as one command of the CLI: this call's warnings only
    (:func:`cad.design.bounds.reset`), and a DesignError carries the unit-slip hint the
    command's error line gives (:func:`cad.design.bounds.error_line`: "did you give
    metres?")."""
    bounds.reset()
    try:
        return load(*args)
    except DesignError as e:
        line = bounds.error_line(str(e), e.field)
        if line != str(e) and len(e.args) == 1 and line.startswith(str(e)):
            e.reason += line[len(str(e)):]
            e.args = (f"{e.field}: {e.reason}",)
        raise


def replace_design(design, changes: Mapping[str, Any]):
    """``design`` with ``changes`` applied to its TOML mapping, parsed as a file is.

    design : a validated design (``FourBarDesign``, ``PantographDesign``,
        ``PowerMouseDesign``), carrying ``raw`` (its TOML mapping) and ``source``.
    changes : ``{key: value}``; key dotted (``"parts.bar_width_mm"``) or a table / top-level
        key whose value is a mapping to merge, the design's nested object changed with its
        ``replace``, or a value (module docstring). ``None`` removes the key.
    Returns a new design of the family of the changed mapping. Raises DesignError naming the
    dotted field (bad value, unknown key, a value no TOML file can hold).
    """
    raw = copy.deepcopy(design.raw)
    leaves: dict[str, Any] = {}  # every dotted key a change sets: two changes of one key conflict
    for key, value in changes.items():
        if not isinstance(key, str) or not key or any(not p for p in key.split(".")):
            raise DesignError(str(key), "a change is named by a key such as 'parts.bar_width_mm'")
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            value = _changed_fields(design, key, value)
        for leaf, v in _leaves(key, value):
            for other, w in leaves.items():
                if (leaf == other and v != w) or leaf.startswith(other + ".") or other.startswith(leaf + "."):
                    raise DesignError(leaf, f"changed twice ({other} = {w!r} and {leaf} = {v!r}): "
                                            f"give each key once")
            leaves[leaf] = v
        _apply(raw, key.split("."), value)
    return parse_design(_through_toml(raw), design.source)


def _leaves(key: str, value: Any):
    """``(dotted key, value)`` of every key a change sets (a mapping merged key by key)."""
    if isinstance(value, Mapping) and value:
        for k, v in value.items():
            yield from _leaves(f"{key}.{k}", v)
    else:
        yield key, value


def _changed_fields(design, key: str, value) -> dict[str, Any]:
    """``{field: new value}`` of the fields where ``value`` differs from the design's own
    nested object ``design.<key>`` (of the same type)."""
    own = getattr(design, key, None) if "." not in key else None
    if type(own) is not type(value):
        raise DesignError(key, f"got a {type(value).__name__}; give a mapping of the keys to "
                          f"change, or design.{key}.replace(...)")
    return {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)
            if getattr(value, f.name) != getattr(own, f.name)}


def _plain(value: Any) -> Any:
    """Tuples as lists (TOML arrays)."""
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    return value


def _apply(raw: dict, path: list[str], value: Any) -> None:
    """Set (mapping: merge; None: remove) ``raw[path[0]]...[path[-1]]``, tables made as needed."""
    table = raw
    for i, part in enumerate(path[:-1]):
        nxt = table.setdefault(part, {})
        if not isinstance(nxt, dict):
            raise DesignError(".".join(path[: i + 1]), f"is not a table (it holds {nxt!r}); "
                              f"cannot set {'.'.join(path)}")
        table = nxt
    last = path[-1]
    if value is None:
        table.pop(last, None)
    elif isinstance(value, Mapping) and isinstance(table.get(last), dict):
        for k, v in value.items():
            _apply(table, [last, *str(k).split(".")], v)
    else:
        table[last] = dict(value) if isinstance(value, Mapping) else _plain(value)
        _check_toml(".".join(path), table[last])


def _check_toml(key: str, value: Any) -> None:
    """DesignError naming ``key`` when ``value`` is nothing a TOML file can hold."""
    import tomli_w

    try:
        tomli_w.dumps({"v": value})
    except (TypeError, ValueError) as exc:
        raise DesignError(key, f"{value!r} is no TOML value ({exc})") from None


def _through_toml(raw: dict) -> dict:
    """``raw`` written as TOML text and read back: what a file with these changes gives."""
    import tomllib

    import tomli_w

    return tomllib.loads(tomli_w.dumps(raw))
