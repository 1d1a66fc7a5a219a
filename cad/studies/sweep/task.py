"""One sweep variant: load, validate, build at the fidelity, check against the targets.

Runs inside a Dask worker process. It computes exactly what ``hapticad check`` computes
(:func:`cad.families.fourbar.inertia.target_values`, as :func:`cad.api.check`), so a row equals a separate check of the
variant. A variant that cannot be evaluated (bad combination, parts that cannot be
built, an interference) returns a row with status ``error`` and the one-line error;
it never raises.
"""

from __future__ import annotations

import os
import time
from typing import Any

from cad.checks import evaluate, merge_targets
from cad.design import parse_design
from cad.design.fourbar import FourBarDesign
from cad.design.targets import TARGET_KEYS
from cad.errors import DesignError, HapticadError
from cad.families.fourbar.inertia import target_values

#: metric and target columns of every row (float, NaN when not computed): every target key
#: of :data:`cad.design.targets.TARGET_KEYS` plus the apparent-mass bounds without a target key
VALUE_KEYS: tuple[str, ...] = tuple(dict.fromkeys(
    (*TARGET_KEYS[:8], "M22_min_g", *TARGET_KEYS[8:])))


def evaluate_variant(raw: dict[str, Any], source: str, fidelity: str, cli_targets: tuple) -> dict[str, Any]:
    """Row of one variant: ``status`` (ok | missed | error), ``error``, ``targets_missed``,
    every :data:`VALUE_KEYS` value, ``wall_s``, ``cpu_s`` (the worker's CPU time for it)
    and ``worker`` (pid).

    ``ok``: evaluated and every target met; ``missed``: evaluated, some target missed;
    ``error``: not evaluable, or (when the clearance is computed) parts overlap.
    """
    import multiprocessing

    if multiprocessing.current_process().name != "MainProcess":
        os.environ.setdefault("HAPTICAD_FORK", "0")  # no fork() inside a threaded worker process
    t0, c0 = time.perf_counter(), time.process_time()
    row: dict[str, Any] = {"status": "error", "error": "", "targets_missed": ""}
    try:

        d = parse_design(raw, source)
        if not isinstance(d, FourBarDesign):
            raise DesignError("mechanism.family", "sweep works on four-bar designs")
        targets = merge_targets(d.targets, cli_targets)
        need_clear = fidelity == "fabrication" or any(t.key == "min_clearance_mm" for t in targets)
        values, report = target_values(d, fidelity, need_clear)
        rows = evaluate(targets, values)
        row.update({k: values.get(k, float("nan")) for k in VALUE_KEYS})
        missed = [r.key for r in rows if not r.ok]
        row["status"] = "missed" if missed else "ok"
        row["targets_missed"] = ",".join(missed)
        overlap = report.get("overlap_volume_mm3") or 0.0
        if overlap > 0:  # parts collide somewhere in the stroke: not a buildable variant
            row["status"] = "error"
            row["error"] = (f"interference: {overlap:.3g} mm^3 of overlap, min clearance "
                            f"{values.get('min_clearance_mm', float('nan')):.3g} mm")
    except Exception as exc:  # every failure is a row, never the end of the sweep

        msg = " ".join(str(exc).split())
        row["error"] = msg if isinstance(exc, HapticadError) else f"{type(exc).__name__}: {msg}"
    row["wall_s"] = time.perf_counter() - t0
    row["cpu_s"] = time.process_time() - c0
    row["worker"] = os.getpid()
    return row
