"""The toy family's layout, build stages, datasheet rows and target values (module docstring
of the package). A block (on body ``slider``) rides on a base plate (``ground``) over
``travel_mm`` along x; both are made of aluminium 6061."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cad.assembly.model import AssemblyModel
from cad.datasheet import row
from cad.datasheet.limits import Limit
from cad.errors import DesignError
from cad.parts import PartInstance, PartKind
from cad.pipeline.run import Stages, run_family

MATERIAL = "aluminium-6061"
BASE_MM = (80.0, 30.0, 4.0)


def _box(x: float, y: float, z: float):
    import build123d as bd

    return bd.Box(x, y, z, align=(bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN)).wrapped


def _slide(design, x_mm: float) -> np.ndarray:
    tf = np.eye(4)
    tf[0, 3], tf[2, 3] = x_mm, BASE_MM[2]
    return tf


def assemble(design, fidelity: str = "fabrication") -> AssemblyModel:
    """The base and the block, the block swept over its travel (5 poses)."""
    base = PartKind("toy_base", _box(*BASE_MM), MATERIAL, True, plate=True,
                    description="base plate", process="machined")
    block = PartKind("toy_block", _box(*design.block_mm), MATERIAL, True,
                     description="slider block", process="machined")
    xs = np.linspace(-design.travel_mm / 2, design.travel_mm / 2, 5)
    inst = (PartInstance("base", base, "ground", np.eye(4)),
            PartInstance("block", block, "slider", np.eye(4)))
    return AssemblyModel(design, inst, {"ground": np.eye(4), "slider": _slide(design, 0.0)},
                         motion={"slider": np.stack([_slide(design, x) for x in xs])},
                         pose_labels=tuple(f"x = {x:.1f} mm" for x in xs))


def _interference(b):
    from cad.assembly import interference as itf

    rep = itf.check_model(b.model, fail_fast=not b.allow_interference, same_body=b.same_body())
    if not b.allow_interference:
        itf.raise_on_collision(rep, 0.0)
    return rep.as_dict()


def _report(b) -> dict:
    mass_g = b.bodies["slider"].mass_kg * 1e3
    return {"notes": [f"slider block of {mass_g:.1f} g"]}


def _check_options(design, fidelity, phi1_deg, formats) -> None:
    if phi1_deg is not None:
        raise DesignError("--phi1-deg", "a slider has no crank")


STAGES = Stages(
    check_options=_check_options, assemble=assemble, interference=_interference,
    report=_report, md_rows=lambda r: [("moving mass", f"{r['moving_mass_g']:.1f} g")],
    preview_title=lambda b: f"{b.design.name}: toy slider", motion_label="travel",
    stroke=lambda d: {"ground": np.stack([np.eye(4)] * 3),
                      "slider": np.stack([_slide(d, x) for x in np.linspace(-1, 1, 3)])})


def build(design, out_dir: Path, formats: set[str], *, fidelity: str = "fabrication",
          allow_interference: bool = False, progress=None, phi1_deg: float | None = None) -> dict:
    """One call to the build driver."""
    return run_family(STAGES, design, out_dir, formats, fidelity=fidelity,
                      allow_interference=allow_interference, progress=progress, phi1_deg=phi1_deg)


def rows_and_limits(design, report: dict, out_dir=None, simulate_wall: bool = True):
    """One datasheet row (the moving mass from the solids) and its limit (<= 100 g)."""
    m = report.get("moving_mass_g")
    rows = [row("moving_mass_g", "moving mass", m, "g", "the block's solid x density")]
    limits = {"moving_mass_g": Limit("<=", 100.0, "a light slider", "mechanism.block_mm")}
    return rows, limits, []


def target_values(design, fidelity: str, wanted: set[str]) -> tuple[dict, dict]:
    """The moving mass by hand: the block's volume x the density of aluminium 6061."""
    from cad.data.materials import get_material

    x, y, z = design.block_mm
    rho = get_material(MATERIAL).density_kg_m3
    return {"moving_mass_g": x * y * z * 1e-9 * rho * 1e3}, {}


def parse_free(spec: str, design):
    raise DesignError("--free", "the toy slider has no free parameter")
