"""Child process that runs one user handle script (``python -m cad.parts.handle_runner``).

Arguments: ``SCRIPT PARAMS_JSON OUT_BREP RESULT_JSON``. Runs ``SCRIPT`` with
:func:`runpy.run_path`, takes ``make_handle(params)`` (or a module-level ``handle`` /
``result``), converts it to an OCP shape and writes it to ``OUT_BREP``
(``BRepTools.Write``); then writes ``{"ok": true}`` or ``{"error": "..."}`` to
``RESULT_JSON``. A script that exits, crashes the interpreter or never returns leaves no
result file: the parent (:func:`cad.parts.handle.user_handle_shape`) reports that.
The process is killed when its parent dies (``prctl(PR_SET_PDEATHSIG)`` on Linux).
"""

from __future__ import annotations

import json
import os
import sys

from cad.errors import GeometryError
from cad.export.shapes import to_topods
from cad.io.signals import child_dies_with_parent


def _run(script: str, params: dict, out_brep: str) -> str | None:
    """None on success (shape written), else the error message."""
    import runpy

    name = os.path.basename(script)
    try:
        ns = runpy.run_path(script, run_name="hapticad_handle")
    except SystemExit as exc:
        return f"{name} called sys.exit({exc.code!r}) instead of returning a shape"
    except Exception as exc:  # noqa: BLE001 - a user script may raise anything
        return f"{name} failed: {type(exc).__name__}: {exc}"
    if callable(ns.get("make_handle")):
        try:
            obj = ns["make_handle"](dict(params))
        except SystemExit as exc:
            return f"{name}: make_handle() called sys.exit({exc.code!r}) instead of returning a shape"
        except Exception as exc:  # noqa: BLE001
            return f"{name}: make_handle() failed: {type(exc).__name__}: {exc}"
    elif "handle" in ns:
        obj = ns["handle"]
    elif "result" in ns:
        obj = ns["result"]
    else:
        return f"{name} defines no make_handle(params), handle or result"
    try:
        shape = to_topods(obj, f"parts.handle_script ({name})")
    except GeometryError as exc:
        return str(exc)
    from OCP.BRepTools import BRepTools

    if not BRepTools.Write_s(shape, out_brep):
        return f"{name}: cannot write its shape"
    return None


def main(argv: list[str]) -> int:
    script, params_json, out_brep, result_json = argv
    child_dies_with_parent(int(os.environ.get("HAPTICAD_PARENT_PID", os.getppid())))
    err = _run(script, json.loads(params_json), out_brep)
    doc = {"ok": True} if err is None else {"error": err}
    with open(result_json, "w", encoding="utf-8") as fh:
        json.dump(doc, fh)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
