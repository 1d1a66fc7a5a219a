"""The contract of the four-bar's ``report.json`` (:mod:`cad.report.contract`): the keys it adds to
:class:`cad.report.contract.CommonReport`, typed; units in the names, frames and meanings on
docs/build-outputs.md. No CAD import."""

from typing import NotRequired

from cad.report.contract import CommonReport


class FourBarReport(CommonReport):
    """The four-bar (Hoeken paper): the linkage (``l1_mm`` .. ``le_mm``, ``phi_e_deg``, ``branch``), its metrics over the stroke, H11..H33 (eqs 13-21) and the motor rotor ``Jm_kg_m2``, the apparent mass (eq 22), each link's mass properties (``links``, link frame), the layer stack, the structure model, the motor the BOM orders; ``sheets`` with ``parts.process = "laser"``."""

    l1_mm: float
    l2_mm: float
    l3_mm: float
    l4_mm: float
    l5_mm: float
    le_mm: float
    phi_e_deg: float
    branch: int
    force_N: float
    stroke_mm: float
    dy_max_mm: float
    slope_max: float
    linearity: float
    min_transmission_angle_deg: float
    phi1_min_deg: float
    phi1_max_deg: float
    torque_mean_mNm: float
    torque_variation: float
    bbox_mm: list
    H11_kg_m2: float
    H12_kg_m2: float
    H22_kg_m2: float
    H33_kg_m2: float
    beta2_deg: float
    Jm_kg_m2: float
    apparent_mass: dict
    structure: dict | None
    links: dict
    part_masses_g: dict
    ground_mass_g: float
    layers: dict
    base_plate_mm: list
    motor: dict
    fidelity_costs: dict
    handle: str
    parts_spec: dict
    preview: str
    sheets: NotRequired[dict]
