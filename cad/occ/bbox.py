"""Tight bounding boxes of OCP shapes (OCCT ``BRepBndLib::AddOptimal``, mm)."""

from __future__ import annotations

import numpy as np


def tight_box(shape) -> np.ndarray:
    """(2, 3) tight axis-aligned bounding box ``[min corner, max corner]`` of ``shape`` (an
    OCP ``TopoDS_Shape``, mm, in the frame its location places it in).

    OCCT ``BRepBndLib.AddOptimal_s`` on the exact geometry (no triangulation, no shape
    tolerance added); the box's gap is included, as ``Bnd_Box.Get`` returns it.
    """
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    b = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, b, False, False)
    return np.array(b.Get()).reshape(2, 3)


def loose_box(shape) -> np.ndarray:
    """(2, 3) fast bounding box ``[min corner, max corner]`` of ``shape`` (mm, as
    :func:`tight_box`): OCCT ``BRepBndLib::Add`` on the geometry (no triangulation), enlarged
    by the shape's tolerances; it holds the solid (it is no smaller than :func:`tight_box`),
    for pruning before the tight one."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    b = Bnd_Box()
    BRepBndLib.Add_s(shape, b, False)
    return np.array(b.Get()).reshape(2, 3)
