"""The contract of the PowerMouse's ``report.json`` (:mod:`cad.report.contract`): the keys it adds to
:class:`cad.report.contract.CommonReport`, typed; units in the names, frames and meanings on
docs/families/pantograph-powermouse.md. No CAD import."""

from cad.report.contract import CommonReport


class PowerMouseReport(CommonReport):
    """The PowerMouse (haptic mouse paper): the actuator optimum (eqs 8-9) and its geometry, the flotor, the force and acceleration figures, the wrench map and its isotropy, the paper's Table 4, the test rig's BOM."""

    actuator: dict
    actuator_geometry_mm: dict
    geometry_mm: dict
    clearances_mm: dict
    gain_N_per_ampere_turn: float
    continuous_force_N: float
    peak_force_N: float
    peak_acceleration_m_s2: float
    peak_acceleration_G: float
    flotor: dict
    flotor_mass_g: float
    stator_mass_kg: float
    wrench_map: list
    wrench_map_singular_values: list
    wrench_map_units: str
    isotropy: dict
    paper_table4: dict
    rig_bom: list
