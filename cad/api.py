"""The supported Python API: what the CLI does, as functions on plain data.

Everything else in :mod:`cad` is internal and may change. Lengths in mm, masses in g or kg
and inertias in kg m^2 as the dict keys say; frames as in docs/conventions.md.

>>> import cad
>>> d = cad.load_design("designs/hoeken.toml")
>>> round(cad.analyze(d)["stroke_mm"], 2)
48.87

The build function is ``build_design`` (``cad.pipeline`` is the build subpackage).

Importing :mod:`cad` stays light: CAD libraries load on the first call that needs them
(:func:`build_design`, :func:`check`, :func:`mass_properties` of a STEP file).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any


def load_design(path: str | Path):
    """Read and validate a TOML design (any family).

    Returns a frozen design object (``FourBarDesign``, ``PantographDesign`` or
    ``PowerMouseDesign``). Raises :class:`cad.errors.DesignError` (a ``ValueError``) naming
    the dotted field, the value and the reason.
    """
    from cad.design import load_design as _load

    return _load(path)


def analyze(design, samples: int | None = None, inertia: dict[str, float] | None = None) -> dict:
    """Four-bar metrics (Hoeken paper Tables I/II), range check, apparent mass; no CAD.

    ``inertia``: optional ``{"H11": ..., "H12": ..., "H22": ..., "H33": ...}`` in kg m^2
    (Hoeken paper eqs 16-19). Returns the ``hapticad analyze --json`` object (schema: docs/commands.md).
    Raises DesignError for a non-four-bar design.
    """
    from cad.analysis import analyze as _analyze
    from cad.design.fourbar import FourBarDesign
    from cad.dynamics.inertia import InertiaCoefficients
    from cad.errors import DesignError

    if not isinstance(design, FourBarDesign):
        raise DesignError("mechanism.family", "analyze works on four-bar designs; use gii()")
    H = None if inertia is None else InertiaCoefficients(
        inertia["H11"], inertia["H12"], inertia["H22"], inertia["H33"])
    return _analyze(design, samples=samples, inertia=H)


def build_design(design, out_dir: str | Path, formats=("step", "stl", "dxf"),
                 fidelity: str = "fabrication", **options: Any) -> dict:
    """Build the parts, the posed assembly and the exports into ``out_dir``; the report dict.

    ``formats``: any of the ``hapticad build --formats`` names. ``options``: the keyword
    options of :func:`cad.pipeline.build_design` (``allow_interference``, ``phi1_deg``,
    ``use_cache`` ...). Raises a :class:`cad.errors.HapticadError` subclass on bad input, a
    collision or a failed CAD operation; ``out_dir`` is then left as it was.
    """
    from cad.pipeline import build_design as _build

    return _build(design, Path(out_dir), set(formats), fidelity=fidelity, **options)


def check(design, targets: tuple[str, ...] | list[str] = (), fidelity: str = "inertia",
          merge: bool = False) -> dict:
    """Computed values of a design against targets (four-bars and pantograph families).

    Four-bars: inertia, apparent mass and metrics from the solids. Pantograph families: the
    GII (isotropy paper eq 5) and, for designs that build, the effective mass at home and
    the moving mass from the solids. ``targets``: ``"KEY=VALUE"``, ``"KEY<=V"``, ``"KEY>=V"``
    strings (a single string is one target). Which targets are checked is the caller's choice: none given, the design's
    ``[targets]``; given, **only those** (``merge=False``), or the design's with the given ones
    replacing those of the same key (``merge=True``, what ``hapticad check --target`` does).
    Returns the ``hapticad check --json`` object: ``ok``, ``rows`` (``key``, ``computed``,
    ``target`` as data, ``margin``, ``gap_rel``), ``computed``, ``targets_checked`` (the keys
    of ``rows``, in order) and ``targets_source`` (``design``, ``given`` or ``design+given``).
    Raises DesignError when there are no targets or the family has no check.
    """
    from cad.checks import evaluate, merge_targets
    from cad.design.fourbar import FourBarDesign
    from cad.design.targets import PANTOGRAPH_TARGET_KEYS, TARGET_KEYS, parse_cli_target
    from cad.errors import DesignError

    if fidelity not in ("inertia", "fabrication"):
        raise DesignError("--fidelity", f"must be inertia or fabrication, got {fidelity!r}")
    four_bar = isinstance(design, FourBarDesign)
    if not four_bar and design.family not in ("pantograph", "twin-pantograph", "haptic-pen"):
        from cad.cli.families import refusal

        raise DesignError("mechanism.family", refusal("check", design.family))
    keys = TARGET_KEYS if four_bar else PANTOGRAPH_TARGET_KEYS
    if isinstance(targets, str):  # one "KEY=VALUE", not its characters
        targets = (targets,)
    given = tuple(parse_cli_target(t, keys) for t in targets)
    merged = merge_targets(design.targets, given) if merge or not given else given
    source = "design+given" if merge and given else ("given" if given else "design")
    if not merged:  # no targets: the default limits of the datasheet (cad.datasheet.limits)
        from cad.datasheet.run import device_datasheet, limit_rows

        ds = device_datasheet(design, fidelity)
        rows = limit_rows(ds)
        return {"name": design.name, "ok": all(r["ok"] for r in rows), "fidelity": fidelity,
                "rows": rows, "computed": {r["key"]: r["value"] for r in ds["rows"]},
                "budget": None, "targets_checked": [r["key"] for r in rows],
                "targets_source": "default limits",
                "checked": "default limits (no [targets]): cad/datasheet/limits.py"}
    wanted = {t.key for t in merged}
    if four_bar:
        from cad.pipeline.inertia import target_values

        build_keys = {"min_clearance_mm", "first_mode_Hz", "max_stress_MPa",
                      "compliance_x_um_per_N", "compliance_z_um_per_N"}
        values, report = target_values(design, fidelity, bool(wanted & build_keys))
        from cad.datasheet.limits import DATASHEET_TARGETS

        if wanted & (set(DATASHEET_TARGETS) - build_keys):  # figures only the datasheet has
            from cad.datasheet.run import device_datasheet

            for r in device_datasheet(design, fidelity)["rows"]:
                if r["value"] is not None and r["key"] in DATASHEET_TARGETS:
                    values.setdefault(r["key"], r["value"])
    else:
        from cad.pipeline.inertia import pantograph_target_values

        values, report = pantograph_target_values(design, fidelity, wanted)
    rows = evaluate(merged, values)
    return {"name": design.name, "ok": all(r.ok for r in rows), "fidelity": fidelity,
            "targets_checked": [r.key for r in rows], "targets_source": source,
            "rows": [r.as_dict() for r in rows], "computed": values,
            "budget": report.get("budget")}


def mass_properties(path: str | Path, density_kg_m3: float | None = None,
                    material: str | None = None) -> dict:
    """Mass, COM (mm, file frame) and inertia tensor about the COM (kg m^2) of a STEP or STL.

    Returns the ``hapticad massprops --json`` object, ``warnings`` included (e.g. a cavity
    shell read as a cavity, duplicate facets dropped, a mesh too small for mm). Without
    density or material the default material is used (a note in ``notes``). Raises
    DesignError / MeshError / GeometryError naming the file and the fault.
    """
    from cad.cli.cmd_massprops import compute
    from cad.design import bounds

    dens = None if density_kg_m3 is None else str(density_kg_m3)
    bounds.reset()  # this call's warnings only, as one CLI command
    out, notes = compute(Path(path), dens, material)
    return {**out, "notes": notes, "warnings": bounds.collected()}


def gii(design) -> dict:
    """Global isotropy index (isotropy paper eq 5) of a pantograph-family design.

    Returns the ``hapticad gii --json`` object (``gii``, ``sigma_min``, ``sigma_max`` and
    where they occur). Raises DesignError for other families.
    """
    from cad.cli.cmd_gii import PANTOGRAPH_FAMILIES, gii_report
    from cad.errors import DesignError

    if getattr(design, "family", None) not in PANTOGRAPH_FAMILIES:
        raise DesignError("mechanism.family", f"gii needs one of {', '.join(PANTOGRAPH_FAMILIES)}")
    return gii_report(design)
