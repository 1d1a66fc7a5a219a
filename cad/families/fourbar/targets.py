"""Values of a four-bar design for ``hapticad check`` / ``fit`` targets (the family's
:class:`cad.families.protocol.TargetHooks`): the inertia model from the solids and the
linkage metrics always, a build (no exports) when a target needs the clearance or the
structure, the datasheet when a target is a datasheet figure only it computes."""

from __future__ import annotations

from cad.datasheet.limits import DATASHEET_TARGETS
from cad.datasheet.run import device_datasheet
from cad.errors import DesignError
from cad.families.fourbar.inertia import target_values
from cad.studies.codesign.report import optimize_fourbar
from cad.studies.fit import precad_checks

#: Target keys that need a build (the interference sweep, the structure model).
BUILD_KEYS = frozenset({"min_clearance_mm", "first_mode_Hz", "max_stress_MPa",
                        "compliance_x_um_per_N", "compliance_z_um_per_N"})


def check_values(design, fidelity: str, wanted: set[str]) -> tuple[dict, dict]:
    """(flat values, inertia model report) of ``design`` for the ``wanted`` target keys
    (:func:`cad.families.fourbar.inertia.target_values`; the datasheet's figures added for
    wanted keys only it has). Raises what the build raises (DesignError, GeometryError)."""
    values, report = target_values(design, fidelity, bool(wanted & BUILD_KEYS))
    if wanted & (set(DATASHEET_TARGETS) - BUILD_KEYS):  # figures only the datasheet has
        for r in device_datasheet(design, fidelity)["rows"]:
            if r["value"] is not None and r["key"] in DATASHEET_TARGETS:
                values.setdefault(r["key"], r["value"])
    return values, report


def fit_values(design, fidelity: str, wanted: set[str]) -> tuple[dict, dict]:
    """(flat values, report) of one ``fit`` candidate: the pre-CAD checks
    (:func:`cad.studies.fit.precad_checks`) and the inertia model with the clearance build
    (every candidate meets the default limits, clearance included)."""
    values, report = target_values(design, fidelity, True)
    return {**precad_checks(design)[0], **values}, report


def optimize(design, options: dict) -> dict:
    """``hapticad optimize`` of a four-bar: the co-design search minimising the apparent mass
    (:func:`cad.studies.codesign.report.optimize_fourbar`). ``options`` as
    :attr:`cad.families.protocol.FamilyPackage.optimize`. Raises DesignError naming
    ``--method`` (a pantograph flag) or ``--objective``."""
    if options.get("method") is not None:
        raise DesignError("--method", f"{options['method']!r} is for pantograph designs; a "
                                      "four-bar takes --objective min-apparent-mass")
    objective = options.get("objective") or "min-apparent-mass"
    if objective != "min-apparent-mass":
        raise DesignError("--objective", f"must be min-apparent-mass, got {objective!r}")
    rep, _ = optimize_fourbar(design, objective, options["trials"], options["seed"],
                              options["exact_top"], None, None, None, options["proportions_tol"],
                              options["starts"], options["beat_prototype"], options.get("where"))
    return rep
