"""``hapticad swap DESIGN --to FAMILY [--out NEW.toml] [--json] [--build]``.

Keeps the joint hardware (the whole ``[parts]`` table: bearings, pins, spacers, motor
mount, base interface, handle) and produces the bar set of another straight-line family
(hoeken, roberts, chebyshev, chebyshev-v) scaled to the same stroke ("provided a
convenient design of the revolute joints, the different straight line mechanisms can
be obtained by fabricating the adequate set of bars", Hoeken paper §III.A). Prints the
old and new metrics side by side and writes the new design atomically (default: beside
DESIGN as ``<stem>_<family>.toml``); never over DESIGN itself, and it says ``replaced``
when the file existed (:func:`cad.io.outdir.check_out_file`). The build's pre-CAD layout
check runs on the new bar set before anything is written (:func:`replan`): a copied
``parts.layer_order`` that is not clear there is dropped (with a warning), and a bar set
no layer order clears is refused (exit 2, the build's one-line error, nothing written).
``--build`` also builds it (and fails if anything collides).
"""

from __future__ import annotations

import copy
from pathlib import Path

import typer

from cad.cli.app import print_json

SWAP_FAMILIES = ("hoeken", "roberts", "chebyshev", "chebyshev-v")
#: Sections of a design that describe the old mechanism only and are dropped by a swap.
DROPPED_SECTIONS = ("inertia",)


def stroke_of(design) -> float:
    """|P(phi1_max) - P(phi1_min)| of a design, mm."""
    import numpy as np

    from cad.kinematics.fourbar import solve

    P = solve(design.linkage, np.array([design.phi1_min_rad, design.phi1_max_rad])).P_mm
    return float(np.linalg.norm(P[1] - P[0]))


def swap_raw(design, family: str, out_path: Path) -> dict:
    """The raw TOML mapping of ``design`` swapped to ``family`` (same stroke, same [parts])."""
    from cad.errors import DesignError

    if family not in SWAP_FAMILIES:
        raise DesignError("--to", f"must be one of {', '.join(SWAP_FAMILIES)}, got {family!r}")
    from cad.design.writer import drop_source_targets, rebase_paths

    raw = copy.deepcopy(design.raw)
    for s in DROPPED_SECTIONS:
        raw.pop(s, None)
    drop_source_targets(raw)
    mech = raw.get("mechanism", {})
    force = mech.get("force_N", design.force_N)
    raw["mechanism"] = {"family": family, "stroke_mm": stroke_of(design), "force_N": force}
    raw["name"] = f"{design.name.split('__')[0]}__{family.replace('-', '_')}"
    raw["description"] = (
        f"{family} bar set on the joint hardware of {Path(design.source).name} "
        f"(hapticad swap, stroke {stroke_of(design):.3f} mm)"
    )
    return rebase_paths(raw, design.source, out_path)


def replan(raw: dict, target: Path, family: str):
    """Parse the swapped ``raw`` and run the build's pre-CAD layout check on it
    (:func:`cad.families.fourbar.build.check_layout`, at the design's ``[parts]`` fidelity), so a
    swap never writes a design ``build`` refuses. A ``parts.layer_order`` copied from the
    source that is not clear for the new bar set is dropped from ``raw`` (a warning on
    stderr names it) and the planner chooses; when no layer order is clear the build's
    one-line DesignError (naming the joint, both parts and the stroke that clears) is
    raised: the CLI exits 2 and writes nothing, with no unit-slip hint about the stroke swap
    computed (:func:`cad.design.bounds.computed`)."""
    from cad.design import parse_design
    from cad.design.bounds import computed, warn
    from cad.errors import DesignError
    from cad.families.fourbar.build import check_layout

    new = parse_design(raw, str(target))
    computed(*(f"mechanism.{k}" for k in raw["mechanism"]))  # swap's numbers, not typed
    try:
        check_layout(new, new.parts.fidelity, False)
        return new
    except DesignError as e:
        if e.field != "parts.layer_order":
            raise
    order = raw["parts"].pop("layer_order")
    new = parse_design(raw, str(target))
    computed(*(f"mechanism.{k}" for k in raw["mechanism"]))
    check_layout(new, new.parts.fidelity, False)
    warn(f"parts.layer_order: {', '.join(order)} (copied from the source) is not clear for "
         f"the {family} bar set; dropped, the planner chooses the layer order")
    return new


def metric_rows(design) -> dict:
    from cad.analysis import METRIC_KEYS
    from cad.kinematics.metrics import compute_metrics

    m = compute_metrics(
        design.linkage,
        design.phi1_min_rad,
        design.phi1_max_rad,
        force_N=design.force_N,
        samples=design.samples,
    ).as_dict()
    out = {k: m[k] for k in METRIC_KEYS if k in m}
    out.update(design.resolved_linkage())
    return out


def register(app: typer.Typer) -> None:
    @app.command("swap")
    def swap_cmd(
        design: Path = typer.Argument(..., help="TOML design file (four-bar)."),
        to: str = typer.Option(..., "--to", help="hoeken | roberts | chebyshev | chebyshev-v."),
        out: Path = typer.Option(
            None, "--out", help="New design file (default <stem>_<family>.toml beside DESIGN)."
        ),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
        build: bool = typer.Option(
            False, "--build", help="Also build the new design into exports/<name>/ (name: the --out file stem)."
        ),
    ) -> None:
        """Same joint hardware, another straight-line bar set; old vs new metrics."""
        run_swap(design, to, out, json_out, build)


def run_swap(design: Path, to: str, out: Path | None, json_out: bool, build: bool) -> None:
    """``hapticad swap``: swap the bar set, check its layout, optionally build, write, print.

    Raises DesignError on bad input or a bar set no layer order clears (nothing written).
    """
    import tomli_w

    from cad.cli import flags
    from cad.design import load_design
    from cad.design.fourbar import FourBarDesign
    from cad.design.writer import dropped_targets_note
    from cad.errors import DesignError
    from cad.io.atomic import write_text_atomic
    from cad.io.outdir import check_out_file

    flags.choice("--to", to, SWAP_FAMILIES)
    flags.out_path("--out", out, folder=False)
    d = load_design(design)
    if not isinstance(d, FourBarDesign):
        from cad.cli.families import refusal

        raise DesignError("mechanism.family", refusal("swap", d.family))
    target = (
        out
        if out is not None
        else design.with_name(f"{design.stem}_{to.replace('-', '_')}.toml")
    )
    replaced = check_out_file(target, design)
    raw = swap_raw(d, to, target)
    if out is not None:  # the written file names the design (and its build folder)
        raw["name"] = out.stem
    dropped = [k for k in (d.raw.get("targets") or {}) if k not in (raw.get("targets") or {})]
    new = replan(raw, target, to)  # validates before anything is written
    plan = _layer_plan(new)
    text = tomli_w.dumps(raw)
    header = f"written by `hapticad swap {design.name} --to {to}`" + dropped_targets_note(dropped)
    old_m, new_m = metric_rows(d), metric_rows(new)
    result = {
        "old": old_m,
        "new": new_m,
        "out": str(target),
        "replaced": replaced,
        "layers": {
            "order": list(plan.order),
            "conflicts": list(plan.conflicts),
            "min_planar_clearance_mm": plan.min_planar_clearance_mm,
        },
    }
    if build:
        result["build"] = _build_swapped(new)
    # the design file last: it is the command's output (cad.io.signals commit point)
    write_text_atomic(
        target, "".join(f"# {ln}\n" for ln in header.splitlines()) + text, final=True
    )
    if json_out:
        print_json(result, sort_keys=True, default=float)
        return
    _print_swap(d, new, old_m, new_m, plan, result, replaced, target)


def _layer_plan(new):
    """The layer planner's choice for the swapped design over its interference poses."""
    import numpy as np

    from cad.assembly.layers import choose_layers
    from cad.assembly.pose import planar_transforms
    from cad.kinematics.linkgeom import link_joints_mm

    phi = np.linspace(new.phi1_min_rad, new.phi1_max_rad, new.parts.interference_poses)
    return choose_layers(link_joints_mm(new.linkage), new.parts, planar_transforms(new.linkage, phi))


def _build_swapped(new) -> dict:
    """Build the swapped design into exports/<name>/; its clearance, overlap and folder."""
    from cad.export import parse_formats
    from cad.pipeline import build_design

    build_dir = Path("exports") / new.name
    rep = build_design(new, build_dir, parse_formats(None))
    return {
        "min_clearance_mm": rep["min_clearance_mm"],
        "overlap_volume_mm3": rep["overlap_volume_mm3"],
        "out": str(build_dir),
    }


def _print_swap(d, new, old_m: dict, new_m: dict, plan, result: dict, replaced: bool, target: Path) -> None:
    """The old and new metrics side by side (a rich table), the layers and what was written."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title=f"swap {d.name} ({d.family}) -> {new.name} ({new.family}); hardware kept")
    t.add_column("quantity")
    t.add_column(d.family, justify="right")
    t.add_column(new.family, justify="right")
    for k, v in old_m.items():
        nv = new_m.get(k)
        if isinstance(v, (list, tuple)):
            t.add_row(k, " x ".join(f"{x:.1f}" for x in v), " x ".join(f"{x:.1f}" for x in nv))
        elif isinstance(v, str):
            t.add_row(k, v, str(nv))
        else:
            t.add_row(k, f"{v:.5g}", f"{nv:.5g}")
    con = Console()
    con.print(t)
    con.print(
        f"layers {', '.join(plan.order)} (bottom to top), planar clearance "
        f"{plan.min_planar_clearance_mm:.2f} mm; {'replaced' if replaced else 'wrote'} {target}"
    )
    if plan.conflicts:
        con.print(f"[yellow]warning:[/] layer conflicts: {'; '.join(plan.conflicts)}")
    if "build" in result:
        con.print(
            f"built {result['build']['out']}: min clearance {result['build']['min_clearance_mm']:.3f} mm"
        )
