"""Exact distance and common volume of two solids (OCCT), for the interference check."""

from __future__ import annotations

import math

from cad.occ.boolean import common


def min_distance_mm(sa, sb) -> float:
    """Smallest distance (mm) between two placed OCP shapes (``BRepExtrema_DistShapeShape``);
    0 where they touch or overlap, ``inf`` when OCCT does not converge."""
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape

    ext = BRepExtrema_DistShapeShape(sa, sb)
    return float(ext.Value()) if ext.IsDone() else math.inf


def common_volume_mm3(sa, sb) -> float:
    """Volume of ``sa`` ∩ ``sb`` (OCCT ``BRepAlgoAPI_Common``, then ``BRepGProp`` volume),
    mm^3; 0 for touching solids (a negative round-off is clipped to 0). Neither solid is
    modified (:func:`cad.occ.boolean.common`: the check must leave the parts' shared solids
    as the exports read them)."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps


    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(common(sa, sb), props)
    return max(0.0, float(props.Mass()))
