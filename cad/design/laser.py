"""Checks of ``parts.process = "laser"`` at design load (no CAD import): which parts are cut
from sheet, the sheet material and its stock thickness, and the features a sheet cannot make.

Plate parts of the four-bar (``PartKind.plate``): the three bars (``bar_style = "plate"``), the
base plate and the motor mount plate. Each is laser-cut from sheet of its material
(:data:`cad.data.materials.SHEETS`); everything else made (hub, post, spacers, legs, handle)
stays turned, as the BOM process column says (one warning lists them).

Refused (``DesignError`` naming the material key, the part and the feature): a plate part in a
material not sold as sheet here; a thickness that is not a stock thickness (the nearest
named); a tapped thread in a sheet that holds none (acrylic, plywood: the coupler's handle
hole, the base plate's motor-mount screw holes). Changed with a warning naming the part and
feature: a reamed or bored H7 bore in such a sheet is laser-cut at nominal (kerf-compensated,
no H7); a bearing seat (a blind step a laser cannot cut) is milled after cutting.
"""

from __future__ import annotations

from typing import Any

from cad.data import catalog
from cad.data.materials import SHEETS
from cad.design import bounds
from cad.errors import DesignError
from cad.printing import is_printed


def plate_groups(v: dict[str, Any]) -> list[tuple[str, str, str, tuple[str, ...]]]:
    """``[(material key, thickness key, parts text, feature keys)]`` of the plate parts of
    resolved ``[parts]`` values ``v``; features: "tap", "ream", "seat"."""
    out = []
    if v["bar_style"] == "plate":
        out.append(("bar_material", "bar_thickness_mm", "crank, coupler, rocker",
                    ("seat", "ream", "tap")))
    out.append(("base_material", "base_thickness_mm", "base plate", ("tap",)))
    out.append(("motor_mount_material", "motor_mount_thickness_mm", "motor mount", ("bore",)))
    return out


def _feature(v: dict[str, Any], names: str, feat: str) -> str:
    """The one feature ``feat`` of plate parts ``names`` as the shop calls it."""
    if feat == "tap":
        if names == "base plate":  # (their size is cad.parts.motor.MOUNT_SCREW: design imports no part)
            return "tapped motor-mount screw holes x4"
        return f"coupler's tapped {v['handle_screw'].split('-')[0]} handle hole"
    if feat == "ream":
        pin = catalog.get_shoulder_screw(v["pin"])
        return f"reamed {pin.ds_mm:g} H7 pin bores"
    if feat == "bore":
        return f"bored {catalog.get_motor(v['motor']).pilot_diameter_mm:g} H7 pilot seat"
    return f"{catalog.get_bearing(v['bearing']).D_mm:g} J7 bearing seats"


def check_laser(v: dict[str, Any], prefix: str) -> None:
    """Refuse or warn (module docstring) for resolved ``[parts]`` values ``v`` under
    ``process = "laser"``; ``prefix`` the table's dotted path ("parts")."""
    def f(key: str) -> str:
        return f"{prefix}.{key}" if prefix else key

    for mkey, tkey, names, feats in plate_groups(v):
        mat, t = v[mkey], v[tkey]
        sheet = SHEETS.get(mat)
        if sheet is None:
            raise DesignError(f(mkey), f"process \"laser\" cuts the {names} from sheet; {mat!r} is "
                                       f"not a sheet material here (sheets: {', '.join(SHEETS)})")
        if not any(abs(t - s) < 1e-9 for s in sheet.thicknesses_mm):
            stock = sheet.thicknesses_mm  # nearest: the stock just under and just over t
            near = " or ".join(f"{x:g}" for x in ([max(x for x in stock if x < t)] if t > stock[0] else [])
                               + ([min(x for x in stock if x > t)] if t < stock[-1] else []))
            shown = f"{t:g}" if float(f"{t:g}") == t else repr(t)  # 6.00000001 is not "6"
            raise DesignError(f(tkey), f"{shown} mm is not a stock thickness of {mat} sheet for the "
                                       f"{names} (nearest: {near} mm; stock: "
                                       f"{', '.join(f'{x:g}' for x in sheet.thicknesses_mm)} mm)")
        if "tap" in feats and not sheet.tappable:
            raise DesignError(f(mkey), f"process \"laser\": {names} in {mat}: the "
                                       f"{_feature(v, names, 'tap')} cannot be made ({mat} holds no "
                                       f"thread); cut it from aluminium sheet or use process "
                                       f"\"machined\"")
        for feat in feats:
            said = f"{f('process')} = \"laser\": {names} ({mat}): the"
            if feat in ("ream", "bore") and not sheet.reamable:
                verb = "is" if feat == "bore" else "are"
                bounds.warn(f"{said} {_feature(v, names, feat)} {verb} laser-cut at nominal "
                            f"(kerf-compensated), not H7: {mat} holds no reamed fit (aluminium "
                            f"sheet in {f(mkey)} does)")
            if feat == "seat" and not sheet.reamable:
                bounds.warn(f"{said} {_feature(v, names, 'seat')} are milled after cutting (a "
                            f"laser cuts no blind step); J7 is not held in {mat}: bond the bearings "
                            f"(aluminium sheet in {f(mkey)} holds J7)")
    keys = {"hub": "hub_material", "post": "post_material", "spacers": "spacer_material",
            "handle": "handle_material"}  # (a PLA or PETG one is printed: its own warning)
    turned = [n for n in ("hub", "post", "spacers", "legs", "handle")
              if n not in keys or not is_printed("laser", v[keys[n]])]
    bounds.warn(f"{f('process')} = \"laser\": {', '.join(turned)} are not plate parts: they stay "
                f"turned (machined), as the BOM process column says")
