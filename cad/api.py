"""The supported Python API: every ``hapticad`` command as a function, on plain data and on
objects.

Everything else in :mod:`cad` is internal and may change. Lengths in mm, masses in g or kg
and inertias in kg m^2 as the dict keys say; frames as in docs/conventions.md. A
function returns what the command prints with ``--json`` (without the run's ``warnings``
list: :func:`cad.design.bounds.collected` holds them) and writes nothing unless writing is
what it is for (``build_design``, ``render``, ``sweep``, ``bench``). Bad input raises
:class:`cad.errors.DesignError` (a ``ValueError``) naming the field or option.

>>> import cad
>>> d = cad.load_design("designs/hoeken.toml")
>>> round(cad.analyze(d)["stroke_mm"], 2)
48.87

Objects: ``design.replace(**changes)`` (validated like a file, :mod:`cad.design.replace`);
``cad.assemble(design)`` the :class:`cad.assembly.model.AssemblyModel`, whose
``.compound()`` is a labelled, coloured build123d ``Compound`` (docs/python-api.md).

======================  ===================================================
command                 function
======================  ===================================================
``hapticad analyze``    :func:`analyze`
``hapticad bench``      :func:`run_bench`
``hapticad bench-log``  :func:`bench_log`
``hapticad build``      :func:`build_design` (and :func:`assemble` for the solids)
``hapticad cache``      :func:`cache`
``hapticad check``      :func:`check`
``hapticad datasheet``  :func:`device_datasheet`
``hapticad fit``        :func:`fit_design`
``hapticad gii``        :func:`gii`
``hapticad identify``   :func:`identify_device`
``hapticad massprops``  :func:`mass_properties`
``hapticad optimize``   :func:`optimize`
``hapticad render``     :func:`render`
``hapticad swap``       :func:`swap`
``hapticad sweep``      :func:`sweep_design`
``hapticad synth``      :func:`synth`
``hapticad tolerance``  :func:`tolerance`
``hapticad voicecoil``  :func:`voicecoil`
``hapticad wall``       :func:`wall`
======================  ===================================================

:data:`COMMANDS` is this table as data (tests/api/test_api_commands.py checks it against the
CLI). Importing :mod:`cad` stays light: CAD libraries load on the first call that needs them
(:func:`build_design`, :func:`assemble`, :func:`check`, :func:`mass_properties` of a STEP
file ...). This module imports no :mod:`cad.cli` (the CLI is built on it). It is the one
module of ``cad`` whose imports of the package stay inside its functions: it is the facade
of every command, and importing what all of them need would cost each ``hapticad`` call
about 0.5 s (166 modules and numpy, measured with ``python -c "import cad.api"``) for the
one it runs; every other module imports the package at module level (the CAD, plotting and
other heavy libraries stay inside functions).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

#: ``hapticad`` command -> the function of this module that does what it does.
COMMANDS = {
    "analyze": "analyze", "bench": "run_bench", "build": "build_design", "cache": "cache",
    "check": "check", "datasheet": "device_datasheet", "fit": "fit_design", "gii": "gii",
    "massprops": "mass_properties", "optimize": "optimize", "render": "render", "swap": "swap",
    "sweep": "sweep_design", "synth": "synth", "tolerance": "tolerance", "voicecoil": "voicecoil",
    "wall": "wall", "identify": "identify_device", "bench-log": "bench_log",
}
__all__ = sorted({*COMMANDS.values(), "assemble", "load_design"})


def _need_design(design) -> None:
    """DesignError naming ``design`` when it is not a loaded design (a path, None ...)."""
    from cad.errors import DesignError

    if not hasattr(design, "family") or not hasattr(design, "raw"):
        hint = " (load it first: cad.load_design(path))" if isinstance(design, (str, Path)) else ""
        raise DesignError("design", f"expected a design from cad.load_design, got "
                          f"{type(design).__name__} {design!r}"[:200] + hint)


def _script_allowed(design) -> None:
    """DesignError ``parts.handle_script`` (naming the opt-in) when the design's handle script
    is not allowed, before any search: a search's candidates would each be refused one by
    one (:func:`cad.parts.handle.resolve_script` holds the rule). Nothing without a script."""
    if getattr(getattr(design, "parts", None), "handle_script", None) is not None:
        from cad.parts.handle import resolve_script

        resolve_script(design.parts, design.source)


def _flag_numbers(**values) -> None:
    """Check keyword numbers against the bounds of the command's flags
    (:data:`cad.design.bounds.FLAGS`, keys ``--name-with-dashes``; None passes), as the CLI does."""
    from cad.design.bounds import FLAGS, check_number

    for key, value in values.items():
        if value is not None:
            flag = "--" + key.replace("_", "-")
            check_number(flag, value, FLAGS[flag])


def _choice(flag: str, value, choices) -> None:
    """DesignError naming ``flag`` when ``value`` is not one of ``choices``."""
    from cad.errors import DesignError

    if value not in choices:
        raise DesignError(flag, f"must be one of {', '.join(choices)}, got {value!r}")


def _targets(targets, field: str = "targets") -> tuple:
    """``targets`` as a tuple of strings (one string is one target); DesignError otherwise."""
    from cad.errors import DesignError

    if isinstance(targets, str):
        return (targets,)
    if targets is None or not isinstance(targets, (list, tuple, set, frozenset)) or not all(
            isinstance(t, str) for t in targets):
        raise DesignError(field, f"must be 'KEY=VALUE' strings (a list of them), got {targets!r}")
    return tuple(targets)


def load_design(path: str | Path):
    """Read and validate a TOML design (any family).

    Returns a frozen design object (``FourBarDesign``, ``PantographDesign`` or
    ``PowerMouseDesign``). Raises :class:`cad.errors.DesignError` (a ``ValueError``) naming
    the dotted field, the value and the reason.
    """
    from cad.design import load_design as _load
    from cad.errors import DesignError

    if not isinstance(path, (str, Path)):
        raise DesignError("design", f"expected a path to a TOML design, got {type(path).__name__} {path!r}")
    from cad.design.replace import with_slip_hint

    return with_slip_hint(_load, path)  # its error: the command's error line


def analyze(design, samples: int | None = None, inertia: dict[str, float] | None = None) -> dict:
    """Four-bar metrics (Hoeken paper Tables I/II), range check, apparent mass; no CAD.

    ``inertia``: optional ``{"H11": ..., "H12": ..., "H22": ..., "H33": ...}`` in kg m^2
    (Hoeken paper eqs 16-19). Returns the ``hapticad analyze --json`` object (schema: docs/commands.md).
    Raises DesignError for a non-four-bar design.
    """
    from cad.analysis import analyze as _analyze
    from cad.data.families import require

    _need_design(design)
    require("analyze", design.family)
    _flag_numbers(samples=samples)
    return _analyze(design, samples=samples, inertia=_inertia(inertia))


def build_design(design, out_dir: str | Path, formats=("step", "stl", "dxf"),
                 fidelity: str = "fabrication", **options: Any) -> dict:
    """Build the parts, the posed assembly and the exports into ``out_dir``; the report dict.

    ``formats``: any of the ``hapticad build --formats`` names. ``options``: the keyword
    options of :func:`cad.pipeline.build_design` (``allow_interference``, ``phi1_deg``,
    ``use_cache`` ...). Raises a :class:`cad.errors.HapticadError` subclass on bad input, a
    collision or a failed CAD operation; ``out_dir`` is then left as it was.
    """
    from cad.export import parse_formats
    from cad.pipeline import build_design as _build

    _need_design(design)
    if isinstance(formats, str):
        fmts = parse_formats(formats, "formats")
    elif isinstance(formats, (list, tuple, set, frozenset)) and all(isinstance(f, str) for f in formats):
        fmts = parse_formats(",".join(formats), "formats")
    else:
        from cad.errors import DesignError

        raise DesignError("formats", f"must be format names such as ('step', 'stl'), got {formats!r}")
    import inspect

    known = [n for n, p in inspect.signature(_build).parameters.items()
             if p.kind is p.KEYWORD_ONLY and n != "fidelity"]
    for key in options:
        if key not in known:
            from cad.errors import DesignError

            raise DesignError(key, f"unknown option of build_design (known: {', '.join(known)})")
    _flag_numbers(phi1_deg=options.get("phi1_deg"))
    return _build(design, Path(out_dir), fmts, fidelity=fidelity, **options)


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
    of ``rows``, in order) and ``targets_source`` (``design``, ``given`` or ``design+given``);
    with targets also ``limits_met`` and ``limit_warnings`` (the datasheet's default limits the
    design misses outside its targets: warning lines; ``ok`` follows the targets).
    Without targets the rows are the default limits (:mod:`cad.datasheet.limits`).
    Raises DesignError when the family has no check, or for a target whose figure the family
    does not compute (naming ``--target.KEY`` / ``targets.KEY``).
    """
    from cad.checks import evaluate, merge_targets
    from cad.design.targets import parse_cli_target
    from cad.errors import DesignError

    if fidelity not in ("inertia", "fabrication"):
        raise DesignError("--fidelity", f"must be inertia or fabrication, got {fidelity!r}")
    from cad.data.families import require

    _need_design(design)
    require("check", design.family)
    hooks = _target_hooks(design, "check")
    given = tuple(parse_cli_target(t, hooks.keys) for t in _targets(targets))  # one str: one target
    merged = merge_targets(design.targets, given) if merge or not given else given
    source = "design+given" if merge and given else ("given" if given else "design")
    if not merged:  # no targets: the default limits of the datasheet (cad.datasheet.limits)
        from cad.datasheet.run import device_datasheet, limit_rows

        ds = device_datasheet(design, fidelity)
        rows = limit_rows(ds)
        return {"name": design.name, "ok": all(r["ok"] for r in rows), "fidelity": fidelity,
                "rows": rows, "computed": {r["key"]: r["value"] for r in ds["rows"]},
                "budget": None, "targets_checked": [r["key"] for r in rows],
                "targets_source": "default limits", "limit_warnings": list(ds["warnings"]),
                "checked": "default limits (no [targets]): cad/datasheet/limits.py"}
    wanted = {t.key for t in merged}
    values, report = hooks.values(design, fidelity, wanted)
    _refuse_not_computed(design, merged, values, {t.key for t in given})
    rows = evaluate(merged, values)
    warnings = _missed_limits(design, fidelity, wanted)
    if hooks.blockers is not None:  # a missed target: what in the layout blocks it
        warnings += hooks.blockers(design, report, rows)
    return {"name": design.name, "ok": all(r.ok for r in rows), "fidelity": fidelity,
            "targets_checked": [r.key for r in rows], "targets_source": source,
            "rows": [r.as_dict() for r in rows], "computed": values,
            "budget": report.get("budget"), "limits_met": not warnings,
            "limit_warnings": warnings}


def _target_hooks(design, command: str):
    """The family's :class:`cad.families.protocol.TargetHooks`; DesignError naming
    ``mechanism.family`` when it has none (the registry lets ``command`` through)."""
    from cad.data.families import refusal
    from cad.errors import DesignError
    from cad.families import family_package

    hooks = family_package(design.family).targets
    if hooks is None:
        raise DesignError("mechanism.family", refusal(command, design.family))
    return hooks


def _missed_limits(design, fidelity: str, checked: set[str]) -> list[str]:
    """The datasheet's warning lines (:func:`cad.datasheet.judge`) of the default limits a
    design misses, other than the figures ``checked`` as targets: a check with ``[targets]``
    says so too (its exit status follows the targets, as ``fit``'s does)."""
    from cad.datasheet.run import device_datasheet

    ds = device_datasheet(design, fidelity)
    missed = [r for r in ds["rows"] if r.get("verdict") == "miss"]  # judge's order
    return [w for r, w in zip(missed, ds["warnings"], strict=True) if r["key"] not in checked]


def mass_properties(path: str | Path, density_kg_m3: float | None = None,
                    material: str | None = None) -> dict:
    """Mass, COM (mm, file frame) and inertia tensor about the COM (kg m^2) of a STEP or STL.

    Returns the ``hapticad massprops --json`` object, ``warnings`` included (e.g. a cavity
    shell read as a cavity, duplicate facets dropped, a mesh too small for mm). Without
    density or material the default material is used (a note in ``notes``). Raises
    DesignError / MeshError / GeometryError naming the file and the fault.
    """
    from cad.design import bounds
    from cad.errors import DesignError
    from cad.pipeline.file_props import compute

    if not isinstance(path, (str, Path)):
        raise DesignError("FILE", f"expected the path of a STEP or STL file, got {path!r}")
    dens = None if density_kg_m3 is None else str(density_kg_m3)
    bounds.reset()  # this call's warnings only, as one CLI command
    out, notes = compute(Path(path), dens, material)
    return {**out, "notes": notes, "warnings": bounds.collected()}


def gii(design) -> dict:
    """Global isotropy index (isotropy paper eq 5) of a pantograph-family design.

    Returns the ``hapticad gii --json`` object (``gii``, ``sigma_min``, ``sigma_max`` and
    where they occur). Raises DesignError for other families.
    """
    from cad.data.families import require
    from cad.isotropy.report import gii_report

    _need_design(design)
    require("gii", design.family)
    return gii_report(design)


def assemble(design, fidelity: str = "fabrication"):
    """The device laid out as part instances: a :class:`cad.assembly.model.AssemblyModel`.

    ``fidelity``: ``fabrication`` (every feature), ``inertia`` or ``preview`` (cheaper
    solids: docs/design-files.md, ``fidelity``). Dispatched through the family registry
    (:mod:`cad.data.families`) to ``cad.families.<package>.assemble``. ``model.compound()``
    is a labelled, coloured build123d ``Compound`` (one child per instance, world frame, mm).
    Raises DesignError naming ``mechanism.family`` for a family with no parts (no package or
    no ``assemble``), ``fidelity`` for an unknown fidelity. Imports the CAD libraries.
    """
    from cad.design.parts import FIDELITIES
    from cad.errors import DesignError
    from cad.families import family_package

    if fidelity not in FIDELITIES:
        raise DesignError("fidelity", f"must be one of {', '.join(FIDELITIES)}, got {fidelity!r}")
    _need_design(design)
    fam = family_package(design.family)  # DesignError: an unknown family
    if fam.assemble is None:
        raise DesignError("mechanism.family", f"{design.family} designs have no parts to "
                                              f"assemble yet")
    return fam.assemble(design, fidelity=fidelity)


def voicecoil(magnet_length_mm: float, magnet_width_mm: float, magnet_thickness_mm: float,
              rattle_mm: float, power_W: float | None = None, br_T: float | None = None,
              resistivity_ohm_m: float | None = None, eta_pack: float | None = None,
              model: str = "closed-form", gap_mm: float | None = None,
              gap_max_mm: float | None = None) -> dict:
    """Optimal gap of a flat voice-coil actuator (isotropy paper eqs 8-9, Fig. 8).

    Lengths mm, power W, remanence T, resistivity ohm m; None takes the command's default
    (8 W, 1.2 T, copper, 0.75). Returns the ``hapticad voicecoil --json`` object
    (``optimal_gap_mm``, ``coil_width_mm``, ``Bg_T``, ``force_N`` ...; with ``gap_mm`` also
    the field and force there). Raises DesignError naming the parameter. No CAD.
    """
    from cad.actuators import voicecoil as vc
    from cad.actuators.report import voicecoil_report
    from cad.design.bounds import FLAGS, check_number

    given = {"magnet_length_mm": magnet_length_mm, "magnet_width_mm": magnet_width_mm,
             "magnet_thickness_mm": magnet_thickness_mm, "rattle_mm": rattle_mm,
             "power_W": power_W, "br_T": br_T, "resistivity_ohm_m": resistivity_ohm_m,
             "eta_pack": eta_pack, "gap_mm": gap_mm, "gap_max_mm": gap_max_mm}
    flag = {"resistivity_ohm_m": "--rho-ohm-m"}  # the others: --name-with-dashes
    for key, value in given.items():  # the command's bounds (a slip in metres is refused)
        if value is not None and isinstance(value, (int, float)) and not isinstance(value, bool):
            check_number(key, value, FLAGS[flag.get(key, "--" + key.replace("_", "-"))])
    params = vc.VoiceCoilParams(
        magnet_length_mm, magnet_width_mm, magnet_thickness_mm, rattle_mm,
        vc.POWER_DEFAULT_W if power_W is None else power_W,
        vc.BR_DEFAULT_T if br_T is None else br_T,
        vc.RHO_COPPER_OHM_M if resistivity_ohm_m is None else resistivity_ohm_m,
        vc.ETA_PACK_DEFAULT if eta_pack is None else eta_pack)
    return voicecoil_report(params, model, gap_mm, gap_max_mm)


def cache(clear: bool = False) -> dict:
    """Where hapticad's disk caches are and their size per folder (``hapticad cache --json``:
    ``cache_dir``, ``enabled``, ``max_MB``, ``total_MB``, ``folders``); ``clear`` first
    removes every cache entry hapticad wrote there (then ``removed``). Raises DesignError
    for a bad ``HAPTICAD_CACHE_MAX_MB``."""
    from cad.errors import DesignError
    from cad.io.cache_report import cache_summary

    if not isinstance(clear, bool):  # "no" is truthy: it would clear the cache
        raise DesignError("clear", f"must be True or False, got {clear!r}")
    return cache_summary(clear)


def device_datasheet(design, fidelity: str = "inertia") -> dict:
    """The device datasheet (``hapticad datasheet --json`` without ``warnings``): ``name``,
    ``family``, ``fidelity`` and ``datasheet`` (every figure with value, unit, source and
    verdict; ``datasheet["warnings"]`` the missed limits). ``fidelity``: inertia,
    fabrication or preview. Raises DesignError for a family without a datasheet (naming
    ``mechanism.family``) or a design that cannot be built. Builds (or reads the cache)."""
    from cad.data.families import require
    from cad.datasheet.run import device_datasheet as _datasheet
    from cad.design.parts import FIDELITIES
    from cad.errors import DesignError

    if fidelity not in FIDELITIES:
        raise DesignError("--fidelity", f"must be one of {', '.join(FIDELITIES)}, got {fidelity!r}")
    _need_design(design)
    require("datasheet", design.family)
    if hasattr(design, "check_buildable"):
        design.check_buildable()
    ds = _datasheet(design, fidelity)
    return {"name": design.name, "family": design.family, "fidelity": fidelity, "datasheet": ds}


def wall(design, K_N_per_m: float | None = None, B_N_s_per_m: float = 0.0,
         Te_s: float | None = None, encoder_counts_per_rev: int | None = None,
         model: str = "reduced", build_dir: str | Path | None = None) -> dict:
    """Largest stable virtual-wall stiffness of a four-bar (``hapticad wall --json``):
    ``K_max_stable_N_per_m`` for damping ``B_N_s_per_m`` beside eq (25) and the passivity
    bound; with ``K_N_per_m`` also whether that wall is stable. ``model``: reduced | mujoco.
    Defaults from the design's ``[stiffness]`` (:func:`cad.sim.device.wall_inputs`).
    Raises DesignError for another family (``mechanism.family``) or a bad value."""
    from cad.data.families import require
    from cad.sim.device import wall_report
    from cad.sim.wall import MODELS, check_sampling_period

    _need_design(design)
    require("wall", design.family)
    _choice("--model", model, MODELS)
    _flag_numbers(K_N_per_m=K_N_per_m, B_N_s_per_m=B_N_s_per_m, Te_s=Te_s,
                  encoder_counts_per_rev=encoder_counts_per_rev)
    if Te_s is None and design.stiffness is not None:  # the design's period: name its key
        check_sampling_period(design.stiffness.Te_s, "stiffness.Te_s")
    return wall_report(design, K=K_N_per_m, B=B_N_s_per_m, Te_s=Te_s,
                       counts_per_rev=encoder_counts_per_rev, model=model,
                       build_dir=None if build_dir is None else Path(build_dir))


def optimize(design, method: str | None = None, objective: str | None = None, trials: int = 300,
             seed: int = 0, exact_top: int = 3, proportions_tol: float = 0.0,
             starts: bool = True, beat_prototype: bool = False, workers: int | None = None,
             scheduler: str | None = None, study: str | Path | None = None) -> dict:
    """Maximize the GII (pantograph families: ``method`` culling | brute, isotropy paper eq 6
    over the design's ``[optimize]`` grid) or minimize the apparent mass (four-bars:
    ``objective`` min-apparent-mass, the co-design search of :mod:`cad.studies.codesign`).

    Returns the ``hapticad optimize --json`` object without the file keys (``command``,
    ``measured``, ``out``, ``replaced*``): pantographs ``best``, ``gii``, evaluations ...,
    ``targets`` (the design's ``[targets]`` evaluated on the optimum: check rows) and
    ``misses`` (their ``target missed:`` lines; the CLI exits 1 when not empty);
    four-bars ``best`` (None when no candidate passed the exact solids), ``trials`` ...,
    ``misses`` (the design's ``[targets]`` the chosen optimum misses on the exact solids:
    ``key``, ``target_text``, ``written``, ``best`` reached; the CLI exits 1 when not empty);
    ``beat_prototype``: the issue 24 §4 limits (:mod:`cad.studies.codesign.prototype`), the
    report's ``prototype`` entry. ``workers`` (an embedded Dask LocalCluster) or ``scheduler``
    (``tcp://HOST:PORT``) run a four-bar's trials on Dask with the optuna journal in the folder
    ``study`` (resumable: the same call again tops up to ``trials``;
    :mod:`cad.studies.codesign.distributed`, ``hapticad optimize --workers/--scheduler/--study``).
    Raises DesignError naming the option or ``mechanism.family``.
    """
    from cad.data.families import family, require
    from cad.errors import DesignError
    from cad.families import family_package

    _need_design(design)
    require("optimize", design.family)
    _script_allowed(design)
    _flag_numbers(trials=trials, exact_top=exact_top, proportions_tol=proportions_tol)
    from cad.studies.codesign.distributed import placement

    where = placement(workers, scheduler, study)
    if where is not None and family(design.family).group != "four-bar":
        raise DesignError("--scheduler" if scheduler is not None else "--workers",
                          f"the Dask search is for four-bar designs, not {design.family!r} (the GII culling "
                          "runs in this process)")
    options = {"method": method, "objective": objective, "trials": trials, "seed": seed,
               "exact_top": exact_top, "proportions_tol": proportions_tol, "starts": starts,
               "beat_prototype": beat_prototype, "where": where}
    return family_package(design.family).optimize(design, options)


def render(designs, out_dir: str | Path = "docs/devices", fidelity: str | None = None) -> list:
    """Shaded picture and stroke GIF of each design (paths or loaded designs), from its build
    in a temporary folder, written to ``out_dir/<name>.png`` and ``.gif``; the
    ``hapticad render --json`` ``rendered`` list (``design``, ``name``, ``png``, ``gif``).
    Raises DesignError (nothing written) for a family without pictures or a clash of names."""
    from cad.pipeline.render import render_designs

    if isinstance(designs, (str, Path)) or hasattr(designs, "family"):  # one design, not its characters
        designs = [designs]
    return render_designs(list(designs), Path(out_dir), fidelity)


def synth(design, objective: str = "max-stroke", free: str = "range", dy_tol_mm: float = 0.2,
          mu_min_deg: float = 30.0, stroke_mm: float | None = None) -> dict:
    """Link lengths and crank range of a four-bar for a stated objective (``hapticad synth``).

    ``objective``: max-stroke | min-torque-variation; ``free``: range | all; ``dy_tol_mm``
    the allowed max |y| (mm); ``mu_min_deg`` the minimum transmission angle; ``stroke_mm``
    the stroke to hold (default the design's ``mechanism.stroke_mm``). Returns the
    ``hapticad synth --json`` object without ``command`` / ``measured`` / ``out`` keys
    (``feasible``, ``evaluations``, ``start``, ``result`` ...) plus ``mechanism``: the
    result's ``[mechanism]`` table (family custom; ``design.replace(mechanism=...)`` makes the
    design of it). Raises DesignError for another family or a stroke no linkage reaches.
    """
    from cad import tolerances as tol
    from cad.data.families import require
    from cad.design.writer import custom_mechanism_table
    from cad.errors import DesignError
    from cad.kinematics.synthesis import synthesize

    _need_design(design)
    require("synth", design.family)
    _flag_numbers(stroke_mm=stroke_mm, dy_tol_mm=dy_tol_mm, mu_min_deg=mu_min_deg)
    held_mm = stroke_mm or (design.stroke_mm_requested or None)
    r = synthesize(design.linkage, design.phi1_min_rad, design.phi1_max_rad, objective,
                   free=free, dy_tol_mm=dy_tol_mm, mu_min_deg=mu_min_deg, stroke_mm=held_mm,
                   force_N=design.force_N)
    got = r.metrics.stroke_mm
    if held_mm is not None and not abs(got - held_mm) <= tol.SYNTH_STROKE_REL * held_mm:
        raise DesignError("--stroke-mm" if stroke_mm is not None else "mechanism.stroke_mm",
                          f"no linkage of this family reaches a stroke of {held_mm:g} mm within "
                          f"the constraints (none found; the start has {got:.4g} mm): change "
                          "--objective, --free, --dy-tol-mm or the stroke")
    mech = custom_mechanism_table(r.linkage, r.phi1_min_rad, r.phi1_max_rad, design.force_N)
    return {
        "objective": objective, "free": free, "feasible": r.feasible,
        "evaluations": r.evaluations, "stroke_mm_held": held_mm,
        "stroke_upper_bound_mm": r.upper_bound_mm,
        "start": {**design.resolved_linkage(), **r.start_metrics.as_dict()},
        "result": {**{k: v for k, v in mech.items() if k != "family"}, **r.metrics.as_dict()},
        "mechanism": mech,
    }


def swap(design, to: str, out: str | Path | None = None, name: str | None = None) -> dict:
    """The same joint hardware with another straight-line bar set (``hapticad swap``): the
    four-bar swapped to ``to`` (hoeken | roberts | chebyshev | chebyshev-v) at the same stroke.

    ``out``: where the new design would be written (relative paths of the design are rebased
    there; default ``<stem>_<family>.toml`` beside the design's file; nothing is written);
    ``name``: its name (default ``<name>__<family>``). Returns ``old`` / ``new`` metrics and
    ``layers`` (as ``hapticad swap --json``), ``design`` (the new validated design), ``raw``
    (its TOML mapping) and ``dropped`` (targets not carried over). Raises DesignError for
    another family (``mechanism.family``), an unknown ``to`` or a bar set no layer order clears.
    """
    from cad.data.families import require
    from cad.families.fourbar.swap import SWAP_FAMILIES as _TO
    from cad.families.fourbar.swap import swap as _swap

    _need_design(design)
    require("swap", design.family)
    _choice("--to", to, _TO)
    src = Path(design.source)
    target = Path(out) if out is not None else src.with_name(f"{src.stem}_{to.replace('-', '_')}.toml")
    return _swap(design, to, target, name)


def _inertia(inertia: dict[str, float] | None):
    """``{"H11": .., "H12": .., "H22": .., "H33": ..}`` (kg m^2, ``_kg_m2`` suffixes allowed)
    as InertiaCoefficients, each checked against its bounds; None stays None."""
    if inertia is None:
        return None
    from cad.design.bounds import FIELDS, check_number
    from cad.dynamics.inertia import InertiaCoefficients
    from cad.errors import DesignError

    if not isinstance(inertia, dict):
        raise DesignError("inertia", f"must be a mapping {{'H11': .., 'H12': .., 'H22': .., "
                          f"'H33': ..}} (kg m^2), got {inertia!r}")
    vals = {str(k).removesuffix("_kg_m2"): v for k, v in inertia.items()}
    missing = sorted({"H11", "H12", "H22", "H33"} - set(vals))
    if missing or len(vals) != 4:
        raise DesignError("inertia", f"expected H11, H12, H22 and H33 (kg m^2), got {sorted(vals)}")
    return InertiaCoefficients(*(check_number(f"inertia.{k}_kg_m2", vals[k], FIELDS[f"inertia.{k}_kg_m2"])
                                 for k in ("H11", "H12", "H22", "H33")))


def tolerance(design, hole_mm: float | None = None, hole=(), pivot_mm: float | None = None,
              pivot=(), length_mm: float | None = None, length=(), distribution: str = "normal",
              samples: int = 10000, seed: int = 0, angles: int = 401, targets=(),
              inertia: dict[str, float] | None = None) -> dict:
    """Monte Carlo of hole, pivot and length tolerances of a four-bar (``hapticad tolerance``):
    distributions, yield against the targets, sensitivity (docs/tolerances.md).

    ``hole_mm`` / ``pivot_mm`` / ``length_mm``: +- mm on every bar hole / base pivot / link
    length; ``hole``, ``pivot``, ``length``: the specific ``"BAR.HOLE=T[:dist]"``,
    ``"A4=T"``, ``"l2=T"`` strings of the flags; ``distribution`` normal (T = 3 sigma) or
    uniform; ``targets``: ``"KEY<=V"`` strings added to the design's; ``inertia`` as in
    :func:`analyze` (default the design's ``[inertia]``, else the solids). Returns the
    ``hapticad tolerance --json`` object (without ``files``). Raises DesignError.
    """
    from cad.design import bounds
    from cad.design.targets import parse_cli_target
    from cad.studies.tolerance_study import tolerances_from_flags

    _need_design(design)
    _flag_numbers(hole_mm=hole_mm, pivot_mm=pivot_mm, length_mm=length_mm, seed=seed)
    bounds.check_work("tolerance", [("--samples", samples), ("--angles", angles)])
    tols = tolerances_from_flags(hole_mm, list(_targets(hole, "hole")), pivot_mm,
                                 list(_targets(pivot, "pivot")), length_mm,
                                 list(_targets(length, "length")), distribution)
    given = tuple(parse_cli_target(t) for t in _targets(targets))
    return tolerance_run(design, tols, given, _inertia(inertia), samples, seed, angles)[0]


def tolerance_run(design, tols, given, H, samples: int, seed: int, angles: int):
    """The tolerance study of :func:`tolerance` from parsed inputs (Tolerance tuple, Target
    tuple, InertiaCoefficients or None): ``(result dict, per-sample metrics, targets)``."""
    from cad.checks import merge_targets
    from cad.data.families import require
    from cad.design import bounds
    from cad.errors import DesignError
    from cad.kinematics.tolerance import METRIC_KEYS
    from cad.studies.tolerance_study import inertia_for_m11, run

    require("tolerance", design.family)
    H, h_source = inertia_for_m11(design, H)
    for t in given:
        if t.key not in METRIC_KEYS:
            raise DesignError("--target", f"{t.key} is not computed by the tolerance study "
                              f"(it computes {', '.join(METRIC_KEYS)})")
    skipped = [t.key for t in design.targets if t.key not in METRIC_KEYS]
    if skipped:
        bounds.warn(f"[targets] {', '.join(skipped)}: not computed by the tolerance study "
                    "(kinematics and M11 only); not in the yield")
    merged = merge_targets(design.targets, given)
    res, m = run(design, tols, samples, seed, angles, H, merged)
    res["inertia_source"] = h_source
    res["inertia_kg_m2"] = H.as_dict()
    return res, m, merged


def fit_design(design, targets=(), free=(), fidelity: str = "inertia", echo=None,
               trials: int | None = None) -> dict:
    """Adjust free parameters of a design to meet targets (``hapticad fit``).

    ``targets``: ``"KEY=VALUE"``, ``"KEY<=V"``, ``"KEY>=V"`` strings (default the design's
    ``[targets]``); ``free``: ``"parts.KEY"`` or ``"parts.KEY=LO:HI"`` (pantographs also
    ``mechanism.KEY``; default the design's ``[fit] free``); ``fidelity``: inertia |
    fabrication; ``echo``: None or a callable receiving one progress line per evaluation;
    ``trials``: the evaluation budget of a TPE search (default ``12 + 6 x`` the free
    parameters; a grid of choices is always evaluated whole).
    Returns the ``hapticad fit --json`` object without the file keys (``start``, ``fitted``,
    ``met`` (the targets), ``limits_met``, ``limit_warnings``, ``max_violation``,
    ``evaluations`` (built), ``rejected_pre_cad``, ``iterations``, ``rows``: the targets, then
    every default datasheet limit (four-bars)) plus ``design``
    (the fitted design, validated) and ``raw`` (its TOML mapping). Nothing is written.
    Raises DesignError (no targets, no free parameter, another family ...).
    """
    from cad.errors import DesignError

    if fidelity not in ("inertia", "fabrication"):
        raise DesignError("--fidelity", f"must be inertia or fabrication, got {fidelity!r}")
    _need_design(design)
    _flag_numbers(trials=trials)
    setup = fit_setup(design, _targets(targets), _targets(free, "free"))
    return fit_run(design, setup, fidelity, Path(design.source), f"{design.name}_fit", echo,
                   trials)


def fit_setup(design, targets: tuple[str, ...], free: tuple[str, ...]) -> dict:
    """The parsed targets and free parameters of :func:`fit`, checked before any search."""
    from cad.checks import merge_targets
    from cad.data.families import require
    from cad.design.targets import parse_cli_target
    from cad.errors import DesignError

    require("fit", design.family)
    _script_allowed(design)
    hooks = _target_hooks(design, "fit")
    if hasattr(design, "check_buildable"):  # links shorter than their hardware: before a search
        design.check_buildable()
    given = tuple(parse_cli_target(t, hooks.keys) for t in targets)
    merged = given if given else merge_targets(design.targets, ())
    if not merged:
        raise DesignError("--target", "no targets: give --target KEY=VALUE or a [targets] table")
    specs = list(free) if free else list(getattr(design, "fit_free", ()))
    if not specs:
        raise DesignError("--free", "no free parameters: give --free parts.KEY (four-bars), "
                                    "mechanism.KEY / parts.KEY (pantographs) or [fit] free")
    params = [hooks.parse_free(s, design) for s in specs]
    seen = [q.path for q in params]
    twice = next((k for i, k in enumerate(seen) if k in seen[:i]), None)
    if twice is not None:
        raise DesignError("--free", f"{twice} is given twice; give each free parameter once")
    return {"hooks": hooks, "given": given, "targets": merged, "params": params}


def fit_run(design, setup: dict, fidelity: str, dest: Path, name: str, echo=None,
            trials: int | None = None) -> dict:
    """Run the fit of ``setup`` (:func:`fit_setup`) with the evaluation budget ``trials``
    (None: the default, :func:`fit_design`); the fitted mapping as a file at ``dest`` named
    ``name`` would hold it (relative paths rebased)."""
    import copy

    from cad.checks import evaluate
    from cad.design import parse_design
    from cad.design.writer import rebase_paths
    from cad.studies.fit import fit as _fit

    hooks, targets, params = setup["hooks"], setup["targets"], setup["params"]
    # every default datasheet limit the family names is a constraint of each candidate (its
    # own material's stress limit); the pre-CAD checks reject candidates before any build
    limits = hooks.fit_limits
    # the limits' figures are evaluated with the targets' (a family that builds only for the
    # figures asked would otherwise leave them uncomputed)
    wanted = {t.key for t in targets} | {t.key for t in (limits(design) if limits else ())}
    values = hooks.fit_values or hooks.values

    def values_of(dd) -> dict:
        return values(dd, fidelity, wanted)[0]

    if echo:
        echo(f"fit {design.name}: {len(params)} free parameter(s), {len(targets)} target(s)")
    res = _fit(dict(design.raw), str(design.source), targets, params, values_of, echo=echo,
               limit_targets=limits, precad=hooks.precad, trials=trials)
    fitted = rebase_paths(copy.deepcopy(res.raw), design.source, dest)
    fitted["name"] = name
    if setup["given"]:  # keep the targets the fit was made for
        fitted["targets"] = _targets_table(fitted.get("targets", {}), setup["given"])
    final = parse_design(fitted, str(dest))
    lim_t = tuple(limits(final)) if limits else ()
    vals, rep = values(final, fidelity, wanted)
    rows = evaluate(tuple(targets) + lim_t, vals)
    blockers = hooks.blockers(final, rep, rows) if hooks.blockers is not None else []
    # exit status from the targets (as before); a missed default limit is a warning, as in the
    # datasheet (the search already ranked every candidate meeting the limits first)
    missed = [f"{r.key} = {'not computed' if r.computed is None else f'{r.computed:.4g}'}, limit {r.target}"
              for r in rows[len(targets):] if not r.ok]
    if limits is None and rep.get("bodies"):  # a family without fit limits: its datasheet's, said
        from cad.datasheet import datasheet, default_limit_misses

        missed += default_limit_misses(rep.get("datasheet") or datasheet(final, rep, simulate_wall=False))
    return {"name": design.name, "start": res.start, "fitted": res.values,
            "met": all(r.ok for r in rows[:len(targets)]), "limits_met": not missed,
            "limit_warnings": missed, "max_violation": res.objective,
            "evaluations": len(res.log) - res.rejected_pre_cad, "rejected_pre_cad": res.rejected_pre_cad,
            "iterations": res.log, "rows": [r.as_dict() for r in rows], "blockers": blockers,
            "design": final, "raw": fitted}


def _refuse_not_computed(design, targets, values: dict, given_keys: set) -> None:
    """DesignError for the first target whose key the family never computes for ``design``
    (no value after its evaluation: e.g. ``compliance_x_um_per_N`` of a haptic pen, whose
    compliance rows are vertical / radial / normal), naming ``--target.KEY`` or
    ``targets.KEY`` -- bad input (exit 2), not a missed target (exit 1)."""
    from cad.errors import DesignError

    for t in targets:
        if values.get(t.key) is None:
            field = f"--target.{t.key}" if t.key in given_keys else f"targets.{t.key}"
            raise DesignError(field, f"not computed for a {design.family} design: its build gives no "
                                     "such figure (`hapticad datasheet` lists the figures it gives)")


def _targets_table(table: dict, given) -> dict:
    """The ``[targets]`` table ``table`` with the ``given`` targets (:class:`Target`) set."""
    tt = dict(table)
    for t in given:
        tt[t.key] = ({"value": t.value, "tol_rel": t.tol_rel} if t.value is not None and t.tol_abs is None
                     else {"value": t.value, "tol_abs": t.tol_abs} if t.value is not None
                     else {k: v for k, v in (("min", t.min), ("max", t.max)) if v is not None})
    return tt


def sweep_design(design: str | Path, vary, out_dir: str | Path, samples: int | None = None,
          fidelity: str = "inertia", workers: int = 2, scheduler: str | None = None, targets=(),
          chart: str = "torque_variation,M11_max_g", seed: int = 0) -> dict:
    """Evaluate many variants of a four-bar design file on Dask (``hapticad sweep``).

    ``design``: the TOML file (its workers reload it); ``vary``: ``"KEY=V1,V2,..."`` or
    ``"KEY=LO:HI:N"`` strings (dotted design keys); ``out_dir``: the folder of
    results.parquet/.csv, sweep.json, chart.png (a sweep there resumes); ``samples``: Latin
    hypercube samples instead of every combination; ``scheduler``: ``tcp://HOST:PORT`` of an
    existing Dask scheduler, else ``workers`` local processes; ``targets`` as in
    :func:`check`; ``chart``: ``"X,Y"`` columns. Returns the ``hapticad sweep --json``
    summary (``variants``, ``ok``, ``missed``, ``error``, ``lost``, ``resumed``, ``wall_s``
    ...). Raises DesignError naming the option or the design key.
    """
    from cad.errors import DesignError

    if not isinstance(design, (str, Path)):  # its workers reload the file
        raise DesignError("design", f"sweep_design takes the design file's path, got "
                          f"{type(design).__name__}"
                          + (f" (give {design.source!r})" if hasattr(design, "source") else ""))
    design, out = Path(design), Path(out_dir)
    from cad.design.fields import load_toml
    from cad.design.targets import parse_cli_target
    from cad.errors import DesignError
    from cad.studies.sweep.run import SweepSpec, run_sweep
    from cad.studies.sweep.spec import parse_vary
    from cad.studies.sweep.table import check_folder
    from cad.studies.sweep.task import VALUE_KEYS

    vary = _targets(vary, "vary")
    targets = (targets,) if isinstance(targets, str) else tuple(targets)
    if not vary:
        raise DesignError("--vary", "give at least one --vary KEY=V1,V2,... or KEY=LO:HI:N")
    varies = tuple(parse_vary(v) for v in vary)
    from cad.design.bounds import FIELDS, check_number

    for v in varies:  # every value of a varied key within its bounds (cad/design/bounds.py)
        if v.key in FIELDS:
            for x in v.grid():
                if not isinstance(x, (int, float)) or isinstance(x, bool):
                    raise DesignError(f"--vary {v.key}", f"must be a number, got {x!r}")
                check_number(f"--vary {v.key}", x, FIELDS[v.key])
    keys = [v.key for v in varies]
    if len(set(keys)) != len(keys):
        raise DesignError("--vary", "a key is varied twice")
    if samples is not None and not 1 <= samples <= 100_000:
        raise DesignError("--samples", f"must be in [1, 100000], got {samples}")
    if fidelity not in ("inertia", "fabrication"):
        raise DesignError("--fidelity", f"must be inertia or fabrication, got {fidelity!r}")
    from cad.studies.cluster import check_flags

    check_flags(workers, scheduler)
    xy = tuple(c.strip() for c in chart.split(","))
    if len(xy) != 2 or not all(c in VALUE_KEYS for c in xy):
        raise DesignError("--chart", f"expected X,Y with X and Y in {', '.join(VALUE_KEYS)}, got {chart!r}")
    cli = tuple(parse_cli_target(t) for t in targets)
    raw = load_toml(design)
    from cad.data.families import command_families, refusal
    from cad.design import family_of, parse_design

    fam = family_of(raw)
    if fam not in command_families()["sweep"]:
        raise DesignError("mechanism.family", refusal("sweep", fam))
    if "handle_script" in (raw.get("parts") or {}) or any(v.key == "parts.handle_script"
                                                            for v in varies):
        raise DesignError("parts.handle_script", "sweep never runs design scripts (its "
                          "workers would run them unseen); sweep a design without one")
    parse_design(raw, str(design))  # the base design as every command loads it (load_design)
    _sweep_check_keys(raw, design, varies)
    # only a folder hapticad wrote (docs/reliability.md "Output folders"); a dead run's temporary
    # files removed and its interrupted table write completed first (cad.studies.sweep.table)
    check_folder(out, str(design))
    spec = SweepSpec(design=design.resolve(), raw=raw, varies=varies, samples=samples, seed=seed,
                     fidelity=fidelity, cli_targets=cli, chart=xy,
                     targets_text=";".join(sorted(t or "" for t in targets)))
    return run_sweep(spec, out, workers, scheduler)


def _sweep_check_keys(raw: dict, design: Path, varies) -> None:
    """Exit 2 on a --vary key the design schema does not know (a typo would fail every variant)."""
    from cad.design import parse_design
    from cad.errors import DesignError
    from cad.studies.sweep.spec import apply

    for v in varies:
        first = v.grid()[0]
        try:
            parse_design(apply(raw, {v.key: first}), str(design))
        except DesignError as exc:
            named = exc.field == v.key or v.key.startswith(exc.field + ".")
            if named and ("unknown key" in exc.reason or "not a table" in exc.reason):
                raise DesignError(f"--vary {v.key}", exc.reason) from None
        except Exception:  # noqa: S110 - other failures are a variant's business (a row with its error)
            pass


def run_bench(out_dir: str | Path = "exports/bench", quick: bool = False, only: str | None = None,
          echo=None) -> dict:
    """Speed against accuracy (``hapticad bench``): error-against-time charts for every
    method with an accuracy knob and the performance goals, written to ``out_dir``
    (``bench.json`` and charts). ``only``: comma list of topics (:data:`cad.bench.run.TOPICS`);
    ``echo(topic)`` is called before each. Returns the ``bench.json`` object (``goals``:
    goal, measured, target, met). Minutes of CPU; raises DesignError for an unknown topic."""
    from cad.bench.run import run_bench as _run

    return _run(Path(out_dir), quick, only, echo)


def _ident_kit(design):
    """The design's :class:`cad.sim.identify_kits.IdentifyKit` (its kinematic model's)."""
    from cad.firmware import linkage_model

    return linkage_model(design).identification


def identify_device(design, log_path: str | Path, build_dir: str | Path | None = None,
             out: str | Path | None = None) -> dict:
    """Identify a built device (a four-bar or a 5-bar pantograph) from a log in the
    identification format (``hapticad identify --json``; docs/identify.md): the apparent mass
    (four-bar: along the path at the log's poses; 5-bar: at the handle along x and y at
    home), Coulomb and viscous friction, gravity and offsets, each encoder's direction and each
    current gain's sign, each with one standard deviation and a verdict against the prediction
    of the design's build (``build_dir``: a finished ``build --formats mjcf``, default the
    cached simulator build). With ``out`` writes ``identify.json``, ``identify.md`` and the
    fit and residual plots there.
    Raises DesignError for another family (``mechanism.family``), FileRefused / FileDamaged
    (field ``LOG``) for a log that is not a regular file, too large, or bad (its one line)."""
    from cad.data.families import require
    from cad.device import resolve_device
    from cad.firmware.spec import motor_data
    from cad.identify.logfile import parse_log
    from cad.io import guard

    _need_design(design)
    require("identify", design.family)
    kit = _ident_kit(design)
    if build_dir is not None:  # a bad --build-dir is named before the log is read
        kit.check_build_dir(design, Path(build_dir))
    text = guard.read_text(log_path, "log", "LOG")
    limits = [motor_data(m.spec).current_continuous_A for m in resolve_device(design).motors]
    log = parse_log(text, log_path, kit.n_joints, limits if len(limits) == kit.n_joints else limits[0])
    pred = kit.predict_from_build(design, None if build_dir is None else Path(build_dir))
    if log.design_hash != pred.design_hash:
        from cad.design import bounds

        bounds.warn(f"LOG: {log_path} names design hash {log.design_hash[:12]}..., not {design.name}'s "
                    f"{pred.design_hash[:12]}...: recorded with another design?")
    res, fit = kit.identify(pred, log, log_path)
    if out is not None:
        from cad.report.identify import write

        res["files"] = write(res, fit, Path(out))
    return res


def bench_log(design, out_csv: str | Path, seed: int = 0, perturb=(),
              build_dir: str | Path | None = None, model: str | None = None) -> dict:
    """The virtual bench (``hapticad bench-log``): simulate the built device running the
    firmware's identification routine with the perturbations ``perturb`` (``KEY=VALUE``
    strings, :func:`cad.sim.bench.parse_perturb`); ``model``: a four-bar's ``mujoco`` (its
    exported MJCF, the default) or ``reduced`` (the 1-DOF crank model, :mod:`cad.sim.bench`),
    a 5-bar's ``mujoco`` (its MJCF, the default) or ``reduced`` (its joint-space dynamics,
    :mod:`cad.sim.bench_fivebar`); None: the layout's default. Writes the log to ``out_csv`` and the true parameters to
    ``<out_csv stem>.true.json`` beside it. Returns the true parameters and the paths.
    Raises DesignError naming ``--perturb``, ``--seed``, ``--model`` or ``mechanism.family``."""
    import json

    from cad.data.families import require
    from cad.identify.logfile import format_log, header_line
    from cad.io.atomic import write_text_atomic
    from cad.sim import bench

    _need_design(design)
    require("bench-log", design.family)
    kit = _ident_kit(design)
    model = kit.models[0] if model is None else model
    _choice("--model", model, kit.models)
    p = bench.parse_perturb(perturb)
    if not isinstance(seed, int) or isinstance(seed, bool) or not 0 <= seed < 2**32:
        from cad.errors import DesignError

        raise DesignError("--seed", f"must be an integer in [0, 2^32), got {seed!r}")
    pred, t, counts, cmd, tr, extra = kit.bench(design, p, seed, build_dir, model)
    out_csv = Path(out_csv)
    side = out_csv.with_name(out_csv.stem + ".true.json")
    head = header_line(design.name, pred.design_hash, f"virtual bench ({model} model, seed {seed})", pred.Te_s)
    write_text_atomic(out_csv, format_log(head, t, counts, cmd))
    tr = {**tr, "design": design.name, "design_hash": pred.design_hash, "seed": seed, "rows": len(t), **extra}
    write_text_atomic(side, json.dumps(tr, indent=1))
    return {**tr, "log": str(out_csv), "truth": str(side)}
