"""Laser-cut made parts (``parts.process = "laser"``, :mod:`cad.design.laser`): the plate
kinds of an assembly turned into laser-cut ones -- BOM process text, fits a sheet cannot hold,
the sheet they are nested on (:attr:`cad.parts.PartKind.sheet_mm`).

The solid is not changed: the DXF is drawn at the finished size and the shop's CAM offsets
the beam by half the kerf (:attr:`cad.data.materials.SheetStock.kerf_mm`); the mass is the
solid's volume x the sheet material's density, as for a machined plate.
"""

from __future__ import annotations

from dataclasses import replace

from cad.data.materials import SHEETS

#: A fit of a bore that a sheet which holds no reamed fit gets instead of its H7.
LASER_FIT = "laser-cut at nominal, kerf-compensated (not H7)"


def laser_process(process: str, material: str, thickness_mm: float) -> str:
    """The BOM process text of a laser-cut plate: the cut, then each later operation of its
    machined ``process`` text ("waterjet/laser ... plate; mill ...; ream ...; tap ...") as
    done on that sheet (reaming and boring dropped where the sheet holds no H7)."""
    sheet = SHEETS[material]
    ops = [o.strip() for o in process.split(";") if o.strip()]
    out = [f"laser cut {thickness_mm:g} mm {material} sheet (kerf {sheet.kerf_mm:g} mm, "
           f"nested: sheets/)"]
    for op in ops:
        if op.startswith(("waterjet", "laser")):
            continue
        if not sheet.reamable and op.startswith("ream "):
            out.append(op.replace("ream ", "", 1) + " " + LASER_FIT)
        elif not sheet.reamable and op.startswith("bore "):
            out.append(op.replace("bore the ", "", 1) + " " + LASER_FIT)
        else:
            out.append(op)
    return "; ".join(out)


def laser_kind(kind, parts):
    """``kind`` (a made plate) as laser-cut: process, fits, ``sheet_mm``."""
    sheet = SHEETS[kind.material]
    t = {"base_plate": parts.base_thickness_mm,
         "motor_mount": parts.motor_mount_thickness_mm}.get(kind.name, parts.bar_thickness_mm)
    fits = kind.fits if sheet.reamable else tuple(
        f"{f[:-3]} {LASER_FIT}" if f.endswith(" H7") else f for f in kind.fits)
    return replace(kind, process=laser_process(kind.process, kind.material, t), fits=fits,
                   sheet_mm=parts.laser_sheet_mm or (0.0, 0.0))


def as_laser(asm, parts):
    """The assembly with every made plate kind laser-cut under ``parts.process = "laser"``;
    the assembly itself otherwise."""
    if parts.process != "laser":
        return asm
    new = {}
    for inst in asm.instances:
        k = inst.kind
        if k.made and k.listed and k.plate and k.name not in new:
            new[k.name] = laser_kind(k, parts)
    inst = tuple(replace(i, kind=new.get(i.kind.name, i.kind)) for i in asm.instances)
    return replace(asm, instances=inst)
