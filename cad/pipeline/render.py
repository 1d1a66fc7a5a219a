"""``hapticad render``: pictures of devices from their builds (module doc of
:mod:`cad.cli.cmd_render`); what :func:`cad.api.render` calls."""

from __future__ import annotations

import tempfile
from pathlib import Path

RENDER_FILES = {"render.png": ".png", "animation.gif": ".gif"}


def render_designs(paths: list, out: Path, fidelity: str | None = None) -> list[dict]:
    """Build each design (a path or a loaded design) and copy its pictures to ``out``;
    returns one dict per design (``design``, ``name``, ``png``, ``gif``: paths)."""
    from cad.design import load_design
    from cad.errors import DesignError
    from cad.io.atomic import atomic_dir_update, write_bytes_atomic
    from cad.io.outdir import MANIFEST_NAME, check_shared_files, record_shared_files
    from cad.pipeline import FIDELITIES, build_design, family_of

    designs = []
    for p in paths:
        d = p if hasattr(p, "family") else load_design(p)
        p = Path(d.source) if hasattr(p, "family") else p
        fid = fidelity or getattr(getattr(d, "parts", None), "fidelity", "fabrication")
        if fid not in FIDELITIES:
            raise DesignError("--fidelity", f"must be one of {', '.join(FIDELITIES)}, got {fid!r}")
        try:
            fam = family_of(d)
        except DesignError:
            fam = None
        if fam is None or not fam.view_formats:
            raise DesignError(str(p), f"rendering {d.family!r} designs is not available")
        if getattr(getattr(d, "parts", None), "handle_script", None) is not None:
            from cad.parts.handle import resolve_script

            resolve_script(d.parts, d.source)  # a script not allowed: refused before any build
        if fam.check_options is not None:  # what the build would refuse, before any build
            try:
                fam.check_options(d, fid, None)
            except DesignError as exc:
                raise DesignError(str(p), str(exc)) from None
        same = next((q for q, e, _ in designs if e.name == d.name), None)
        if same is not None:  # both would write <name>.png: the second over the first
            raise DesignError(str(p), f"name: {d.name!r} is also the name of {same}; both would "
                              f"write {d.name}.png and {d.name}.gif; rename one")
        designs.append((p, d, fid))
    names = [f"{d.name}{ext}" for _, d, _ in designs for ext in RENDER_FILES.values()]
    out = Path(out)
    check_shared_files(out, names)
    done = []
    with tempfile.TemporaryDirectory(prefix="hapticad-render-") as tmp:
        for _, d, fid in designs:  # every build first: a failing one writes nothing at all
            build_design(d, Path(tmp) / d.name, set(), fidelity=fid, use_cache=False, simulate_wall=False)
        check_shared_files(out, names)  # again: the builds took a while

        def still_ours(target: Path) -> None:  # and once more as the folder is published
            check_shared_files(target, names)

        # the folder is published whole (pictures and manifest at once, the other files kept):
        # an interrupt or a failure leaves it as it was (cad.io.atomic.atomic_dir_update)
        with atomic_dir_update(out, still_ours) as new:
            if (out / MANIFEST_NAME).is_file():  # its entries of other pictures are kept
                write_bytes_atomic(new / MANIFEST_NAME, (out / MANIFEST_NAME).read_bytes())
            for p, d, _ in designs:
                row = {"design": str(p), "name": d.name}
                for src, ext in RENDER_FILES.items():
                    write_bytes_atomic(new / f"{d.name}{ext}", (Path(tmp) / d.name / src).read_bytes())
                    row[ext[1:]] = str(out / f"{d.name}{ext}")
                done.append(row)
            record_shared_files(new, names)
    return done
