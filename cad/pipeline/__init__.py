"""``hapticad build``: design -> parts -> exports, dispatched on the design's family.

The family's :class:`cad.families.protocol.FamilyPackage` (:func:`family_of`) gives the
build: ``FAMILY.build(design, out_dir, formats, *, fidelity, allow_interference, progress,
phi1_deg) -> report dict``, one call to the build driver :func:`cad.pipeline.run.run_family`
with the family's :class:`cad.pipeline.run.Stages`. ``out_dir`` is a fresh temporary
directory (the dispatcher publishes it atomically with :func:`cad.io.atomic.atomic_dir` only
when everything succeeded); the driver writes the part files, the assembly STEP, the viewer
files and ``assembly.md`` into it and returns the report dict, with the stage wall times
under ``"_timings_s"`` (returned as ``timings_s``, kept out of ``report.json`` so that the
file is deterministic), the bytes of the assembly's ``.glb`` under ``"_viewer_glb"``
(embedded in ``report.html``) and the family's part of ``report.md`` under ``"_report_md"``.
The dispatcher then writes, once each: ``bom.csv`` and ``order.csv`` (priced,
:func:`write_order`), ``report.md`` (title, datasheet, the family's table, BOM and notes,
order: :func:`write_report_md`), the firmware (the family's ``firmware`` hook),
``report.json`` (with ``device``: the resolved device), ``report.html`` and
``manifest.json``; then it reads the files back against the device
(:func:`cad.device.readback.check_outputs`). ``progress`` (may be None) is called as
``progress(description, done, total)``. Before any CAD import the family's
``check_options`` / ``check_layout`` refuse what it cannot build and the formats it does not
write are refused in one line.

Build cache: the dispatcher hashes the design object, the build options and the source
code (the family's ``code_deps``) into ``build_key``. When ``out_dir/manifest.json`` already
carries that key, every listed file still has its size and sha256 and every file the report
names is listed, nothing is rebuilt and no CAD library is imported (the report is read back,
``"cached": true``); otherwise the folder is built again, whole.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import cad
from cad.data.families import FAMILIES, refusal
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families import family_package
from cad.io.atomic import atomic_dir, write_text_atomic
from cad.io.outdir import check_out_dir

Progress = Callable[[str, int, int], None]
FIDELITIES = ("fabrication", "inertia", "preview")
REPORT_NAME = "report.json"
HTML_NAME = "report.html"
#: Bump when the cache key payload changes shape.
CACHE_SCHEMA = 1


def family_of(design):
    """The :class:`cad.families.protocol.FamilyPackage` that builds ``design``.

    Raises DesignError naming ``mechanism.family`` for an object that is no registered
    family's design, a family whose registry row does not take ``build``, or one with no
    parts yet."""
    family = getattr(design, "family", None)
    if family in FAMILIES and "build" not in FAMILIES[family].commands:
        raise DesignError("mechanism.family", refusal("build", family))
    if family not in FAMILIES or not hasattr(design, "raw"):
        raise DesignError(
            "mechanism.family", f"no builder for designs of type {type(design).__name__}"
        )
    fam = family_package(family)
    if fam.build is None:
        raise DesignError("mechanism.family", f"building {family!r} designs is not available yet")
    return fam


def _jsonable(obj: Any) -> Any:
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: _jsonable(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in sorted(obj.items(), key=lambda kv: str(kv[0]))}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else repr(obj)
    if isinstance(obj, (str, int, bool)) or obj is None:
        return obj
    if hasattr(obj, "tolist"):
        return _jsonable(obj.tolist())
    return repr(obj)


@functools.lru_cache(maxsize=8)
def code_version(deps: tuple[str, ...] | None = None) -> str:
    """sha256 over the source of the ``cad`` package, or of the listed sub-packages/modules
    (``deps``: paths relative to the package, e.g. ``("parts", "data")``)."""
    root = Path(cad.__file__).parent
    files = (
        sorted(root.rglob("*.py"))
        if deps is None
        else sorted(
            {
                p
                for d in deps
                for p in ((root / d).rglob("*.py") if (root / d).is_dir() else [root / d])
            }
        )
    )
    h = hashlib.sha256()
    for p in files:
        if p.is_file():
            h.update(p.relative_to(root).as_posix().encode())
            h.update(p.read_bytes())
    return h.hexdigest()


def _design_payload(design) -> dict:
    return {
        "design": _jsonable(
            {k: v for k, v in _jsonable(design).items() if k not in ("source", "raw")}
        ),
        "raw": _jsonable(getattr(design, "raw", {})),
    }


def design_hash(design) -> str:
    """sha256 of the validated design and its TOML mapping (no path, no options, no code):
    the hash the generated firmware names."""
    text = json.dumps(_design_payload(design), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def build_key(
    design, formats: set[str], fidelity: str, allow_interference: bool, phi1_deg: float | None,
    simulate_wall: bool = True,
    prices: dict | None = None,
) -> str:
    """Hash of everything a build's output depends on (design, options, code, extra inputs,
    the ``--prices`` table)."""
    payload = {
        "schema": CACHE_SCHEMA,
        **_design_payload(design),
        "formats": sorted(formats),
        "fidelity": fidelity,
        "allow_interference": bool(allow_interference),
        "phi1_deg": phi1_deg,
    }
    if simulate_wall != (fidelity == "fabrication"):  # not the default (key unchanged otherwise)
        payload["simulate_wall"] = bool(simulate_wall)
    if prices is not None:
        payload["prices"] = _jsonable(prices)
    fam = family_of(design)
    payload["code"] = code_version(fam.code_deps)
    # the dispatcher adds the datasheet to every family's report (cad/datasheet, its inputs);
    # cad/tolerances.py for every family (K_RTOL of the wall, part clearances, mesh tolerances)
    payload["datasheet_code"] = code_version(("datasheet", "data", "families", "sim/wall.py",
                                              "structure", "design/motor.py", "device",
                                              "tolerances.py"))
    if fam.cache_inputs is not None:
        payload["extra"] = _jsonable(fam.cache_inputs(design))
    text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def cached_report(out_dir: Path, key: str) -> dict | None:
    """The report of an up-to-date build in ``out_dir``, else None (a rebuild).

    Up to date: the manifest carries ``key``, every file it lists has its size and sha256,
    and it lists every file the build made -- ``report.json`` (itself listed, so checked by
    hash) names them all, so a part file deleted together with its manifest row is a miss.
    """
    from cad.export.manifest import verify_manifest

    doc = verify_manifest(out_dir)
    if doc is None or doc.get("build_key") != key:
        return None
    from cad.errors import FileRefused
    from cad.io import guard

    try:  # listed and hashed above; read through the guard all the same (cad/io/guard.py)
        report = guard.load_json(Path(out_dir) / REPORT_NAME, "report", "--out")
        listed = {str(row["path"]) for row in doc["files"]}
        made = report["files"]
    except (FileRefused, KeyError, TypeError):
        return None
    if REPORT_NAME not in listed or not isinstance(made, list) or not set(map(str, made)) <= listed:
        return None
    report["cached"] = True
    return report


def add_datasheet(design, report: dict, out_dir: Path, simulate_wall: bool = True) -> list[str]:
    """``report["datasheet"]`` (:mod:`cad.datasheet`) and the design file's name in
    ``report["source"]`` (every family); returns the datasheet's lines of ``report.md``."""
    from cad.datasheet import datasheet, markdown

    if not report.get("source") and getattr(design, "source", None):
        report["source"] = Path(design.source).name
    ds = datasheet(design, report, out_dir, simulate_wall=simulate_wall)
    report["datasheet"] = ds
    if isinstance(report.get("files"), list):
        report["files"] = sorted({*report["files"], *ds["charts"]})
    return markdown(ds)


def _design_prices(design) -> dict | None:
    from cad.design import design_prices

    return design_prices(getattr(design, "raw", None) or {})


def write_order(report: dict, out_dir: Path, prices: dict | None) -> str:
    """Price the report's BOM (:func:`cad.export.order.apply_prices`), write ``bom.csv`` (its
    one writer) with the prices and ``order.csv``; ``report["order"]``: the total and its
    unpriced lines. Returns the "Order" section of ``report.md`` (and the assembly steps'
    link); a report without a BOM: nothing written, "" returned."""
    from cad.export import write_bom
    from cad.export.order import apply_prices, order_csv, order_md, total_text

    bom = report.get("bom")
    if not bom:
        return ""
    summary = apply_prices(bom, prices)
    write_bom(bom, out_dir)
    write_text_atomic(out_dir / "order.csv", order_csv(bom, summary))
    report["order"] = {**{k: v for k, v in summary.items() if k != "extra_lines"},
                       "total": total_text(summary)}
    steps = "assembly.md" if (out_dir / "assembly.md").is_file() else None
    pictures = sorted(p.relative_to(out_dir).as_posix() for p in out_dir.glob("steps/step_*.png"))
    if isinstance(report.get("files"), list):
        report["files"] = sorted({*report["files"], "bom.csv", "order.csv",
                                  *([steps] if steps else []), *pictures})
    return order_md(bom, summary) + ("\nAssembly steps: [assembly.md](assembly.md).\n" if steps else "")


def write_report_md(out_dir: Path, family_lines: list[str], datasheet_lines: list[str],
                    order_text: str) -> None:
    """``report.md``, written once: the family's title, the datasheet, the family's table,
    BOM and notes (:func:`cad.pipeline.family.report_md_lines`), then the order section."""
    lines = [family_lines[0], "", *datasheet_lines, *family_lines[1:]]
    write_text_atomic(Path(out_dir) / "report.md", "\n".join(lines) + "\n" + order_text)


@contextlib.contextmanager
def _children_cancelled_on_error():
    """No forked stage outlives a failed or interrupted build (it would write into the
    temporary folder being removed)."""
    try:
        yield
    except BaseException:
        from cad.pipeline import forked

        forked.cancel_all()
        raise


def build_design(
    design,
    out_dir: Path,
    formats: set[str],
    *,
    fidelity: str = "fabrication",
    allow_interference: bool = False,
    progress: Progress | None = None,
    phi1_deg: float | None = None,
    use_cache: bool = True,
    simulate_wall: bool | None = None,
    prices: dict | None = None,
) -> dict:
    """Build ``design`` into ``out_dir`` atomically and return the report dict.

    ``simulate_wall``: whether the datasheet simulates the virtual wall for its K_max row (a
    few seconds per new design, then derived-cached); default: at fabrication fidelity only
    (the build a user keeps; ``hapticad datasheet`` asks for it at any fidelity, evaluation
    builds of ``check``/``fit``/``optimize`` never).

    ``prices``: a price table (:func:`cad.export.order.load_prices`, ``--prices``), used
    instead of the design's ``[prices]`` table; the BOM gets unit and line prices and
    ``order.csv`` is written (:func:`write_order`).

    Raises the builder's :class:`cad.errors.HapticadError` subclasses (DesignError,
    GeometryError, MeshError, InterferenceError ...); on any failure ``out_dir`` is
    left exactly as it was. ``out_dir`` is replaced whole, so it must hold only files
    an earlier build wrote (:func:`cad.io.outdir.check_out_dir`, DesignError ``--out``
    otherwise: checked before the build and again just before publishing).
    """
    if fidelity not in FIDELITIES:
        raise DesignError("--fidelity", f"must be one of {', '.join(FIDELITIES)}, got {fidelity!r}")
    from cad.io import cache_faults, cache_limit

    cache_faults.writable()  # the cache-fault flag exists before any stage is forked (shared)
    cache_limit.max_bytes()  # a bad HAPTICAD_CACHE_MAX_MB is refused before anything is made
    out_dir = Path(out_dir)
    check = functools.partial(check_out_dir, design_source=getattr(design, "source", None))
    check(out_dir)
    if simulate_wall is None:
        simulate_wall = fidelity == "fabrication"
    key = build_key(design, formats, fidelity, allow_interference, phi1_deg, simulate_wall, prices)
    if use_cache:
        rep = cached_report(out_dir, key)
        if rep is not None:
            return rep
    fam = family_of(design)
    device = resolve_device(design, fidelity)  # once: every writer reads these facts (cad.device)
    _check_before_cad(fam, design, set(formats), fidelity, phi1_deg, allow_interference)
    from cad.export.manifest import write_manifest  # noqa: F401 - imported before the routed import, as always
    from cad.parts.lazy_import import routed_first_import

    # build123d is imported only if a solid (or a file derived from one) is missing from the
    # shape and derived caches, and then without scikit-learn (cad.parts.lazy_import)
    with (
        routed_first_import(),
        atomic_dir(out_dir, check=check) as tmp,
        _children_cancelled_on_error(),
    ):
        report = dict(fam.build(design, tmp, set(formats), fidelity=fidelity,
                                allow_interference=allow_interference, progress=progress,
                                phi1_deg=phi1_deg))
        family_md = report.pop("_report_md")
        order_text = write_order(report, tmp, prices if prices is not None else _design_prices(design))
        write_report_md(tmp, family_md, add_datasheet(design, report, tmp, simulate_wall), order_text)
        timings = report.pop("_timings_s", None)
        viewer_glb = report.pop("_viewer_glb", None)
        build = {"formats": sorted(formats), "fidelity": fidelity,
                 "allow_interference": bool(allow_interference), "build_key": key}
        _write_report_files(fam, design, report, tmp, formats, build, viewer_glb, device)
    report["cached"] = False
    if timings is not None:
        report["timings_s"] = timings
    cache_limit.prune_after_build()  # least recently used cache entries beyond the cap
    return report


def _check_before_cad(fam, design, formats: set[str], fidelity: str, phi1_deg: float | None,
                      allow_interference: bool) -> None:
    """Refuse, before any CAD import, what the family ``fam`` cannot build: its unsupported
    options, a format it does not write, links shorter than their joint hardware, a stack with
    no clear layer order. Raises DesignError."""
    if fam.check_options is not None:  # unsupported combinations: before any CAD import
        fam.check_options(design, fidelity, phi1_deg, set(formats))
    for fmt, ok in (("mjcf", "mjcf" in fam.sim_formats), ("urdf", "urdf" in fam.sim_formats),
                    ("glb", fam.view_formats), ("3mf", fam.view_formats),
                    ("firmware", fam.firmware is not None)):
        if fmt in formats and not ok:
            raise DesignError("--formats", f"{fmt} is not written for {design.family!r} designs "
                                           f"(docs/commands.md lists the formats of each family)")
    check_buildable = getattr(design, "check_buildable", None)
    if check_buildable is not None:  # links shorter than their joint hardware, before any CAD
        check_buildable()
    if fam.check_layout is not None:  # no clear layer order: refused before the CAD import
        fam.check_layout(design, fidelity, allow_interference)


def _write_report_files(fam, design, report: dict, tmp: Path, formats, build: dict, viewer_glb,
                        device) -> None:
    """Into the build's temporary folder: the firmware (when asked), report.json (with
    ``device``: the resolved device; its keys and types checked against the family's
    ``report_type``, :mod:`cad.report.contract`), report.html and the manifest;
    ``report["files"]`` lists them, ``report["build"]`` is ``build`` (formats, fidelity,
    allow_interference, build_key).
    Then the written files are read back (:func:`cad.device.readback.check_outputs`): a file
    that disagrees with ``device`` raises OutputsDisagree and nothing is published."""
    from cad.device.readback import check_outputs
    from cad.export.manifest import write_manifest
    from cad.report import contract
    from cad.report.html import write_report_html

    if "firmware" in formats:  # from the report's mass properties (the family's hook, no CAD)
        from cad.firmware import write_files

        fw = write_files(tmp, fam.firmware(design, _jsonable(report), design_hash(design), device))
        report["files"] = sorted({*report.get("files", []), *fw})
    if isinstance(report.get("files"), list):
        report["files"] = sorted({*report["files"], HTML_NAME})
    report["build"] = build
    report["device"] = device.as_dict()
    doc = _jsonable(report)
    contract.check(doc, fam.report_type.resolve() if fam.report_type is not None
                   else contract.CommonReport)  # ReportContractError: nothing is published
    write_text_atomic(tmp / REPORT_NAME, json.dumps(doc, indent=2, sort_keys=True) + "\n")
    write_report_html(doc, tmp, viewer_glb)
    write_manifest(tmp, {"build_key": build["build_key"]})
    check_outputs(device, tmp)  # the files read back agree with the device, or nothing is published
