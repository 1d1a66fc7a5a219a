"""Printed made parts (``parts.process``, :mod:`cad.printing`): the kinds of an assembly
turned into printed ones -- mass from the wall/infill model, print orientation, BOM text.

The solid's inertia about its COM is scaled with its mass (a uniform effective density):
the printed shell sits outside the lighter core, so the true inertia per mass is a little
higher than this (stated, not corrected).
"""

from __future__ import annotations

from dataclasses import replace

from cad.data.materials import get_material
from cad.parts.printed import print_flip, printed_mass_kg
from cad.printing import printed_fit, printed_process


def printed_kind(kind, parts):
    """``kind`` as printed: ``mass_kg`` (wall/infill model), ``print_flip``, ``process``, and
    its fits as a print holds them (:func:`cad.printing.printed_fit`: no ISO 286 class)."""
    s = parts.print_settings()
    flip = print_flip(kind.shape, s)
    return replace(
        kind,
        mass_kg=printed_mass_kg(kind.shape, get_material(kind.material).density_kg_m3, s),
        print_flip=flip,
        process=printed_process(kind.process, kind.material, s, flip),
        fits=tuple(printed_fit(f) for f in kind.fits),
    )


def as_printed(asm, parts):
    """The assembly with every made kind in a printed material (``parts.printed``) printed;
    the assembly itself when none is."""
    new = {}
    for inst in asm.instances:
        k = inst.kind
        if k.made and k.listed and k.name not in new and parts.printed(k.material):
            new[k.name] = printed_kind(k, parts)
    if not new:
        return asm
    inst = tuple(replace(i, kind=new.get(i.kind.name, i.kind)) for i in asm.instances)
    return replace(asm, instances=inst)
