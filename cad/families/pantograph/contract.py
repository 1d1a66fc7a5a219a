"""The contract of the 5-bar and the twin pantograph's ``report.json`` (:mod:`cad.report.contract`): the keys it adds to
:class:`cad.report.contract.CommonReport`, typed; units in the names, frames and meanings on
docs/families/pantograph-powermouse.md. No CAD import."""

from typing import NotRequired

from cad.report.contract import CommonReport


class PantographReport(CommonReport):
    """The 5-bar and the twin pantograph (isotropy paper): the GII (eq 5) over the workspace, the layout and 2-D clearances, the bench plane, the effective mass at home (the twin pantograph: Table 1, with and without the rotors), the motor the BOM orders."""

    design: str
    gii: dict
    layout_mm: dict
    clearances_mm: dict
    bench_z_mm: float
    lowest_z_mm: float
    motor: dict
    home: dict
    effective_mass_home: dict
    crank_mm: NotRequired[float]
    effective_mass_home_without_rotors: NotRequired[dict]
    paper_table1: NotRequired[dict]
    effective_mass_note: NotRequired[str]
