"""The handle at the coupler point P: a built-in knob or a user script (build123d or cadquery).

Built-in knob (frame: z = 0 on the coupler's top face, axis through P, z up): a
cylinder of ``handle_diameter_mm`` x ``handle_height_mm`` with a counterbore from the
top down to a floor, through which an ISO 4762 screw goes into the tapped coupler
(nothing hangs under the coupler at P). The top edge round (``handle_fillet_mm``) is
cosmetic and is left out at ``inertia`` and ``preview`` fidelity.

User script (``parts.handle_script``): a Python file run with :func:`runpy.run_path`
that defines ``make_handle(params: dict)`` (preferred) or a module-level ``handle`` or
``result``; it may return a build123d object (Part, Solid, BuildPart) or a cadquery
object (Workplane, Shape); both become an OCP shape (:func:`cad.export.shapes.to_topods`)
and go through the same pipeline. ``params`` has ``diameter_mm``, ``height_mm``,
``screw_clearance_mm``, ``counterbore_mm``, ``floor_mm``, all from ``[parts]``.
The script's frame is the knob's frame above.
"""

from __future__ import annotations

import hashlib
import runpy
from pathlib import Path

from cad.errors import DesignError, GeometryError
from cad.parts.catalog import clearance_hole_mm, get_cap_screw
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


def resolve_script(parts, design_source: str) -> Path | None:
    """Absolute path of ``parts.handle_script`` (relative to the design file), checked."""
    if parts.handle_script is None:
        return None
    p = Path(parts.handle_script)
    if not p.is_absolute():
        p = Path(design_source).resolve().parent / p
    if not p.is_file():
        raise DesignError("parts.handle_script", f"file not found: {p}")
    return p.resolve()


def script_sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def user_handle_shape(path: Path, params: dict):
    """Run a user handle script and return its solid as an OCP shape (module docstring)."""
    from cad.export.shapes import count_solids, is_valid, to_topods

    try:
        ns = runpy.run_path(str(path), run_name="hapticad_handle")
    except Exception as exc:  # a user script may raise anything: report it as bad input
        raise DesignError(
            "parts.handle_script", f"{path.name} failed: {type(exc).__name__}: {exc}"
        ) from None
    if callable(ns.get("make_handle")):
        try:
            obj = ns["make_handle"](dict(params))
        except Exception as exc:
            raise DesignError(
                "parts.handle_script",
                f"{path.name}: make_handle() failed: {type(exc).__name__}: {exc}",
            ) from None
    elif "handle" in ns:
        obj = ns["handle"]
    elif "result" in ns:
        obj = ns["result"]
    else:
        raise DesignError(
            "parts.handle_script", f"{path.name} defines no make_handle(params), handle or result"
        )
    try:
        shape = to_topods(obj, f"parts.handle_script ({path.name})")
    except GeometryError as exc:
        raise DesignError("parts.handle_script", str(exc)) from None
    if count_solids(shape) < 1 or not is_valid(shape):
        raise DesignError("parts.handle_script", f"{path.name} must return a valid solid")
    return shape
