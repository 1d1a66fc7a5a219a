"""The handle at the coupler point P: a built-in knob or a user script (build123d or cadquery).

Built-in knob (frame: z = 0 on the coupler's top face, axis through P, z up): a
cylinder of ``handle_diameter_mm`` x ``handle_height_mm`` with a counterbore from the
top down to a floor, through which an ISO 4762 screw goes into the tapped coupler
(nothing hangs under the coupler at P). The top edge round (``handle_fillet_mm``) is
cosmetic and is left out at ``inertia`` and ``preview`` fidelity.

User script (``parts.handle_script``): a Python file run with :func:`runpy.run_path`
in a child process (:mod:`cad.parts.handle_runner`, time limit
``HAPTICAD_SCRIPT_TIMEOUT_S``, default 300 s) only when the user opted in
(:func:`script_policy`: ``--allow-scripts`` or ``HAPTICAD_ALLOW_SCRIPTS=1`` for a script
inside the design's folder, ``--allow-scripts-anywhere`` or
``HAPTICAD_ALLOW_SCRIPTS=anywhere`` for any path). The script defines
``make_handle(params: dict)`` (preferred) or a module-level ``handle`` or ``result``; it may return a build123d object (Part, Solid, BuildPart) or a cadquery
object (Workplane, Shape); both become an OCP shape (:func:`cad.export.shapes.to_topods`)
and go through the same pipeline. ``params`` has ``diameter_mm``, ``height_mm``,
``screw_clearance_mm``, ``counterbore_mm``, ``floor_mm``, all from ``[parts]``.
The script's frame is the knob's frame above.
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import cad
from cad.data.catalog import clearance_hole_mm, get_cap_screw
from cad.errors import DesignError, FileRefused
from cad.export.shapes import count_solids, is_valid
from cad.io import guard
from cad.parts.part_cache import part_cached


def handle_params(parts, floor_mm: float) -> dict:
    cs = get_cap_screw(parts.handle_screw, "parts.handle_screw")
    return {
        "diameter_mm": parts.handle_diameter_mm,
        "height_mm": parts.handle_height_mm,
        "screw_clearance_mm": clearance_hole_mm(parts.handle_screw),
        "counterbore_mm": cs.dk_mm + 1.0,
        "floor_mm": floor_mm,
    }


@part_cached
def knob_shape(parts, floor_mm: float, cosmetic: bool = True):
    """Built-in knob (module docstring); ``cosmetic=False`` drops the top round."""
    from build123d import Align, Axis, Cylinder, Pos, fillet

    p = handle_params(parts, floor_mm)
    a = (Align.CENTER, Align.CENTER, Align.MIN)
    h = p["height_mm"]
    k = Cylinder(p["diameter_mm"] / 2, h, align=a)
    if cosmetic and parts.handle_fillet_mm > 0:
        k = fillet(k.edges().group_by(Axis.Z)[-1], parts.handle_fillet_mm)
    k = k.cut(Cylinder(p["screw_clearance_mm"] / 2, h, align=a),
              Pos(0, 0, floor_mm) * Cylinder(p["counterbore_mm"] / 2, h - floor_mm, align=a))
    return k.solids()[0].wrapped


#: ``HAPTICAD_ALLOW_SCRIPTS`` values: design folder only / any path.
_ALLOW_FOLDER = ("1", "yes", "on", "true", "folder")
_ALLOW_ANYWHERE = ("anywhere",)
#: Set by the CLI flags (``--allow-scripts`` -> "folder", ``--allow-scripts-anywhere``
#: -> "anywhere"); None: the environment decides.
_POLICY_OVERRIDE: list[str | None] = [None]
#: Default time limit of one script run (s); ``HAPTICAD_SCRIPT_TIMEOUT_S`` overrides.
SCRIPT_TIMEOUT_S = 300.0


def script_policy() -> str:
    """"off", "folder" (scripts inside the design's folder) or "anywhere"."""
    if _POLICY_OVERRIDE[0] is not None:
        return _POLICY_OVERRIDE[0]
    env = os.environ.get("HAPTICAD_ALLOW_SCRIPTS", "").strip().lower()
    if env in _ALLOW_ANYWHERE:
        return "anywhere"
    return "folder" if env in _ALLOW_FOLDER else "off"


def set_script_policy(flag: bool, anywhere: bool = False) -> None:
    """The CLI flags widen :func:`script_policy` (never narrow it) for this command;
    :func:`cad.cli.app.run` clears the override when the command ends."""
    env = script_policy()
    if anywhere or env == "anywhere":
        _POLICY_OVERRIDE[0] = "anywhere"
    elif flag or env == "folder":
        _POLICY_OVERRIDE[0] = "folder"


def clear_script_policy() -> None:
    _POLICY_OVERRIDE[0] = None


def resolve_script(parts, design_source: str) -> Path | None:
    """Absolute path of ``parts.handle_script`` (relative to the design file), checked.

    Raises :class:`DesignError` (``parts.handle_script``) when the file is missing, when
    scripts are not allowed (:func:`script_policy` "off": no ``--allow-scripts``, no
    ``HAPTICAD_ALLOW_SCRIPTS``), or when the resolved script (symbolic links followed)
    lies outside the design's folder and the policy is not "anywhere".
    """
    if parts.handle_script is None:
        return None
    folder = Path(design_source).resolve().parent
    p = Path(parts.handle_script)
    if not p.is_absolute():
        p = folder / p
    policy = script_policy()
    if policy == "off":
        raise DesignError(
            "parts.handle_script",
            f"the design wants to run the Python script {p}; design scripts run only with "
            "--allow-scripts (build, check, fit, optimize) or HAPTICAD_ALLOW_SCRIPTS=1",
        )
    if not p.is_file():
        raise DesignError("parts.handle_script", f"file not found: {p}")
    real = p.resolve()
    if policy != "anywhere" and folder not in real.parents:
        raise DesignError(
            "parts.handle_script",
            f"{real} is outside the design's folder {folder}; allowed only with "
            "--allow-scripts-anywhere or HAPTICAD_ALLOW_SCRIPTS=anywhere",
        )
    return real


def script_timeout_s() -> float:
    """``HAPTICAD_SCRIPT_TIMEOUT_S`` (s, > 0) or :data:`SCRIPT_TIMEOUT_S`."""
    env = os.environ.get("HAPTICAD_SCRIPT_TIMEOUT_S")
    if env is None:
        return SCRIPT_TIMEOUT_S
    try:
        t = float(env)
    except ValueError:
        t = float("nan")
    if not 0 < t < 1e6:
        raise DesignError("HAPTICAD_SCRIPT_TIMEOUT_S", f"must be a number of seconds > 0, got {env!r}")
    return t


def script_sha256(path: Path) -> str:
    """sha256 of the handle script, read through :mod:`cad.io.guard` (a regular file <= 1 MiB)."""
    return hashlib.sha256(guard.read_bytes(path, "script", "parts.handle_script")).hexdigest()


def _run_script(path: Path, params: dict, workdir: Path) -> Path:
    """Run the script in a child process (:mod:`cad.parts.handle_runner`); the BREP path."""
    out, result = workdir / "handle.brep", workdir / "result.json"
    env = dict(os.environ)
    root = str(Path(cad.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join([root] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    env["HAPTICAD_PARENT_PID"] = str(os.getpid())
    cmd = [sys.executable, "-m", "cad.parts.handle_runner", str(path), json.dumps(params),
           str(out), str(result)]
    timeout = script_timeout_s()
    print(f"hapticad: running design script {path}", file=sys.stderr, flush=True)
    try:
        proc = subprocess.run(cmd, env=env, capture_output=True, timeout=timeout,
                              stdin=subprocess.DEVNULL, check=False)
    except subprocess.TimeoutExpired:
        raise DesignError(
            "parts.handle_script",
            f"{path} did not finish within {timeout:g} s (HAPTICAD_SCRIPT_TIMEOUT_S); stopped",
        ) from None
    try:
        doc = guard.load_json(result, "json", "parts.handle_script")
        doc = doc if isinstance(doc, dict) else {"error": f"result {doc!r} is not an object"}
    except FileRefused:
        tail = (proc.stderr.decode("utf-8", "replace").strip().splitlines() or [""])[-1]
        raise DesignError(
            "parts.handle_script",
            f"{path} ended (exit status {proc.returncode}) without returning a shape"
            + (f": {tail}" if tail else ""),
        ) from None
    if "error" in doc:
        raise DesignError("parts.handle_script", str(doc["error"]))
    return out


def user_handle_shape(path: Path, params: dict):
    """Run a user handle script in a child process (time limit :func:`script_timeout_s`)
    and return its solid as an OCP shape (module docstring). Every failure -- an
    exception, ``sys.exit``, a crash, no shape, the time limit -- is a
    :class:`DesignError` naming the script."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepTools import BRepTools
    from OCP.TopoDS import TopoDS_Shape

    path = Path(path)
    guard.check_file(path, "script", "parts.handle_script")  # a regular file <= 1 MiB
    with tempfile.TemporaryDirectory(prefix="hapticad-script-") as tmp:
        brep = _run_script(path, params, Path(tmp))
        shape = TopoDS_Shape()
        if not BRepTools.Read_s(shape, str(brep), BRep_Builder()) or shape.IsNull():
            raise DesignError("parts.handle_script", f"{path.name}: its shape could not be read back")
    if count_solids(shape) < 1 or not is_valid(shape):
        raise DesignError("parts.handle_script", f"{path.name} must return a valid solid")
    return shape
