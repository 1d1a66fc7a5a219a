"""Mass properties of a STEP or STL file, as ``hapticad massprops --json`` prints them and
:func:`cad.api.mass_properties` returns them (no printing; warnings through
:func:`cad.design.bounds.warn`).

STEP: exact OCCT B-rep integration of every closed solid (read in a forked child, so a crash of
the STEP reader on a hostile file is one error naming the file), per-solid materials where
hapticad's ``report.json`` beside the file names them. STL: trimesh, every closed shell on its
own (:mod:`cad.massprops.shells`), a warning when the mesh is not watertight or implausibly
small or large for mm (:func:`cad.massprops.mesh.unit_slip_note`). Lengths in the file are
millimetres; the dict's keys name their units and the file frame.
"""

from __future__ import annotations

from pathlib import Path

from cad.data.materials import DEFAULT_MATERIAL, get_material
from cad.errors import DesignError, GeometryError


def _resolve_density(density: str | None, material: str | None) -> tuple[float, str | None, bool]:
    """``(density_kg_m3, material name or None, defaulted)`` from the two exclusive flags."""
    if density is not None and material is not None:
        raise DesignError("--density/--material", "give one of them, not both")
    if density is not None:
        from cad.design.bounds import parse_flag

        return parse_flag("--density", density), None, False
    if material is not None:
        mat = get_material(material, "--material")
        return mat.density_kg_m3, mat.name, False
    mat = get_material(DEFAULT_MATERIAL)
    return mat.density_kg_m3, mat.name, True


def compute(
    file: Path, density: str | None = None, material: str | None = None
) -> tuple[dict, list[str]]:
    """Mass properties of ``file`` as the command's JSON dict, plus stderr notes (no printing)."""
    from cad.massprops import io as mpio

    notes: list[str] = []
    kind = mpio.file_kind(file)
    rho, mat_name, defaulted = _resolve_density(density, material)
    if defaulted:
        notes.append(f"note: no --density or --material given; using {mat_name} ({rho:g} kg/m^3)")
    out: dict = {"file": str(file), "format": kind}
    if kind == "step":
        props, vol, info = _step_props_isolated(Path(file), rho, mat_name, defaulted)
        out.update(method="occt-exact", watertight=None, **info)
        if out.get("material") == "per-solid":
            notes = [f"note: materials per solid from {info['material_source']}"]
    else:
        from cad.design.bounds import warn
        from cad.massprops import mesh

        stl_warnings: list[str] = []
        v, f = mpio.read_stl(file, stl_warnings)
        for w in stl_warnings:
            warn(w)
        res = _mesh_props(mesh, v, f, rho, Path(file).name)
        for note in res.notes:
            warn(note)
        if not res.watertight:
            warn(f"{Path(file).name} is not watertight (open or non-manifold edges); "
                 "volume and inertia are unreliable")
        scale = mesh.unit_slip_note(v, res.props.mass_kg, Path(file).name)
        if scale:
            warn(scale)
        props, vol = res.props, res.volume_mm3
        out.update(method="trimesh", watertight=res.watertight, n_triangles=res.n_triangles)
    out.setdefault("density_kg_m3", rho)
    out.setdefault("material", mat_name)
    out.update(
        volume_mm3=vol,
        **props.to_dict(),
        principal_axes=props.principal_axes.tolist(),
    )
    return out, notes


def file_materials(path: Path, names: list[str]) -> tuple[dict[str, str] | None, str]:
    """Material of every named solid, where the file names them: ``({name: material}, source)``.

    hapticad's ``assembly.step`` names every solid after its part instance and the build's
    ``report.json`` beside it maps those names to materials (``part_materials``). ``None``
    when a solid is unnamed or not in such a map.
    """
    from cad.errors import FileRefused
    from cad.io import guard

    rep = path.parent / "report.json"
    if not rep.is_file() or not names:
        return None, ""
    try:  # a side file: anything unreadable (a FIFO, damaged, too large) is no materials map
        mats = guard.load_json(rep, "report", "FILE").get("part_materials")
    except (FileRefused, AttributeError):
        return None, ""
    if not isinstance(mats, dict) or not all(n in mats for n in names):
        return None, ""
    return {n: mats[n] for n in names}, f"{rep.name} beside {path.name}"


def _step_props_isolated(path: Path, rho: float, mat_name: str | None, defaulted: bool):
    """:func:`_step_props` after :func:`cad.io.guard.check_step` (size, parenthesis nesting),
    run in a forked child (:mod:`cad.pipeline.forked`) so that a crash of OCCT's STEP reader on
    a hostile file is one error line naming the file, not a segmentation fault of the command.
    The child's warnings are recorded again here."""
    from cad.design import bounds
    from cad.io import guard
    from cad.pipeline import forked

    guard.check_step(path, "FILE")

    def child():
        import faulthandler

        faulthandler.disable()  # a crash is reported by the parent in one line, not dumped
        before = len(bounds.collected())
        return _step_props(path, rho, mat_name, defaulted), bounds.collected()[before:]

    try:
        result, warnings = forked.Forked(child, f"massprops {path.name}").result()
    except forked.StageDied as exc:
        from cad.errors import FileRefused

        how = f"crash (signal {exc.signal})" if exc.signal else "stop without a result"
        raise FileRefused("FILE", path, f"made OCCT's STEP reader {how} (read in a child "
                          "process): the file is damaged or hostile") from None
    for text in warnings:
        bounds.warn(text)
    return result


def _step_props(path: Path, rho: float, mat_name: str | None, defaulted: bool):
    """Exact mass properties of the closed solids of a STEP file, per-solid materials where
    the file names them (:func:`file_materials`); loose faces and shells ignored and warned."""
    from cad.design.bounds import warn
    from cad.massprops import io as mpio
    from cad.massprops import occt
    from cad.massprops.props import combine

    name = path.name
    named: list[tuple[str | None, object]] = []
    ignored: dict[str, int] = {}
    for leaf_name, leaf in occt.read_step_named(path):
        solids, ign = occt.split_solids(leaf)
        named += [(leaf_name, s) for s in solids]
        for k, n in ign.items():
            ignored[k] = ignored.get(k, 0) + n
    if ignored:  # surfaces bound no volume: never integrated, always said
        warn(f"{name}: ignored {mpio.ignored_text(ignored)} (only closed solids are integrated)")
    if not named:
        raise GeometryError(f"{name}: STEP file holds no closed solid (only surfaces or curves?)")
    for n, s in named:
        occt.check_valid(s, f"{name}: solid {n!r}" if n else name)
    integrals = [occt.volume_props_mm(s) for _, s in named]
    info: dict = {"n_solids": len(named), "ignored": ignored}
    names = [n for n, _ in named]
    materials, source = (file_materials(path, sorted(set(names)))
                         if all(n is not None for n in names) else (None, ""))
    if materials is not None and defaulted:
        from cad.data.materials import get_material

        parts = [occt.to_si(*i, get_material(materials[n]).density_kg_m3)
                 for n, i in zip(names, integrals, strict=True)]
        props = combine(parts)
        vol = sum(i[0] for i in integrals)
        info.update(solid_materials=materials, material_source=source, material="per-solid",
                    density_kg_m3=props.mass_kg / (vol * occt.MM3_TO_M3))
        return props, vol, info
    if materials is not None:
        flag = "--density" if mat_name is None else "--material"
        warn(f"{name}: {source} names a material for each of the {len(named)} solids; the "
             f"given {flag} overrides them all")
    elif len(named) > 1:
        warn(f"{name}: one density ({rho:g} kg/m^3) applied to all {len(named)} solids: the "
             "file names no materials per solid (the mass is right only if every part is of "
             "this material)")
    v, com, inertia = occt.sum_volume_props(integrals)
    return occt.to_si(v, com, inertia, rho), v, info


def _mesh_props(mesh, v, f, rho: float, name: str):
    """:func:`cad.massprops.mesh.mesh_arrays_mass_props` of an STL, open meshes accepted with a
    warning; when an open mesh gives no physical inertia the refusal says it is open and how
    many edges bound only one triangle (the cause a user can act on), naming the file."""
    from cad.errors import HapticadError

    try:
        return mesh.mesh_arrays_mass_props(v, f, rho, allow_open=True, what=name)
    except HapticadError as exc:
        import numpy as np

        _, same = np.unique(np.asarray(v, dtype=float), axis=0, return_inverse=True)  # STL: a soup
        e = np.sort(same.reshape(-1)[np.asarray(f, dtype=np.int64)][:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
        _, counts = np.unique(e, axis=0, return_counts=True)
        n_open = int((counts == 1).sum())
        if n_open:
            raise type(exc)(f"{name}: the mesh is not closed ({n_open} open edges): it encloses no "
                            f"volume, so it has no mass properties ({exc})") from None
        raise

