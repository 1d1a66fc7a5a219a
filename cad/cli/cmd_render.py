"""``hapticad render DESIGN... [--out DIR] [--fidelity F] [--json]``: pictures of devices.

Builds each design into a temporary folder (nothing under ``exports/`` is touched) and
copies the build's ``render.png`` (shaded still of the assembly) and ``animation.gif``
(the mechanism over its stroke) to ``DIR/<name>.png`` and ``DIR/<name>.gif``
(default ``docs/devices``). Every design is loaded and checked before anything is built:
a design whose family has no render yet is refused with exit 2, nothing written; every
design is built before any picture is written, so a build that fails writes none. ``DIR``
is shared with other files: an existing ``<name>.png`` / ``.gif`` is replaced only when
``DIR/manifest.json`` says hapticad wrote it unchanged (:mod:`cad.io.outdir`), else exit 2.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import typer

RENDER_FILES = {"render.png": ".png", "animation.gif": ".gif"}


def render_designs(paths: list[Path], out: Path, fidelity: str | None = None) -> list[dict]:
    """Build each design and copy its pictures to ``out``; returns one dict per design."""
    import importlib

    from cad.cli import flags
    from cad.design import load_design
    from cad.errors import DesignError
    from cad.io.atomic import write_bytes_atomic
    from cad.io.outdir import check_shared_files, record_shared_files
    from cad.pipeline import FIDELITIES, build_design, builder_module_name

    designs = []
    for p in paths:
        d = load_design(p)
        fid = fidelity or getattr(getattr(d, "parts", None), "fidelity", "fabrication")
        if fid not in FIDELITIES:
            raise DesignError("--fidelity", f"must be one of {', '.join(FIDELITIES)}, got {fid!r}")
        try:
            mod = importlib.import_module(builder_module_name(d))
        except ModuleNotFoundError:
            mod = None
        if not getattr(mod, "VIEW_EXPORT", False):
            raise DesignError(str(p), f"rendering {d.family!r} designs is not available")
        flags.design_script(d)  # a script not allowed: refused before any build
        if hasattr(mod, "check_options"):  # what the build would refuse, before any build
            try:
                mod.check_options(d, fid, None)
            except DesignError as exc:
                raise DesignError(str(p), str(exc)) from None
        same = next((q for q, e, _ in designs if e.name == d.name), None)
        if same is not None:  # both would write <name>.png: the second over the first
            raise DesignError(str(p), f"name: {d.name!r} is also the name of {same}; both would "
                              f"write {d.name}.png and {d.name}.gif; rename one")
        designs.append((p, d, fid))
    names = [f"{d.name}{ext}" for _, d, _ in designs for ext in RENDER_FILES.values()]
    check_shared_files(Path(out), names)
    done = []
    with tempfile.TemporaryDirectory(prefix="hapticad-render-") as tmp:
        for _, d, fid in designs:  # every build first: a failing one writes nothing at all
            build_design(d, Path(tmp) / d.name, set(), fidelity=fid, use_cache=False, simulate_wall=False)
        check_shared_files(Path(out), names)  # again: the builds took a while
        for p, d, _ in designs:
            row = {"design": str(p), "name": d.name}
            for src, ext in RENDER_FILES.items():
                dst = Path(out) / f"{d.name}{ext}"
                write_bytes_atomic(dst, (Path(tmp) / d.name / src).read_bytes())
                row[ext[1:]] = str(dst)
            done.append(row)
        record_shared_files(Path(out), names)
    return done


def register(app: typer.Typer) -> None:
    @app.command("render")
    def render_cmd(
        designs: list[Path] = typer.Argument(..., help="TOML design files."),
        out: Path = typer.Option(Path("docs/devices"), "--out", help="Folder of the pictures."),
        fidelity: str = typer.Option(
            None, "--fidelity", help="fabrication | inertia | preview (default: the design's)."
        ),
        json_out: bool = typer.Option(False, "--json", help="Print the written files as JSON."),
    ) -> None:
        """Shaded picture and stroke GIF of each design, from its build."""
        from cad.cli import flags
        from cad.cli.app import print_json
        from cad.pipeline import FIDELITIES

        flags.choice("--fidelity", fidelity, FIDELITIES)
        flags.out_path("--out", out, folder=True)
        rows = render_designs(designs, out, fidelity)
        if json_out:
            print_json({"rendered": rows}, sort_keys=True)
            return
        for r in rows:
            print(f"{r['design']}: wrote {r['png']}, {r['gif']}")
