"""``hapticad optimize DESIGN``: maximize the GII (pantographs) or minimize the apparent mass (four-bars).

Pantograph families: ``--method culling|brute``, isotropy paper eq (6) over the design's
``[optimize]`` candidate grid; culling (Stocco, Salcudean & Sassani 1998) returns the
brute-force optimum exactly while evaluating far fewer Jacobians.

Four-bar families: ``--objective min-apparent-mass [--trials N] [--seed S] [--exact-top K]
[--no-starts]``,
the co-design search of :mod:`cad.studies.codesign` (optuna on the cheap mass model, the best K
candidates re-evaluated on the exact solids with interference and structure).
"""

from __future__ import annotations

from pathlib import Path

import typer

from cad.cli.app import print_json
from cad.cli.families import FOUR_BARS as FOURBAR_FAMILIES
from cad.isotropy.report import optimize_report  # noqa: F401 - re-exported


def write_optimum(design, rep: dict, out: Path, command: str) -> bool:
    """Write ``design`` with its ``[mechanism]`` set to the optimum, validated first, atomically.

    The ``[optimize]`` ranges are kept (re-running reproduces the search); ``name`` becomes
    the file's stem. Raises DesignError (--out) when ``out`` is the input design itself
    (same path, symbolic or hard link). Returns True when an existing file was replaced.
    """
    import copy

    from cad.design import parse_design
    from cad.design.writer import write_design
    from cad.io.outdir import check_out_file

    replaced = check_out_file(out, Path(design.source))  # never the input design (any link)
    raw = copy.deepcopy(design.raw)
    raw["mechanism"].update(rep["best"])
    raw["name"] = out.stem
    parse_design(raw, str(out))  # its own family's schema; validated before anything is written
    write_design(out, raw, f"Optimum of `{command}`: GII {rep['gii']:.6f} ({rep['method']})"
                 + "".join(f"\n{m}" for m in rep.get("misses", ()))
                 + "".join(f"\ndefault limit missed: {w}" for w in rep.get("limit_warnings", ())))
    return replaced





def _fourbar(d, path: Path, objective: str, trials: int, seed: int, top: int, out: Path | None,
             json_out: bool, proportions_tol: float = 0.0, starts: bool = True,
             beat_prototype: bool = False, where: dict | None = None) -> None:
    """The four-bar co-design path (module docstring); exit 1 when no candidate is accepted.
    ``where``: the search on Dask (:func:`dask_where`), None in this process."""
    import sys
    import time

    from cad.studies.codesign import exact
    from cad.studies.codesign.report import optimize_fourbar

    def progress(msg):
        print(f"hapticad: {msg}", file=sys.stderr)

    from cad.io.outdir import check_out_file

    replaced = check_out_file(out, path) if out is not None else False  # before the search
    chart_dir = out.parent if out is not None else None  # <out stem>_pareto.png/.svg beside --out
    charts = [] if out is None else [out.parent / f"{out.stem}_pareto.{e}" for e in ("png", "svg")]
    replaced_charts = [str(c) for c in charts if chart_replaceable(c, path)]  # said, never silent
    rep, best = optimize_fourbar(d, objective, trials, seed, top, chart_dir, progress,
                                 out.stem if out is not None else None, proportions_tol, starts,
                                 beat_prototype, where)
    cmd = (f"hapticad optimize {path} --objective {objective} --trials {trials} --seed {seed} "
           f"--exact-top {top}" + (f" --proportions-tol {proportions_tol:g}" if proportions_tol else "")
           + ("" if starts else " --no-starts") + (" --beat-prototype" if beat_prototype else "")
           + "".join(f" --{k} {where[k]}" for k in ("workers", "scheduler", "study") if (where or {}).get(k))
           + (f" --out {out}" if out is not None else ""))
    rep["command"] = cmd
    rep["measured"] = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())  # the docs' generated tables (cad.bench.readme)
    if out is not None and best is not None:
        ex = rep["best"]["exact"]
        exact.write_optimum(d, best, out, f"Optimum of `{cmd}`\nexact solids: M11 {ex['M11_min_g']:.2f}-"
                            f"{ex['M11_max_g']:.2f} g, cheap model {rep['best']['cheap']['M11_max_g']:.2f} g "
                            f"({100 * ex['cheap_error_rel']:+.1f} %), first mode "
                            f"{ex['structure']['first_mode_Hz']:.0f} Hz, min clearance {ex['min_clearance_mm']:.2f} mm"
                            + "".join(f"\n{exact.miss_line(m)}" for m in rep["misses"]))
        rep["out"] = str(out)
        rep["replaced"] = replaced
    rep["replaced_files"] = replaced_charts + ([str(out)] if replaced else [])
    if json_out:
        print_json(rep)
    else:
        _print_fourbar(rep)
    for m in rep["misses"]:  # one line per missed target of the design (the optimum was not enough)
        print(f"hapticad: {exact.miss_line(m)}", file=sys.stderr)
    if beat_prototype and best is None:
        print(f"hapticad: prototype not beaten: {prototype_blocker(rep['prototype'])}", file=sys.stderr)
    if best is None or rep["misses"]:
        raise typer.Exit(1)


def dask_where(workers: int | None, scheduler: str | None, study: Path | None,
               out: Path | None) -> dict | None:
    """The Dask placement of a four-bar search (:func:`cad.studies.codesign.distributed.run`):
    None without ``--workers`` and ``--scheduler`` (in this process); the study folder is
    ``--study`` or, without it, ``<--out stem>_study`` beside ``--out``. Raises DesignError
    naming the flag: both given, ``--workers`` out of range, ``--scheduler`` not an address,
    ``--study`` without either or missing with no ``--out``, ``--study`` not a folder."""
    from cad.cli import flags
    from cad.studies.codesign.distributed import placement

    where = placement(workers, scheduler, study, out)
    if where is not None:
        flags.out_path("--study", Path(where["study"]), folder=True)
    return where


def prototype_blocker(proto: dict) -> str:
    """One line naming the figure that keeps every design from the prototype's limits and by
    how much: the friction every linkage has at the force limit with the best catalog motor
    (``motor_bounds``: F_cont / F_s <= T_cont / (Kt I0) whatever the linkage or a capstan
    ratio, both figures scale alike), against the friction limit."""
    lim = proto["limits"]
    f_lim, force = lim["friction_N"]["value"], lim["continuous_force_N"]["value"]
    mb = max(proto["motor_bounds"], key=lambda b: b["ratio"])
    need = force / f_lim
    if mb["ratio"] >= need:
        return (f"no trial of this search met all {len(lim)} limits (judged: {proto['judged_trials']}); "
                "more --trials may find one")
    over = 100 * (mb["friction_at_force_limit_N"] / f_lim - 1)
    return (f"friction_N: at the {force:g} N continuous-force limit every linkage has at least "
            f"{mb['friction_at_force_limit_N']:.3g} N of friction with the best catalog motor "
            f"({mb['motor']}) against the {f_lim:g} N limit (+{over:.0f} %): continuous force / "
            f"friction <= T_cont / (Kt I0) = {mb['ratio']:.1f} for any linkage or capstan ratio, "
            f"{need:.1f} needed (docs/codesign.md)")


def chart_replaceable(chart: Path, design: Path) -> bool:
    """True when the Pareto chart ``chart`` (named after ``--out``, not by the user) exists
    and hapticad wrote it; a user's file of that name is refused (DesignError ``--out``)."""
    from cad.errors import DesignError
    from cad.io.outdir import check_out_file
    from cad.report.figures import written_by_hapticad

    if not check_out_file(chart, design):
        return False
    if chart.is_symlink() or not written_by_hapticad(chart):
        raise DesignError("--out", f"{chart} exists and hapticad did not write it (the Pareto "
                          "chart goes beside --out); move it away or name another --out")
    return True


def _print_fourbar(rep: dict) -> None:
    print(f"{rep['design']}: {rep['objective']}, {rep['trials']} trials ({rep['feasible_trials']} feasible), "
          f"{rep['library']}")
    b = rep["best"]
    if b is None:
        if rep["feasible_trials"] == 0:
            print("  no trial met every check on the cheap model; the commonest reasons:")
            for r in rep.get("infeasible_reasons", ()):
                print(f"    {r['trials']:>4} trials: {r['reason']}")
        else:
            print("  no candidate passed interference and the structural limits on the exact solids")
        return
    ex = b["exact"]
    print(f"  M11 {ex['M11_min_g']:.2f} .. {ex['M11_max_g']:.2f} g on the solids "
          f"(cheap model {b['cheap']['M11_max_g']:.2f} g, error {100 * ex['cheap_error_rel']:+.1f} %)")
    print(f"  joints {b['parts']['bearing']} + {b['parts']['pin']} ({b['parts']['pin_material']}), bars "
          f"{b['parts']['bar_material']} {b['parts']['bar_thickness_mm']:g} x {b['parts']['bar_width_mm']:g} mm, "
          f"motor {b['parts']['motor']}, layers (bottom to top) {', '.join(b['layer_order'])}")
    print(f"  crank {b['mechanism']['phi1_min_deg']:.1f} .. {b['mechanism']['phi1_max_deg']:.1f} deg, "
          f"dy_max {ex['dy_max_mm']:.3f} mm, torque variation {ex['torque_variation']:.4f}, "
          f"first mode {ex['structure']['first_mode_Hz']:.0f} Hz, min clearance {ex['min_clearance_mm']:.2f} mm")
    if rep.get("out"):
        print(f"  {'replaced' if rep.get('replaced') else 'wrote'} {rep['out']}")
    for f in rep.get("replaced_files", []):
        if f != rep.get("out"):
            print(f"  replaced {f}")


def register(app: typer.Typer) -> None:
    @app.command("optimize")
    def optimize_cmd(
        design: Path = typer.Argument(..., help="Design TOML with an [optimize] table."),
        method: str = typer.Option(None, "--method", help="Culling (default) or brute (pantographs)."),
        objective: str = typer.Option(None, "--objective", help="min-apparent-mass (four-bars)."),
        trials: int = typer.Option(300, "--trials", help="Optuna trials on the cheap model (four-bars)."),
        seed: int = typer.Option(0, "--seed", help="Sampler seed (four-bars)."),
        exact_top: int = typer.Option(3, "--exact-top", help="Candidates re-evaluated on the solids."),
        out: Path = typer.Option(None, "--out", help="Write the optimum as a new design (TOML)."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
        proportions_tol: float = typer.Option(
            0.0, "--proportions-tol",
            help="Four-bars: also perturb the family's link proportions by up to this fraction "
                 "(0 = keep them; at most 0.2)."),
        no_starts: bool = typer.Option(
            False, "--no-starts",
            help="Four-bars: leave out the hand-written starting guesses (TPE from random trials only)."),
        beat_prototype: bool = typer.Option(
            False, "--beat-prototype",
            help="Four-bars: every figure of the Hoeken prototype as a limit (M11 <= 30 g, stroke >= 50 mm, "
                 "dy <= 0.2 mm, first mode >= 250 Hz, continuous force >= 5 N, K_max >= 15 kN/m, friction "
                 "<= 0.083 N); without a design meeting all, the Pareto front of the two that conflict."),
        workers: int = typer.Option(
            None, "--workers",
            help="Four-bars: run the trials on an embedded Dask LocalCluster of N worker processes "
                 "(the study in a journal under --study; resumable)."),
        scheduler: str = typer.Option(
            None, "--scheduler", help="Four-bars: tcp://HOST:PORT of an existing Dask scheduler instead."),
        study: Path = typer.Option(
            None, "--study",
            help="Four-bars, with --workers/--scheduler: folder of the optuna journal every worker "
                 "reaches (default: <--out stem>_study beside --out); rerun to resume."),
        allow_scripts: bool = typer.Option(
            False, "--allow-scripts", help="Run the design's [parts] handle_script (inside its folder)."
        ),
        allow_scripts_anywhere: bool = typer.Option(
            False, "--allow-scripts-anywhere", help="Run handle_script from any path."
        ),
    ) -> None:
        """Maximize the GII (pantographs) or minimize the apparent mass (four-bars)."""
        from cad.cli import flags
        from cad.parts.handle import set_script_policy

        set_script_policy(allow_scripts, allow_scripts_anywhere)
        from cad.errors import DesignError

        flags.out_path("--out", out, folder=False)
        if method is not None and method not in ("culling", "brute"):
            raise DesignError("--method", f"must be 'culling' or 'brute', got {method!r}")
        flags.choice("--objective", objective, ("min-apparent-mass",))
        flags.number("--trials", trials)
        flags.number("--seed", seed)
        flags.number("--exact-top", exact_top)
        flags.number("--proportions-tol", proportions_tol)
        where = dask_where(workers, scheduler, study, out)
        from cad.design import load_design

        loaded = load_design(design)
        flags.design_script(loaded)  # exit 2 naming the opt-in, as build does, before the search
        if getattr(loaded, "family", None) in FOURBAR_FAMILIES:
            if method is not None:
                raise DesignError("--method", f"{method!r} is for pantograph designs; a four-bar "
                                              "takes --objective min-apparent-mass")
            _fourbar(loaded, design, objective or "min-apparent-mass", trials, seed, exact_top, out,
                     json_out, proportions_tol, not no_starts, beat_prototype, where)
            return
        if where is not None:
            flag = "--scheduler" if scheduler is not None else "--workers"
            raise DesignError(flag, f"the Dask search is for four-bar designs, not {loaded.family!r} "
                                    "(the GII culling runs in this process)")
        if objective is not None:
            raise DesignError("--objective", f"min-apparent-mass is for four-bar designs, not "
                                             f"{loaded.family!r} (use --method)")
        _pantograph(loaded, design, method or "culling", out, json_out)


def _pantograph(d, design: Path, method: str, out: Path | None, json_out: bool) -> None:
    """``hapticad optimize`` of a GII-family design: the GII optimum by ``method``
    (culling | brute) with its targets and default limits (:func:`cad.api.optimize`),
    written to ``out`` when given (misses and limit warnings in its comment), printed."""
    import sys

    from cad.api import optimize

    if out is not None:
        from cad.io.outdir import check_out_file

        check_out_file(out, design)  # before the search, as for four-bars
    rep = optimize(d, method=method)
    if out is not None:
        rep["replaced"] = write_optimum(
            d, rep, out, f"hapticad optimize {design.name} --method {method}"
        )
        rep["out"] = str(out)
    if json_out:
        print_json(rep)
    else:
        _print_gii(rep, out)
    for w in rep["limit_warnings"]:  # said, never silent; the exit status follows the targets
        print(f"hapticad: warning: the optimum misses a default datasheet limit: {w}", file=sys.stderr)
    _exit_on_misses(rep)


def _print_gii(rep: dict, out: Path | None) -> None:
    print(f"{rep['design']} ({rep['family']}), {rep['method']}: GII = {rep['gii']:.6f}")
    print(f"  best: {rep['best']}")
    print(
        f"  {rep['jacobian_evaluations']} Jacobian evaluations "
        f"(brute force {rep['brute_force_evaluations']}, ratio {rep['evaluation_ratio']:.1f}) "
        f"in {rep['wall_time_s']:.3f} s; {rep['n_candidates']} candidates x {rep['n_points']} samples"
    )
    if rep["at_bound"]:
        print(f"  note: optimum at the range bound of {', '.join(rep['at_bound'])}")
    if out is not None:
        print(f"  {'replaced' if rep['replaced'] else 'wrote'} {out}")


def _exit_on_misses(rep: dict) -> None:
    """One ``hapticad: target missed:`` line per target the optimum misses, then exit 1."""
    if rep["misses"]:
        import sys

        for m in rep["misses"]:
            print(f"hapticad: {m}", file=sys.stderr)
        raise typer.Exit(1)
