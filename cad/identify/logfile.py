"""The identification log: one public CSV format (issue 37), its writer and its parser.

Format (a public contract, docs/identify.md)::

    # hapticad identification log; design <name>; design hash sha256:<64 hex>; ...
    t_s,counts_0[,counts_1 ...],current_A_0[,current_A_1 ...]
    0.0,0,0.0
    0.00033,1,0.012
    ...

* line 1: a comment (``#``) naming the design hash as ``sha256:<hex>`` (more ``;``-separated
  notes may follow: the routine, the control period);
* line 2: the column names, exactly, one ``counts_i`` and one ``current_A_i`` per motor;
* then one row per control period: time (s, strictly increasing), raw encoder counts
  (integers, as the counter reads them), the commanded motor currents (A).

:func:`parse_log` refuses, with one line naming the file and the problem
(:class:`cad.errors.FileDamaged`, exit 2): an empty file, a missing hash line, wrong columns,
a row with another number of cells, a cell that is not a number, non-monotonic time, encoder
counts that are not integers, currents at the clamp in too many rows (saturation).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cad.errors import FileDamaged
from cad.tolerances import IDENT_SATURATION_FRACTION_MAX

HASH = re.compile(r"sha256:([0-9a-f]{64})")


def columns(n_joints: int) -> list[str]:
    """The column names of a log of a device with ``n_joints`` motors."""
    return (["t_s"] + [f"counts_{i}" for i in range(n_joints)]
            + [f"current_A_{i}" for i in range(n_joints)])


@dataclass(frozen=True)
class Log:
    """A parsed log: ``t_s`` (N,) s, ``counts`` (N, n) int, ``current_A`` (N, n) A,
    ``design_hash`` (64 hex) and the comment line ``note``."""

    t_s: np.ndarray
    counts: np.ndarray
    current_A: np.ndarray
    design_hash: str
    note: str


def header_line(name: str, design_hash: str, what: str, Te_s: float) -> str:
    """The comment line of a log (no newline)."""
    return (f"# hapticad identification log; design {name}; design hash sha256:{design_hash}; "
            f"{what}; control period {Te_s!r} s")


def format_log(comment: str, t_s, counts, current_A) -> str:
    """CSV text of a log: ``comment`` line, column names, rows (``repr`` of floats: exact)."""
    counts = np.asarray(counts, dtype=np.int64).reshape(len(t_s), -1)
    cur = np.asarray(current_A, dtype=float).reshape(len(t_s), -1)
    lines = [comment, ",".join(columns(counts.shape[1]))]
    for t, c, i in zip(np.asarray(t_s, dtype=float), counts, cur, strict=True):
        lines.append(",".join([repr(float(t)), *map(str, c.tolist()), *map(repr, i.tolist())]))
    return "\n".join(lines) + "\n"


def _refuse(path, why: str, field: str = "LOG") -> FileDamaged:
    return FileDamaged(field, Path(path), why)


def _rows(lines: list[str], path, n_cols: int) -> np.ndarray:
    data = np.empty((len(lines), n_cols))
    for k, line in enumerate(lines):
        cells = line.split(",")
        if len(cells) != n_cols:
            raise _refuse(path, f"line {k + 3} has {len(cells)} cells, the header {n_cols}")
        for j, cell in enumerate(cells):
            try:
                v = float(cell)
            except ValueError:
                raise _refuse(path, f"line {k + 3} column {j + 1}: {cell.strip()[:40]!r} is not a number") from None
            if not math.isfinite(v):
                raise _refuse(path, f"line {k + 3} column {j + 1}: {cell.strip()[:40]!r} is not finite")
            data[k, j] = v
    return data


def parse_log(text: str, path, n_joints: int, current_limit_A) -> Log:
    """A :class:`Log` from the CSV ``text`` of ``path`` for a device with ``n_joints``
    motors whose commanded current is clamped at ``current_limit_A`` (A; one number, or one per
    motor where they differ). Raises
    FileDamaged (field ``LOG``) naming the first problem (module docstring)."""
    lines = [ln.rstrip("\r") for ln in text.split("\n")]
    while lines and not lines[-1].strip():
        lines.pop()
    if not lines:
        raise _refuse(path, "is empty (expected a '# ... design hash sha256:...' line, the columns, rows)")
    m = HASH.search(lines[0]) if lines[0].startswith("#") else None
    if m is None:
        raise _refuse(path, "has no design hash: line 1 must be a '#' comment naming 'sha256:<64 hex>'")
    want = columns(n_joints)
    got = [c.strip() for c in lines[1].split(",")] if len(lines) > 1 else []
    if got != want:
        raise _refuse(path, f"has the columns {','.join(got)[:120]!r}; this {n_joints}-motor device "
                            f"logs {','.join(want)!r}")
    if len(lines) < 3:
        raise _refuse(path, "has no rows (only the header)")
    data = _rows(lines[2:], path, len(want))
    t, counts, cur = data[:, 0], data[:, 1:1 + n_joints], data[:, 1 + n_joints:]
    dt = np.diff(t)
    if np.any(dt <= 0):
        k = int(np.argmax(dt <= 0))
        raise _refuse(path, f"time is not increasing: line {k + 4} has t_s = {float(t[k + 1])!r} after {float(t[k])!r}")
    if np.any(counts != np.round(counts)):
        k = int(np.argmax(np.any(counts != np.round(counts), axis=1)))
        raise _refuse(path, f"line {k + 3}: encoder counts must be integers (raw counter values)")
    lim = np.broadcast_to(np.asarray(current_limit_A, float), (n_joints,))
    at_clamp = np.abs(cur) >= lim * (1.0 - 1e-9)
    frac = float(at_clamp.any(axis=1).mean())
    if frac > IDENT_SATURATION_FRACTION_MAX:
        said = " / ".join(f"{x:.4g}" for x in dict.fromkeys(lim.tolist()))
        raise _refuse(path, f"is saturated: the current is at the {said} A limit in "
                            f"{100 * frac:.1f} % of the rows (at most "
                            f"{100 * IDENT_SATURATION_FRACTION_MAX:g} %): lower the excitation or free the handle")
    return Log(t, counts.astype(np.int64), cur, m.group(1), lines[0])
