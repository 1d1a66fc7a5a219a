"""One flat voice-coil actuator as solids (isotropy paper Fig. 7): magnets, iron, spacers, coil, frame.

Parameters in, build123d solids out (build123d imported inside the functions).
Actuator frame as in :mod:`cad.actuators.voicecoil`: z gap normal (gap centre
at z = 0), x force, y along the magnets' length; mm.

Parts (name -> material key):
* ``magnet_{top,bottom}_{A,B}`` (magnet material): w_m x l_m x t_m; pair A at
  x = +w/2, B at x = -w/2, faces at z = +-d/2.
* ``iron_{top,bottom}``: back-iron plates t_s thick on the magnets' backs,
  covering both magnets with ``plate_margin_mm`` and reaching the spacers.
* ``spacer_{+y,-y}`` (non-magnetic, else they would short the flux): hold
  the plates d + 2 t_m apart beyond the coil's end turns.
* ``coil``: racetrack (stadium) 2 w_m x (l_m + 2 w_m), d_c = d - d_r thick,
  centred in the gap; ``coil_carrier``: plate around the coil leaving the
  gap along +x (where it attaches to the moving body).
* ``base``: mounting plate under the bottom iron plate, four M3 clearance holes.

Rattle space: the coil clears each magnet face by d_r/2 and the spacers by
at least d_r/2 in y; :func:`rattle_clearances_mm` measures both on the solids.
"""

from __future__ import annotations

from dataclasses import dataclass

from cad.errors import DesignError


@dataclass(frozen=True)
class ActuatorGeometry:
    """Dimensions of one actuator (mm).

    magnet_length_mm, magnet_width_mm, magnet_thickness_mm: l_m, w_m, t_m;
    gap_mm: d; rattle_mm: d_r; plate_thickness_mm: t_s; plate_margin_mm: iron
    overhang beyond the magnets in x; carrier_length_mm: carrier reach past
    the magnets along +x; base_thickness_mm; spacer_thickness_mm (along y).
    """

    magnet_length_mm: float
    magnet_width_mm: float
    magnet_thickness_mm: float
    gap_mm: float
    rattle_mm: float
    plate_thickness_mm: float
    plate_margin_mm: float = 2.0
    carrier_length_mm: float = 25.0
    base_thickness_mm: float = 5.0
    spacer_thickness_mm: float = 5.0

    def __post_init__(self) -> None:
        for k in (
            "magnet_length_mm",
            "magnet_width_mm",
            "magnet_thickness_mm",
            "gap_mm",
            "plate_thickness_mm",
        ):
            if not getattr(self, k) > 0:
                raise DesignError(k, f"must be > 0, got {getattr(self, k)!r}")
        if not self.gap_mm > self.rattle_mm >= 0:
            raise DesignError(
                "gap_mm",
                f"must exceed rattle_mm {self.rattle_mm} (coil thickness d - d_r > 0), got {self.gap_mm}",
            )

    @property
    def coil_width_mm(self) -> float:
        """d_c = d - d_r."""
        return self.gap_mm - self.rattle_mm

    @property
    def coil_half_extent_y_mm(self) -> float:
        """Coil reach along y: l_m/2 + w_m (end turns of outer radius w_m)."""
        return self.magnet_length_mm / 2 + self.magnet_width_mm

    @property
    def carrier_half_y_mm(self) -> float:
        return self.coil_half_extent_y_mm + 2.0

    @property
    def spacer_inner_y_mm(self) -> float:
        """Spacer inner face: the carrier's edge plus d_r/2 travel plus 0.5 mm."""
        return self.carrier_half_y_mm + self.rattle_mm / 2 + 0.5

    @property
    def plate_half_x_mm(self) -> float:
        return self.magnet_width_mm + self.plate_margin_mm

    @property
    def plate_half_y_mm(self) -> float:
        return self.spacer_inner_y_mm + self.spacer_thickness_mm

    @property
    def plate_z_mm(self) -> float:
        """Plate centre height |z|."""
        return self.gap_mm / 2 + self.magnet_thickness_mm + self.plate_thickness_mm / 2

    @property
    def height_mm(self) -> float:
        """2 t_s + 2 t_m + d (the paper's d_max constraint)."""
        return 2 * self.plate_thickness_mm + 2 * self.magnet_thickness_mm + self.gap_mm


def stadium(length_mm: float, width_mm: float, thickness_mm: float):
    """Racetrack solid: straight length ``length_mm`` along y between semicircle centres,
    total width ``width_mm`` along x, thickness along z, centred at the origin."""
    import build123d as bd

    sk = bd.SlotCenterToCenter(length_mm, width_mm, rotation=90)
    return bd.extrude(sk, amount=thickness_mm / 2, both=True)


def actuator_solids(g: ActuatorGeometry) -> dict[str, tuple[object, str]]:
    """All solids of one actuator in the actuator frame: name -> (build123d Solid, role).

    role is one of "magnet", "iron", "spacer", "coil", "carrier", "base";
    the caller maps roles to materials.
    """
    import build123d as bd

    w, lm, t, d = g.magnet_width_mm, g.magnet_length_mm, g.magnet_thickness_mm, g.gap_mm
    out: dict[str, tuple[object, str]] = {}
    for side, zs in (("top", 1.0), ("bottom", -1.0)):
        for pair, xs in (("A", 1.0), ("B", -1.0)):
            out[f"magnet_{side}_{pair}"] = (
                bd.Pos(xs * w / 2, 0, zs * (d / 2 + t / 2)) * bd.Box(w, lm, t),
                "magnet",
            )
        out[f"iron_{side}"] = (
            bd.Pos(0, 0, zs * g.plate_z_mm)
            * bd.Box(2 * g.plate_half_x_mm, 2 * g.plate_half_y_mm, g.plate_thickness_mm),
            "iron",
        )
    span = d + 2 * t
    for name, ys in (("spacer_+y", 1.0), ("spacer_-y", -1.0)):
        yc = ys * (g.spacer_inner_y_mm + g.spacer_thickness_mm / 2)
        out[name] = (
            bd.Pos(0, yc, 0) * bd.Box(2 * g.plate_half_x_mm, g.spacer_thickness_mm, span),
            "spacer",
        )
    dc = g.coil_width_mm
    coil = stadium(lm, 2 * w, dc)
    out["coil"] = (coil, "coil")
    x0, x1 = -(w + 2.0), w + g.carrier_length_mm
    carrier = bd.Pos((x0 + x1) / 2, 0, 0) * bd.Box(x1 - x0, 2 * g.carrier_half_y_mm, dc)
    out["coil_carrier"] = (carrier - stadium(lm, 2 * w, dc + 2.0), "carrier")
    bx, by = 2 * g.plate_half_x_mm + 16.0, 2 * g.plate_half_y_mm
    zb = -(g.gap_mm / 2 + t + g.plate_thickness_mm + g.base_thickness_mm / 2)
    base = bd.Pos(0, 0, zb) * bd.Box(bx, by, g.base_thickness_mm)
    for sx in (-1, 1):
        for sy in (-1, 1):
            base = base - bd.Pos(sx * (bx / 2 - 4.0), sy * (by / 2 - 4.0), zb) * bd.Cylinder(
                1.7, g.base_thickness_mm + 2
            )
    out["base"] = (base, "base")
    return out


def rattle_clearances_mm(g: ActuatorGeometry, solids: dict | None = None) -> dict[str, float]:
    """Exact minimum distances (OCCT) from the coil and carrier to the magnets and the spacers (mm).

    Expected: coil-magnets = d_r/2; carrier-spacers = d_r/2 + 0.5.
    """
    s = actuator_solids(g) if solids is None else solids
    coil, carrier = s["coil"][0], s["coil_carrier"][0]
    mags = [v[0] for k, v in s.items() if k.startswith("magnet")]
    spacers = [v[0] for k, v in s.items() if k.startswith("spacer")]
    return {
        "coil_to_magnets_mm": min(coil.distance_to(m) for m in mags),
        "carrier_to_magnets_mm": min(carrier.distance_to(m) for m in mags),
        "carrier_to_spacers_mm": min(carrier.distance_to(sp) for sp in spacers),
    }
