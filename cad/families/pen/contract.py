"""The contract of the haptic pen's ``report.json`` (:mod:`cad.report.contract`): the keys it adds to
:class:`cad.report.contract.CommonReport`, typed; units in the names, frames and meanings on
docs/families/pen.md. No CAD import."""

from cad.report.contract import CommonReport


class PenReport(CommonReport):
    """The haptic pen (isotropy paper §5): the GII, the layout and the ground, the bench plane, the 5 x 5 effective mass at home and its breakdown over the parts (x axis), the paper's Table 3."""

    design: str
    gii: dict
    layout_mm: dict
    ground_mm: dict
    home: dict
    bench_z_mm: float
    lowest_z_mm: float
    effective_mass_home: dict
    effective_mass_breakdown: dict
    paper_table3: dict
