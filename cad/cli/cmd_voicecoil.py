"""``hapticad voicecoil``: optimal gap of a flat voice-coil actuator (isotropy paper eqs 8-9, Fig. 8).

    hapticad voicecoil --magnet-length-mm L --magnet-width-mm W --magnet-thickness-mm T
                       --rattle-mm DR [--power-W P] [--br-T BR] [--rho-ohm-m RHO]
                       [--eta-pack E] [--model closed-form|images|magpylib]
                       [--gap-mm D] [--gap-max-mm DMAX] [--json]

Defaults: P = 8 W (the paper's Fig. 8), B_r = 1.2 T (NdFeB, N42 class derated),
rho = 1.72e-8 ohm m (copper, 20 C), eta_pack = 0.75 (round wire, paper section 6).

Models: ``closed-form`` eq (9) (one ideal back-iron image per plate, field at
the gap centre); ``images`` the converged two-plate image series at the gap
centre; ``magpylib`` magpylib cuboids of the whole actuator (both magnet
pairs, opposite polarity, 32 image slabs per plate) with B_z averaged over the
coil leg volume (the B_g that makes eq 8 exact).

JSON (one object): ``optimal_gap_mm``, ``coil_width_mm`` (d_c = d - d_r),
``Bg_T`` (field used in eq 8 at the optimum), ``force_N`` (eq 8), ``model``,
``at_bound`` (true when the maximum sits on ``--gap-max-mm``), plus ``eta_geom``, ``power_W``, ``br_T``, ``rattle_mm``; with ``--gap-mm`` also
``gap_mm``, ``Bg_at_gap_T`` and ``force_at_gap_N`` for that gap. No actuator
gain (N/A) is given: it needs the number of turns, which eq (8) leaves free.
Bad values exit 2 with one line naming the flag.
"""

from __future__ import annotations

import typer

from cad.cli.app import print_json
from cad.errors import DesignError

_MODELS = ("closed-form", "images", "magpylib")


def _num(
    value: str | None,
    flag: str,
    *,
    positive: bool = True,
    default: float | None = None,
    required: bool = False,
) -> float | None:
    """Parse a numeric flag; DesignError naming the flag when it is not a finite (positive) number."""
    from cad.design.bounds import parse_flag

    if value is None:
        if default is None and required:
            raise DesignError(flag, "missing (required)")
        return default
    x = parse_flag(flag, value)  # range and unit slips: cad/design/bounds.py
    if positive and x <= 0:
        raise DesignError(flag, f"must be > 0, got {value!r}")
    return x


def compute(
    length: str | None,
    width: str | None,
    thickness: str | None,
    rattle: str | None,
    power: str | None = None,
    br: str | None = None,
    rho: str | None = None,
    eta_pack: str | None = None,
    model: str = "closed-form",
    gap: str | None = None,
    gap_max: str | None = None,
) -> dict:
    """Validate the flags and return the command's JSON dict (no printing)."""
    from cad.actuators import voicecoil as vc

    lm = _num(length, "--magnet-length-mm", required=True)
    wm = _num(width, "--magnet-width-mm", required=True)
    tm = _num(thickness, "--magnet-thickness-mm", required=True)
    dr = _num(rattle, "--rattle-mm", required=True)
    pw = _num(power, "--power-W", default=vc.POWER_DEFAULT_W)
    b = _num(br, "--br-T", default=vc.BR_DEFAULT_T)
    r = _num(rho, "--rho-ohm-m", default=vc.RHO_COPPER_OHM_M)
    ep = _num(eta_pack, "--eta-pack", default=vc.ETA_PACK_DEFAULT)
    if ep > 1:
        raise DesignError("--eta-pack", f"must be in (0, 1], got {eta_pack!r}")
    if model not in _MODELS:
        raise DesignError("--model", f"unknown model {model!r} (known: {', '.join(_MODELS)})")
    g = _num(gap, "--gap-mm")
    if g is not None and g <= dr:
        raise DesignError(
            "--gap-mm", f"must exceed --rattle-mm {dr:g} (no room for a coil), got {gap!r}"
        )
    gmax = _num(gap_max, "--gap-max-mm")
    if gmax is not None and gmax <= dr:
        raise DesignError("--gap-max-mm", f"must exceed --rattle-mm {dr:g}, got {gap_max!r}")
    try:
        from cad.actuators.report import voicecoil_report

        out = voicecoil_report(vc.VoiceCoilParams(lm, wm, tm, dr, pw, b, r, ep), model, g, gmax)
    except DesignError as exc:  # name the flag the user typed, not the API parameter
        raise DesignError(_FLAGS.get(exc.field, exc.field), exc.reason) from None
    return out


#: API parameter -> the flag that sets it (error messages name what the user typed).
_FLAGS = {
    "magnet_length_mm": "--magnet-length-mm",
    "magnet_width_mm": "--magnet-width-mm",
    "magnet_thickness_mm": "--magnet-thickness-mm",
    "rattle_mm": "--rattle-mm",
    "power_W": "--power-W",
    "br_T": "--br-T",
    "resistivity_ohm_m": "--rho-ohm-m",
    "eta_pack": "--eta-pack",
    "gap_max_mm": "--gap-max-mm",
    "gap_mm": "--gap-mm",
    "model": "--model",
}


def register(app: typer.Typer) -> None:
    @app.command("voicecoil")
    def voicecoil(
        magnet_length_mm: str = typer.Option(
            None, "--magnet-length-mm", metavar="MM", help="l_m, along the coil legs."
        ),
        magnet_width_mm: str = typer.Option(
            None, "--magnet-width-mm", metavar="MM", help="w_m, along the force."
        ),
        magnet_thickness_mm: str = typer.Option(
            None, "--magnet-thickness-mm", metavar="MM", help="t_m."
        ),
        rattle_mm: str = typer.Option(None, "--rattle-mm", metavar="MM", help="d_r = d - d_c."),
        power_W: str = typer.Option(None, "--power-W", metavar="W", help="Coil power [8]."),
        br_T: str = typer.Option(None, "--br-T", metavar="T", help="Magnet remanence [1.2]."),
        rho_ohm_m: str = typer.Option(
            None, "--rho-ohm-m", metavar="OHM_M", help="Resistivity [1.72e-8]."
        ),
        eta_pack: str = typer.Option(
            None, "--eta-pack", metavar="E", help="Packing efficiency [0.75]."
        ),
        model: str = typer.Option(
            "closed-form", "--model", metavar="MODEL", help="closed-form|images|magpylib."
        ),
        gap_mm: str = typer.Option(None, "--gap-mm", metavar="MM", help="Also evaluate this gap."),
        gap_max_mm: str = typer.Option(None, "--gap-max-mm", metavar="MM", help="Upper gap bound."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Optimal magnet gap of a flat voice-coil actuator (eqs 8-9, Fig. 8)."""
        out = compute(
            magnet_length_mm,
            magnet_width_mm,
            magnet_thickness_mm,
            rattle_mm,
            power_W,
            br_T,
            rho_ohm_m,
            eta_pack,
            model,
            gap_mm,
            gap_max_mm,
        )
        if as_json:
            print_json(out)
            return
        print(f"model            {out['model']}")
        print(f"optimal gap      {out['optimal_gap_mm']:.3f} mm")
        print(f"coil width       {out['coil_width_mm']:.3f} mm")
        print(f"gap field B_g    {out['Bg_T']:.4f} T")
        print(f"force (eq 8)     {out['force_N']:.3f} N at {out['power_W']:g} W")
        print(f"eta_geom         {out['eta_geom']:.4f}")
        if out["at_bound"]:
            print("note: the maximum lies on --gap-max-mm (the free optimum is beyond it)")
        if "gap_mm" in out:
            print(
                f"at gap {out['gap_mm']:g} mm: B_g {out['Bg_at_gap_T']:.4f} T, force {out['force_at_gap_N']:.3f} N"
            )
