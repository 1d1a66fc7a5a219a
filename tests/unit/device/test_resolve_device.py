"""cad.device.resolve_device: one description of the device per design (issue 32 item 1).

References: the papers' encoders (Hoeken paper §III.A "a general purpose 2000 counts/rev
optical encoder"; isotropy paper §3.2 "a 1000 window (4000 cpt) optical encoder"), the
issue's measured 3836.75 counts/rev of the bundled Hoeken's [stiffness] Delta (the datasheet
of c980ef6) recomputed here by central finite differences of the coupler point, and the
design file's own values.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design
from cad.device import resolve_device
from cad.errors import DesignError

DESIGNS = Path(__file__).resolve().parents[3] / "designs"


def _hoeken(tmp_path, parts: str = "", extra: str = ""):
    p = tmp_path / "d.toml"
    p.write_text((DESIGNS / "hoeken.toml").read_text().replace("[parts]\n", "[parts]\n" + parts) + extra)
    return load_design(p)


def test_the_hoeken_encoder_is_its_stiffness_step_in_whole_counts():
    from cad.kinematics.fourbar import coupler_point_and_jacobian

    d = load_design(DESIGNS / "hoeken.toml")
    h, mid = 1e-6, 0.5 * (d.phi1_min_rad + d.phi1_max_rad)
    P = coupler_point_and_jacobian(d.linkage, np.array([d.phi1_min_rad, d.phi1_max_rad, mid - h, mid + h]))[0]
    x = (P[1] - P[0]) / np.linalg.norm(P[1] - P[0])
    J_m = abs((P[3] - P[2]) @ x) / (2 * h) * 1e-3
    exact = 2 * math.pi * J_m / d.stiffness.encoder_resolution_m
    assert exact == pytest.approx(3836.75, abs=0.005)  # the figure
    e = resolve_device(d).encoder
    assert (e.counts_per_rev, e.field, e.joint) == (round(exact), "stiffness.encoder_resolution_m", "crank")


@pytest.mark.parametrize("fn, n", [("pantograph.toml", 2), ("haptic_mouse.toml", 4), ("haptic_pen.toml", 6)])
def test_the_isotropy_paper_devices_get_its_4000_cpt_encoder_on_every_motor(fn, n):
    dev = resolve_device(load_design(DESIGNS / fn))
    assert len(dev.motors) == len(dev.encoders) == len(dev.transmissions) == n
    assert {e.counts_per_rev for e in dev.encoders} == {4000}
    assert all("isotropy paper §3.2" in e.source for e in dev.encoders)
    assert [e.joint for e in dev.encoders] == [m.joint for m in dev.motors]
    assert {t.kind for t in dev.transmissions} == {"direct"} and {t.ratio for t in dev.transmissions} == {1.0}


def test_a_four_bar_without_encoder_data_gets_the_hoeken_prototypes():
    e = resolve_device(load_design(DESIGNS / "roberts.toml")).encoder
    assert e.counts_per_rev == 2000 and "Hoeken paper §III.A" in e.source


def test_the_powermouse_has_no_rotary_motor_or_encoder():
    dev = resolve_device(load_design(DESIGNS / "powermouse.toml"))
    assert dev.motors == () and dev.encoders == ()


def test_the_motor_table_overrides_the_catalog_with_its_sources(tmp_path):
    # Kt 60 mN m/A with 1.5 A carries 90 mN m continuous (T_N = Kt I_N: one continuous limit)
    d = _hoeken(tmp_path, extra='\n[motor]\nname = "acme-60"\ntorque_constant_mNm_per_A = 60.0\n'
                                'torque_continuous_mNm = 90.0\nrotor_inertia_g_cm2 = 20.0\n'
                                'current_continuous_A = 1.5\n')
    m = resolve_device(d).motor
    assert (m.name, m.catalog_key, m.from_motor_table) == ("acme-60", "maxon-re35", True)
    assert m.kt_Nm_per_A == 0.06 and m.rotor_inertia_kg_m2 == pytest.approx(2.0e-6, rel=1e-15)
    assert "[motor] torque_constant_mNm_per_A" in m.spec.source_of("torque_constant_mNm_per_A")
    assert m.spec.stall_torque_mNm == 972.5  # not given: the catalog's, sourced to it
    doc = json.loads(json.dumps(resolve_device(d).as_dict()))
    assert doc["motors"][0]["constants"]["torque_constant_mNm_per_A"]["value"] == 60.0


def test_two_rotor_inertias_that_disagree_are_refused(tmp_path):
    with pytest.raises(DesignError, match=r"parts.motor_rotor_inertia_g_cm2: 30 g cm\^2 disagrees with "
                                          r"motor.rotor_inertia_g_cm2 = 20"):
        resolve_device(_hoeken(tmp_path, "motor_rotor_inertia_g_cm2 = 30.0\n",
                               "\n[motor]\nrotor_inertia_g_cm2 = 20.0\n"))
    m = resolve_device(_hoeken(tmp_path, "motor_rotor_inertia_g_cm2 = 30.0\n")).motor
    assert m.rotor_inertia_kg_m2 == pytest.approx(3.0e-6, rel=1e-15)
    assert m.spec.source_of("rotor_inertia_g_cm2") == "design file: parts.motor_rotor_inertia_g_cm2"


def test_the_device_is_frozen_and_resolved_once_per_design(tmp_path):
    d = _hoeken(tmp_path)
    a, b = resolve_device(d, "inertia"), resolve_device(d, "preview")
    assert a.encoders is b.encoders and (a.fidelity, b.fidelity) == ("inertia", "preview")
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.fidelity = "fabrication"


@pytest.mark.parametrize("name", ["pantograph", "delta"])
def test_encoder_bom_line_fills_material_as_other_bought_parts_do(name):
    """The encoder line reads like every other bought line: its process is "bought" and its
    material column names a material or is empty -- never "bought" (bearings read steel-1018,
    screws the fastener steel; no catalog states an encoder's material, so it is empty)."""
    from cad.data.materials import MATERIALS
    from cad.device import encoder_bom_rows

    rows = encoder_bom_rows(resolve_device(load_design(DESIGNS / f"{name}.toml")))
    assert rows and all(r["process"] == "bought" and r["made_or_bought"] == "bought" for r in rows)
    assert all(r["material"] == "" or r["material"] in MATERIALS for r in rows)
