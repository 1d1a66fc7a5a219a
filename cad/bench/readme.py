"""The documentation's measured tables, generated from the JSON they come from (issue 21 §2).

A generated block in a page of the documentation (``README.md`` or a Markdown page under
``docs/``, :func:`pages`)::

    <!-- generated: KIND SOURCE [SOURCE ...] -->
    ... written by this module, never by hand ...
    <!-- end generated -->

``KIND`` names a renderer of :data:`RENDERERS`; each ``SOURCE`` is a JSON path relative to the
repository root, optionally ``PATH:WORD`` to keep only the rows whose goal contains ``WORD``.
Every block ends with each source's date and command, read from the JSON's ``measured`` and
``command`` (or ``commands``) keys; a source without them is refused. A page then cannot
disagree with its JSON: ``tests/docs/test_readme_generated.py`` regenerates every block and compares.

``python -m cad.bench.readme`` rewrites every page holding a block in place; ``--check`` only
compares and exits 1 naming the page and the first block that differs; ``--capture OUT.json -- ARGV...`` runs ``hapticad ARGV``
(a ``--json`` command) and saves its object with ``command`` and ``measured`` added, for a
command that does not record them itself (``check``, ``tolerance``, ``swap``). ``hapticad
bench``, ``optimize --json`` and ``synth --json`` record them. No CAD import here (a captured
command imports what it needs).
"""

from __future__ import annotations

import json
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from cad.data.catalog import MOTORS
from cad.datasheet import fmt_value, verdict_text
from cad.errors import DesignError
from cad.io.atomic import write_text_atomic

ROOT = Path(__file__).resolve().parents[2]
BLOCK = re.compile(r"(<!-- generated: (?P<spec>[^>]*?) -->\n)(?P<body>.*?)(<!-- end generated -->)", re.S)


def pages(root: Path = ROOT) -> list[Path]:
    """The documentation pages that hold a generated block: ``README.md`` and the Markdown
    pages under ``docs/`` (sorted), as paths under ``root``."""
    candidates = [root / "README.md", *sorted((root / "docs").rglob("*.md"))]
    return [p for p in candidates if p.is_file() and BLOCK.search(p.read_text(encoding="utf-8"))]


def _load(source: str, root: Path) -> tuple[str, str | None, dict[str, Any]]:
    """(path, row filter word or None, JSON object) of one SOURCE."""
    path, _, word = source.partition(":")
    try:
        data = json.loads((root / path).read_text())
    except (OSError, ValueError) as exc:
        raise DesignError("generated block", f"source {path}: {exc}") from None
    if "measured" not in data or not ("command" in data or "commands" in data):
        raise DesignError("generated block", f"source {path} records no `measured` date and "
                                                    "`command`: a table must say when and how it was measured")
    return path, word or None, data


def _provenance(i: int, path: str, data: dict[str, Any]) -> str:
    cmds = data.get("commands") or [data["command"]]
    note = f" ({data['measured_note']})" if data.get("measured_note") else ""
    return (f"[{i}] `{path}`: measured {data['measured']}{note}; "
            + " then ".join(f"`{c}`" for c in cmds) + ".")


def _met(ok: bool | None) -> str:
    return "—" if ok is None else ("yes" if ok else "no")


def _goal_rows(sources) -> dict[str, list[dict[str, Any] | None]]:
    """goal -> its row in each source (None where that run did not measure it), in first-seen order."""
    rows: dict[str, list[dict[str, Any] | None]] = {}
    for i, (_, word, data) in enumerate(sources):
        for g in data.get("goals", []):
            if word is None or word in g["goal"]:
                rows.setdefault(g["goal"], [None] * len(sources))[i] = g
    return rows


def render_goals(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """The ``goals`` rows the bench wrote (goal, measured, target, met). Runs that measured the
    same goal are shown side by side, one column per run; otherwise each row names its run."""
    rows = _goal_rows(sources)
    if all(sum(r is not None for r in runs) == 1 for runs in rows.values()):
        lines = ["| goal | measured | target | met | run |", "|---|---|---|---|---|"]
        for goal, runs in rows.items():
            i, g = next((i, g) for i, g in enumerate(runs, 1) if g is not None)
            lines.append(f"| {goal} | **{g['measured']}** | {g['target']} | {_met(g['met'])} | [{i}] |")
        return "\n".join(lines)
    n = len(sources)
    lines = ["| goal | target | " + " | ".join(f"run [{i}]: measured, met" for i in range(1, n + 1)) + " |",
             "|---|---|" + "---|" * n]
    for goal, runs in rows.items():
        target = next(g["target"] for g in runs if g is not None)
        cells = ["—" if g is None else f"**{g['measured']}**, {_met(g['met'])}" for g in runs]
        lines.append(f"| {goal} | {target} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _range_g(ex: dict[str, Any]) -> str:
    return f"{ex['M11_min_g']:.2f} – {ex['M11_max_g']:.2f} g"


def _motor_limit(req: dict[str, Any], motor: str) -> str:
    """The continuous-torque limit the run checked ``motor`` against, and the catalog's current
    value (``cad.data.catalog.MOTORS``, no CAD import) when they differ, so a catalog correction
    made after the run is visible in the table instead of hidden by it."""
    used = req["motor_continuous_torque_mNm"][motor]
    now = MOTORS[motor].torque_continuous_mNm if motor in MOTORS else None
    if now is None or abs(now - used) < 0.05:
        return f"{used:g} mN·m continuous"
    return f"the run checked {used:g} mN·m continuous, the catalog now gives {now:g} mN·m"


def render_codesign(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """The optimum an ``optimize --json`` run accepted, rebuilt on the exact solids."""
    (_, _, data), = sources
    b = data["best"]
    ex, p, mech, req = b["exact"], b["parts"], b["mechanism"], data["requirements"]
    st = ex["structure"]
    rows = [
        ("trials, feasible (cheap model)", f"{data['trials']}, {data['feasible_trials']} (seed {data['seed']})"),
        ("accepted trial; search / whole command wall", f"{b['trial']}; {data['search_wall_s']:.0f} s / {data['wall_s']:.0f} s"),
        ("M11 over the stroke (exact solids)", f"**{_range_g(ex)}** (cheap model {ex['cheap_M11_max_g']:.2f} g: "
                                               f"{100 * ex['cheap_error_rel']:+.1f} %)"),
        ("joints", f"{p['bearing']} bearings, {p['pin']} pins ({p['pin_material']})"),
        ("bars", f"{p['bar_material']} {p['bar_thickness_mm']:g} × {p['bar_width_mm']:g} mm"
                 f"{', pockets' if p.get('bar_pockets') else ''}, {p['bar_end_radius_mm']:g} mm ends"),
        ("layers (bottom to top)", ", ".join(b["layer_order"])),
        ("handle, motor", f"{p['handle_material']} ⌀{p['handle_diameter_mm']:g} × {p['handle_height_mm']:g} mm "
                          f"on {p['handle_screw']}, {p['motor']} ({b['cheap']['torque_max_mNm']:.1f} mN·m peak at "
                          f"{req['force_N']:g} N; {_motor_limit(req, p['motor'])})"),
        ("crank range, dy_max, torque variation",
         f"{mech['phi1_min_deg']:.1f}–{mech['phi1_max_deg']:.1f}°, {ex['dy_max_mm']:.3f} mm, {ex['torque_variation']:.3f}"),
        ("overlap, min clearance", f"{ex['overlap_volume_mm3']:g} mm³, {ex['min_clearance_mm']:.2f} mm"),
        ("first mode, max stress", f"{st['first_mode_Hz']:.0f} Hz, {st['max_stress_MPa']:.1f} MPa ({st['method']})"),
    ]
    return "\n".join(["| | accepted optimum |", "|---|---|"] + [f"| {k} | {v} |" for k, v in rows])


def render_candidates(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """Every ``--exact-top`` candidate of an ``optimize --json`` run, as rebuilt on the solids."""
    (_, _, data), = sources
    lines = ["| trial | exact M11 | cheap model | overlap | first mode | max stress | structure |",
             "|---|---|---|---|---|---|---|"]
    for c in data["exact_checked"]:
        ex = c["exact"]
        st = ex["structure"]
        lines.append(f"| {c['trial']} | {_range_g(ex)} | {100 * ex['cheap_error_rel']:+.1f} % | "
                     f"{ex['overlap_volume_mm3']:g} mm³ | {st['first_mode_Hz']:.0f} Hz | "
                     f"{st['max_stress_MPa']:.1f} MPa | {'ok' if st['ok'] else 'failed'} |")
    return "\n".join(lines)


def _span(vals: list[float], fmt: str) -> str:
    return format(vals[0], fmt) if len(vals) == 1 else f"{vals[0]:{fmt}} … {vals[-1]:{fmt}}"


def render_massprops(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """The bench's mass-property methods on its bar, per method over its knob (first … last)."""
    (_, _, data), = sources
    mp = data["massprops"]
    bar = mp["parts"]["bar"]
    by: dict[str, list[dict[str, Any]]] = {}
    for pt in mp["points"]:
        if pt["part"] == "bar":
            by.setdefault(pt["method"], []).append(pt)
    lines = [f"Bar {bar['L_mm']:g} mm between hole centres, {2 * bar['R_mm']:g} mm wide, {bar['T_mm']:g} mm "
             f"thick, two Ø{2 * bar['r_mm']:g} holes; {mp['repeats']} repeats, medians:", "",
             "| method | knob | time | error of mass | error of Izz |", "|---|---|---|---|---|"]
    for method, pts in by.items():
        izz = [p["error_Izz"] for p in pts]
        lines.append(f"| {method} | {_span([p['knob'] for p in pts], 's')} | "
                     f"{_span([1e3 * p['time_s'] for p in pts], '.2f')} ms | "
                     f"{_span([p['error_mass'] for p in pts], '.1e')} | "
                     f"{'— (volume only)' if None in izz else _span(izz, '.1e')} |")
    return "\n".join(lines)


def render_families(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """Cold builds of the other families and the PowerMouse motion check (bench ``families``)."""
    (_, _, data), = sources
    f = data["families"]
    lines = ["| measured (bench `families`) | wall, median (range) | CPU, median |", "|---|---|---|"]
    for fam, r in f["cold"].items():
        goal = "" if r["goal_s"] is None else f" (goal ≤ {r['goal_s']:g} s: {_met(r['meets_goal'])})"
        lines.append(f"| {fam}: cold `hapticad build --no-cache`, {len(r['times_s'])} runs{goal} | "
                     f"**{r['median_s']:.2f} s** ({min(r['times_s']):.2f}–{max(r['times_s']):.2f} s) | "
                     f"{r['cpu_median_s']:.2f} s |")
    for pt in f["motion_check"]["points"]:
        lines.append(f"| PowerMouse motion check, {pt['method']} ({pt['exact_poses']} of {pt['poses']} poses "
                     f"exact; largest clearance difference to every-pose-exact {pt['error']:.1g} mm) | **{pt['time_s']:.2f} s** "
                     f"({min(pt['times_s']):.2f}–{max(pt['times_s']):.2f} s) | {pt['cpu_s']:.2f} s |")
    return "\n".join(lines)


def render_synth(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """``hapticad synth --json`` results side by side, after the first source's start."""
    def col(r: dict[str, Any]) -> list[str]:
        return [" / ".join(f"{r[k]:.4g}" for k in ("l1_mm", "l2_mm", "l3_mm", "l5_mm", "le_mm")),
                f"{r['phi1_min_deg']:.1f} – {r['phi1_max_deg']:.1f}", f"{r['stroke_mm']:.1f}",
                f"{r['dy_max_mm']:.3f}", f"{r['torque_variation']:.4f}", f"{r['min_transmission_angle_deg']:.1f}°"]

    names = ["l1 / l2 / l3 / l5 / le (mm)", "φ1 range (deg)", "stroke_mm", "dy_max_mm", "torque_variation",
             "min transmission angle"]
    heads = ["start (the design)"]
    cols = [col(sources[0][2]["start"])]
    for i, (_, _, d) in enumerate(sources, 1):
        held = f", {d['stroke_mm_held']:g} mm held" if d.get("stroke_mm_held") else ""
        heads.append(f"[{i}] `{d['objective']}`, `--free {d['free']}`{held}"
                     + ("" if d["feasible"] else " (infeasible)"))
        cols.append(col(d["result"]))
    lines = ["| | " + " | ".join(heads) + " |", "|---|" + "---|" * len(heads)]
    lines += [f"| {n} | " + " | ".join(c[j] for c in cols) + " |" for j, n in enumerate(names)]
    return "\n".join(lines)


def render_check(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """A ``check --json`` capture: computed against each target, then the M11 budget's largest parts."""
    (_, _, data), = sources
    lines = ["| key | computed (solids) | target | gap | met |", "|---|---|---|---|---|"]
    for r in data["rows"]:
        gap = "—" if r["gap_rel"] is None else f"{100 * r['gap_rel']:+.0f} %"
        lines.append(f"| {r['key']} | {r['computed']:.4g} | {r['target_text']} | {gap} | {_met(r['ok'])} |")
    worst = sorted(data.get("budget") or [], key=lambda b: -b["M11_worst_g"])
    if worst:
        total = data["computed"]["M11_max_g"]
        lines += ["", f"M11 at its worst point = {total:.1f} g = " + " + ".join(
            f"{b['part']} {b['M11_worst_g']:.1f}" for b in worst[:8]) + " + … g (`budget`)."]
    return "\n".join(lines)


def render_tolerance(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """``tolerance --json`` captures, one row each: dy_max_mm spread, yields, first-order sigma;
    then each run's largest sensitivity shares of dy_max_mm, stroke_mm and M11_max_g."""
    lines = ["| run | tolerances, samples | dy_max_mm mean ± std | p01 … p99 (min … max) | σ_lin | "
             "yield per target | every target | M11 from | wall |", "|---|---|---|---|---|---|---|---|---|"]
    notes = []
    for i, (_, _, d) in enumerate(sources, 1):
        m = d["metrics"]["dy_max_mm"]
        tols = ", ".join(sorted({f"±{t['tol_mm']:g} mm {t['distribution']}" for t in d["tolerances"]}))
        ys = "; ".join(f"{k} {t['target']}: {100 * t['yield']:.3g} %" for k, t in d["yield"]["by_target"].items())
        overall = d["yield"]["overall"]
        lines.append(f"| [{i}] | {tols}, {d['samples']} | {m['mean']:.4f} ± {m['std']:.4f} | {m['p01']:.4f} … "
                     f"{m['p99']:.4f} ({m['min']:.3f} … {m['max']:.3f}) | {m['linear_std']:.4f} | {ys} | "
                     f"**{'—' if overall is None else f'{100 * overall:.3g} %'}** | {d['inertia_source']} | "
                     f"{d['wall_s']:.0f} s |")
        shares = "; ".join(f"{k}: " + ", ".join(f"{s['tolerance']} {100 * s['share']:.0f} %"
                                                for s in d["sensitivity"][k][:3])
                           for k in ("dy_max_mm", "stroke_mm", "M11_max_g") if k in d["sensitivity"])
        notes.append(f"Largest first-order shares of the variance, [{i}]: {shares}.")
    return "\n".join(lines + ["", "  \n".join(notes)])


def render_swap(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """A ``swap --json`` capture: the source and the swapped bar set side by side."""
    (_, _, data), = sources
    old, new = data["old"], data["new"]

    def cells(k: str, fmt: str) -> str:
        return f"{old[k]:{fmt}} | {new[k]:{fmt}}"

    lengths = [" / ".join(f"{d[k]:.3g}" for k in ("l1_mm", "l2_mm", "l3_mm", "l5_mm", "le_mm")) for d in (old, new)]
    bbox = [" × ".join(f"{v:.1f}" for v in d["bbox_mm"]) for d in (old, new)]
    return "\n".join([
        f"| (stroke {old['stroke_mm']:.1f} / {new['stroke_mm']:.1f} mm) | {old['family']} | {new['family']} (swapped) |",
        "|---|---|---|",
        f"| dy_max_mm | {cells('dy_max_mm', '.3f')} |", f"| torque_mean_mNm | {cells('torque_mean_mNm', '.1f')} |",
        f"| torque_variation | {cells('torque_variation', '.3f')} |", f"| bbox_mm | {bbox[0]} | {bbox[1]} |",
        f"| l1 / l2 / l3 / l5 / le (mm) | {lengths[0]} | {lengths[1]} |"])


#: bench voicecoil model names -> the ``hapticad voicecoil --model`` that computes them.
VOICECOIL_MODELS = {
    "eq9 closed form (one image per plate, centre)": "`closed-form` (eq 9)",
    "image series converged (one pair, centre)": "`images`",
    "magpylib whole actuator, 32 slabs, coil-volume mean": "`magpylib`",
}


def render_voicecoil(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """Optimal gap, force and gap field of each voice-coil field model the bench ran."""
    (_, _, data), = sources
    lines = ["| field model (bench) | `--model` | optimal gap | force | B_g |", "|---|---|---|---|---|"]
    for name, r in data["voicecoil"]["optimal_gap_by_model"].items():
        bg = f"{r['Bg_T']:.3f} T" if "Bg_T" in r else "—"
        lines.append(f"| {name} | {VOICECOIL_MODELS.get(name, '—')} | **{r['optimal_gap_mm']:.2f} mm** | "
                     f"{r['force_N']:.2f} N | {bg} |")
    return "\n".join(lines)


#: How a datasheet verdict reads in a generated table.
VERDICT_WORDS = {"ok": "ok", "miss": "**miss**", "within sampling error": "within sampling error"}


def render_datasheet(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """A ``datasheet --json`` capture: every figure with its range, unit, verdict and the paper's value."""
    (_, _, data), = sources
    lines = ["| figure | value (min .. max over the stroke) | unit | verdict | the paper's prototype |",
             "|---|---|---|---|---|"]
    for r in data["datasheet"]["rows"]:
        err = r.get("sampling_error_rel")
        val = fmt_value(r) + (f" ± {100 * err:.1f} %" if err else "")
        lines.append(f"| {r['figure']}{' *' if r['unverified'] else ''} | {val} | {r['unit']} | "
                     f"{verdict_text(r)} | {r.get('paper') or ''} |")
    return "\n".join(lines)


#: Datasheet row keys a ``structure`` block shows (the structural figures, in this order of kinds).
STRUCTURE_KEYS = ("first_mode", "compliance_", "max_stress_MPa")
#: Datasheet row keys a ``figures`` block shows: the headline figures of a fabricated device.
FIGURE_KEYS = ("M11_g", "total_mass_g", "first_mode_Hz", "max_stress_MPa", "continuous_force_N")


def _side_by_side(sources: list[tuple[str, str | None, dict[str, Any]]], kinds: tuple[str, ...]) -> str:
    """The rows of ``datasheet --json`` captures whose key starts with one of ``kinds`` (in that
    order), one column per device (``value unit`` with the verdict where the row has a limit);
    a figure one device does not state reads "—"."""
    rows: dict[str, dict[int, dict[str, Any]]] = {}
    for kind in kinds:
        for i, (_, _, d) in enumerate(sources):
            for r in d["datasheet"]["rows"]:
                if r["key"].startswith(kind) and r["value"] is not None:
                    rows.setdefault(r["key"], {})[i] = r
    heads = [f"[{i}] {d['name']}" for i, (_, _, d) in enumerate(sources, 1)]
    lines = ["| figure | " + " | ".join(heads) + " |", "|---|" + "---|" * len(heads)]
    for by in rows.values():
        first = next(iter(by.values()))
        cells = []
        for i in range(len(sources)):
            r = by.get(i)
            v = "—" if r is None else f"{fmt_value(r)} {r['unit']}"
            cells.append(v if r is None or r.get("limit") is None else f"{v}, {verdict_text(r)}")
        lines.append(f"| {first['figure']} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def render_structure(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """The structural rows (first modes, handle compliances, peak stress) of ``datasheet --json``
    captures side by side (:data:`STRUCTURE_KEYS`)."""
    return _side_by_side(sources, STRUCTURE_KEYS)


def render_figures(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """The headline rows (apparent mass, total mass, first mode, stress, continuous force) of
    ``datasheet --json`` captures side by side (:data:`FIGURE_KEYS`)."""
    return _side_by_side(sources, FIGURE_KEYS)


def render_wall(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """``wall --json`` captures, one row each: K_max with its sampling error and intermittent
    band, beside eq (25) and the passivity bound."""
    lines = ["| model | B | K_max | sampling error | stable and unstable walls interleave | eq (25) | "
             "passivity | M11 at the wall | method |", "|---|---|---|---|---|---|---|---|---|"]
    for _, _, d in sources:
        e = d.get("K_max_sampling_error_rel")
        band = d.get("K_band_N_per_m") or [None, None]
        lines.append(f"| {d['model']} | {d['B_N_s_per_m']:g} N·s/m | **{d['K_max_stable_N_per_m'] / 1e3:.1f} kN/m** | "
                     f"{'—' if e is None else f'± {100 * e:.1f} %'} | "
                     f"{'—' if band[0] is None else f'{band[0] / 1e3:.1f} .. {band[1] / 1e3:.1f} kN/m'} | "
                     f"{d['eq25_K_max_N_per_m']:.0f} N/m | {d['passivity_K_max_N_per_m']:.0f} N/m | "
                     f"{d['M11_wall_g']:.1f} g | {d.get('K_max_method', '')} |")
    return "\n".join(lines)


def render_prototype_front(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """The Pareto fronts of ``optimize --beat-prototype --json`` (cheap model, every limit
    outside the pair met), their ends on the full datasheet (solids, simulated K_max)."""
    (_, _, data), = sources
    lines = ["| front (x up, y down) | trial | motor, bars | crank span | continuous force | friction | "
             "M11 max | first mode | datasheet of the end (solids, simulated K_max) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for f in data["prototype"]["fronts"].values():
        ends = {e["trial"]: e for e in f["ends_exact"]}
        name = f"{f['x']} / {f['y']}" + (f" ({', '.join(f['relaxed'])} relaxed)" if f["relaxed"] else "")
        for r in f["points"]:
            e = ends.get(r["trial"])
            ds = "—" if e is None else "; ".join(
                f"{k} {v['value']:.4g} {VERDICT_WORDS.get(v['verdict'], '')}"
                for k, v in e["rows"].items() if v["value"] is not None)
            lines.append(f"| {name} | {r['trial']} | {r['motor']}, {r['bar_material']} | {r['crank_span_deg']:.0f}° | "
                         f"{r['continuous_force_N']:.2f} N | {r['friction_N']:.3f} N | {r['M11_max_g']:.1f} g | "
                         f"{r['first_mode_Hz']:.0f} Hz | {ds} |")
    return "\n".join(lines)


def render_motor_choice(sources: list[tuple[str, str | None, dict[str, Any]]]) -> str:
    """``hapticad bench --only motor_choice``: per brief and method, the best feasible cheap M11
    of each seed, their mean and the seeds with no feasible trial (:mod:`cad.bench.motor_choice`)."""
    lines = ["| brief (trials) | motor by | best cheap M11 per seed | mean | no feasible trial |",
             "|---|---|---|---|---|"]
    for _, _, d in sources:
        mc = d.get("motor_choice", d)
        for b in mc["briefs"]:
            for method, m in b["methods"].items():
                per = ", ".join("—" if r["best_M11_g"] is None else f"{r['best_M11_g']:.1f}" for r in m["runs"])
                mean = "—" if m["mean_best_M11_g"] is None else f"**{m['mean_best_M11_g']:.1f} g**"
                lines.append(f"| {Path(b['brief']).stem} ({b['trials']}) | {method} | {per} | {mean} | "
                             f"{m['no_feasible']} of {len(m['runs'])} |")
    return "\n".join(lines)


RENDERERS: dict[str, Callable[[list], str]] = {
    "prototype-front": render_prototype_front,
    "goals": render_goals, "codesign": render_codesign, "candidates": render_candidates,
    "massprops": render_massprops, "voicecoil": render_voicecoil, "families": render_families,
    "synth": render_synth, "check": render_check, "tolerance": render_tolerance,
    "swap": render_swap, "datasheet": render_datasheet, "wall": render_wall,
    "structure": render_structure, "figures": render_figures, "motor-choice": render_motor_choice,
}


def render_block(spec: str, root: Path = ROOT) -> str:
    """The body of one generated block (table, blank line, one provenance line per source)."""
    kind, *srcs = spec.split()
    if kind not in RENDERERS or not srcs:
        raise DesignError("generated block", f"{spec!r}: want KIND SOURCE..., KIND one of "
                                                    f"{', '.join(RENDERERS)}")
    sources = [_load(s, root) for s in srcs]
    prov = [_provenance(i, p, d) for i, (p, _, d) in enumerate(sources, 1)]
    return RENDERERS[kind](sources) + "\n\n" + "  \n".join(prov) + "\n"


def regenerate(text: str, root: Path = ROOT) -> str:
    """``text`` with every generated block's body rendered again from its sources."""
    return BLOCK.sub(lambda m: m.group(1) + render_block(m.group("spec"), root) + m.group(4), text)


def stale_block(text: str, root: Path = ROOT) -> str | None:
    """The spec of the first generated block of ``text`` that its sources no longer give, or None."""
    for m in BLOCK.finditer(text):
        if m.group("body") != render_block(m.group("spec"), root):
            return m.group("spec")
    return None


def capture(out: Path, argv: list[str]) -> int:
    """Run ``hapticad ARGV`` (which must print one JSON object; ``python -m cad``) and save that
    object to ``out`` with ``command`` and ``measured`` (UTC) added: a source for a block.
    The command's exit code is saved as ``exit_code`` (``check`` exits 1 when a target is
    missed); returns 0 once saved, or the command's code when it failed (2)."""
    import shlex
    import subprocess
    import time

    # through the entry point, as a user runs it (nothing outside cad/cli imports the CLI)
    proc = subprocess.run([sys.executable, "-m", "cad", *argv], stdout=subprocess.PIPE, text=True)
    code = proc.returncode
    if code not in (0, 1):
        return code
    data = {"command": "hapticad " + shlex.join(argv), "measured": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "exit_code": code, **json.loads(proc.stdout)}
    out.parent.mkdir(parents=True, exist_ok=True)
    write_text_atomic(out, json.dumps(data, indent=1) + "\n")
    return 0


def main(argv: list[str] | None = None) -> int:
    """``python -m cad.bench.readme [--check]``: rewrite every page holding a generated block
    (:func:`pages`), or compare (exit 1 if one is stale).
    ``python -m cad.bench.readme --capture OUT.json -- ARGV...``: save ``hapticad ARGV``'s JSON."""
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--capture"] and len(argv) > 3 and argv[2] == "--":
        return capture(Path(argv[1]), argv[3:])
    for page in pages():
        name = page.relative_to(ROOT).as_posix()
        text = page.read_text(encoding="utf-8")
        if "--check" in argv:
            spec = stale_block(text)
            if spec is not None:
                print(f"{name}: generated block `{spec}` differs from its JSON; run python -m "
                      "cad.bench.readme", file=sys.stderr)
                return 1
            continue
        new = regenerate(text)
        if new != text:

            write_text_atomic(page, new)
        print(f"{name}: {len(BLOCK.findall(new))} generated blocks")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
