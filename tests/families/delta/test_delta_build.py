"""The delta through the family protocol (issue 36 §3-4): ``hapticad build`` and its
datasheet rows.

* the force in every direction (:func:`cad.families.delta.datasheet.force_in_every_direction_N`,
  tau sigma_min(J^T)) against a brute force over 2000 sampled force directions at every grid
  point, each mapped to joint torques by :func:`cad.kinematics.delta.joint_torques_Nm`
  (tau = J^-T f, eq 2) and scaled to |tau|_2 = the torque: a second path through the
  statics;
* the Falcon design (Stamper's joint offset g > 0) is refused before any CAD in one line;
* (slow) the bundled delta builds: the report's moving mass is the sum of the placement's
  body masses read back from report.json, its Lambda eigenvalues are recomputed from those
  body mass properties, its first mode is the frame model's at the centre.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import cad
from cad.errors import DesignError
from cad.families.delta.datasheet import force_in_every_direction_N
from cad.kinematics.delta import joint_torques_Nm
from tests.conftest import DELTA_FORMATS

ROOT = Path(__file__).resolve().parents[3]


def test_force_in_every_direction_matches_sampled_directions():
    d = cad.load_design(ROOT / "designs" / "delta.toml")
    tau = 0.0876  # N m, a motor's continuous torque (any value: the figure is linear in it)
    got, where = force_in_every_direction_N(d, tau)
    rng = np.random.default_rng(36)
    u = rng.normal(size=(2000, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    X = d.workspace_points()
    worst = np.inf
    for P in X:
        t = joint_torques_Nm(d.mechanism, np.repeat(P[None], len(u), 0), u)  # per unit force
        worst = min(worst, float(np.min(tau / np.linalg.norm(t, axis=1))))
    # sampled directions can only find a force at or above the exact minimum
    assert worst >= got * (1 - 1e-12)
    assert worst == pytest.approx(got, rel=2e-3)
    assert any(np.allclose(where, P) for P in X)


def test_a_clashing_knee_layout_is_refused_before_any_cad(tmp_path, monkeypatch):
    """The Falcon on the layout before the crank (straight fork, brackets at the g = 0 stack:
    its knees fold under eq (1)'s limit) is refused in one line, nothing written."""
    from cad.families.delta import hardware as hw

    monkeypatch.setattr(hw, "CRANK_ANGLE_DEG", 0.0)
    monkeypatch.setattr(hw, "KNEE_BRACKET_OFFSET_MM", 0.0)
    d = cad.load_design(ROOT / "designs" / "delta_falcon.toml")
    with pytest.raises(DesignError, match="mechanism.joint_offset_mm") as e:
        cad.build_design(d, tmp_path / "f", formats="step")
    assert "\n" not in str(e.value) and not (tmp_path / "f").exists()


@pytest.mark.slow  # a minute: every pair of solids at 125 workspace points (the cheap checks above)
def test_the_bundled_delta_builds_and_its_report_reads_back(shared_build):
    from cad.families.delta.dynamics import mass_matrix_from_bodies_kg
    from cad.families.delta.structure import first_mode
    from cad.massprops.props import MassProps

    d, out, rep = shared_build("delta.toml", DELTA_FORMATS, "preview")  # report.json read back
    bodies = {k: MassProps(v["mass_kg"], np.asarray(v["com_mm"]) * 1e-3,
                           np.asarray(v["inertia_com_kg_m2"]))
              for k, v in rep["placement"]["bodies"].items()}
    moving = sum(mp.mass_kg for k, mp in bodies.items() if k != "ground")
    assert rep["moving_mass_g"] == pytest.approx(moving * 1e3, rel=1e-9)
    lam = mass_matrix_from_bodies_kg(d.mechanism, d.workspace_points(), d.parallelogram_width_mm,
                                     bodies, rep["apparent_mass"]["rotor_inertia_kg_m2"])
    eig = np.linalg.eigvalsh(lam)
    assert rep["apparent_mass"]["Lambda_max_eig_g"] == pytest.approx(eig[:, -1].max() * 1e3, rel=1e-9)
    st = first_mode(d.mechanism, np.asarray(d.workspace["center_mm"]), d.parallelogram_width_mm)
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    assert rows["first_mode_Hz"]["value"] == pytest.approx(st["first_mode_Hz"], rel=1e-12)
    assert rep["overlap_volume_mm3"] == 0.0 and (out / "bom.csv").is_file()


def test_the_report_maps_the_apparent_mass_over_the_workspace(shared_build):
    """The map (issue 36 §4): apparent_mass_map.png written, listed and shown in report.md;
    read back as an image of one panel per grid height (5 for the 5 x 5 x 5 box); its layers
    hold Lambda's eigenvalues at every grid point, recomputed here from report.json's bodies,
    and the extremes are report.json's."""
    import matplotlib.image as mpimg

    from cad.families.delta.dynamics import mass_matrix_from_bodies_kg
    from cad.families.delta.report_map import APPARENT_MASS_MAP, map_layers
    from cad.massprops.props import MassProps

    d, out, rep = shared_build("delta.toml", DELTA_FORMATS, "preview")
    assert APPARENT_MASS_MAP in rep["files"]
    assert f"]({APPARENT_MASS_MAP})" in (out / "report.md").read_text()
    img = mpimg.imread(out / APPARENT_MASS_MAP)
    assert img.shape[:2] == (480, round((2.3 * 5 + 1.2) * 100))
    bodies = {k: MassProps(v["mass_kg"], np.asarray(v["com_mm"]) * 1e-3, np.asarray(v["inertia_com_kg_m2"]))
              for k, v in rep["placement"]["bodies"].items()}
    X = d.workspace_points()
    eig = np.linalg.eigvalsh(mass_matrix_from_bodies_kg(d.mechanism, X, d.parallelogram_width_mm, bodies,
                                                        rep["apparent_mass"]["rotor_inertia_kg_m2"])) * 1e3
    layers = map_layers(X, eig)
    assert len(layers) == 5 and sum(len(xy) for _, xy, _ in layers) == len(X)
    assert max(e[:, -1].max() for *_, e in layers) == pytest.approx(rep["apparent_mass"]["Lambda_max_eig_g"],
                                                                     rel=1e-9)
    assert min(e[:, 0].min() for *_, e in layers) == pytest.approx(rep["apparent_mass"]["Lambda_min_eig_g"],
                                                                   rel=1e-9)


@pytest.mark.slow  # a delta build (every pair of solids at 125 points); cheap share: test_delta_sim.py
def test_the_built_delta_mjcf_against_eq1_over_the_grid(tmp_path):
    """The written MJCF (workspace centre) and the MJCF of the built bodies at every grid
    point in MuJoCo against Lambda(x) of eq (1): they differ only through the rods' free spin
    (docs/families/delta.md, "MuJoCo model"): a regression pin of the measured worst, 0.28 %,
    with the built rod's axial inertia and the offset of its centre from its axis."""
    from cad.device import resolve_device
    from cad.export.sim import mjcf_text
    from cad.families.delta.dynamics import mass_matrix_from_bodies_kg
    from cad.families.delta.sim import sim_model
    from cad.massprops.props import MassProps
    from tests.families.delta.test_delta_sim import mujoco_lambda

    d = cad.load_design(ROOT / "designs" / "delta.toml")
    out = tmp_path / "delta"
    cad.build_design(d, out, formats="step,mjcf", fidelity="preview")
    rep = json.loads((out / "report.json").read_text())
    bodies = {k: MassProps(v["mass_kg"], np.asarray(v["com_mm"]) * 1e-3, np.asarray(v["inertia_com_kg_m2"]))
              for k, v in rep["bodies"].items()}
    rod = bodies["lower_0_a"]
    assert rod.inertia_com_kg_m2[0, 0] == pytest.approx(1.08e-8, rel=0.01)  # regression pin
    assert np.hypot(*rod.com_m[1:]) * 1e3 == pytest.approx(0.44, abs=0.005)  # regression pin
    dev = resolve_device(d)
    lam0, residual, _ = mujoco_lambda((out / "delta.xml").read_text())
    assert residual < 1e-12
    worst = 0.0
    for P in d.workspace_points():
        lam = lam0 if np.allclose(P, d.workspace["center_mm"]) else mujoco_lambda(
            mjcf_text(sim_model(d, bodies, dev, P)))[0]
        ref = mass_matrix_from_bodies_kg(d.mechanism, P[None], d.parallelogram_width_mm, bodies,
                                         dev.motor.rotor_inertia_kg_m2)[0]
        worst = max(worst, float(np.abs(lam - ref).max() / np.abs(ref).max()))
    assert worst == pytest.approx(0.0028, abs=0.00005)  # regression pin of the measured 0.28 %


def test_k_max_row_is_eq25_at_the_worst_resolution():
    """The delta's K_max row (issue 36 §4): eq (25) of the Hoeken paper, 2 (Fs + Fv xdot) /
    (Delta + xdot Te), with the paper's Fv 0.12 N s/m, Fs 0.083 N, Te 0.33 ms, xdot 0.04 m/s
    (§III.B.4, typed here from the paper) and Delta the datasheet's worst resolution."""
    from cad.families.delta.datasheet import rows_and_limits

    d = cad.load_design(ROOT / "designs" / "delta.toml")
    rows = {r["key"]: r for r in rows_and_limits(d, {})[0]}
    delta_m = rows["resolution_um"]["value"] * 1e-6
    k = rows["eq25_K_max_N_per_m"]
    assert k["value"] == pytest.approx(2 * (0.083 + 0.12 * 0.04) / (delta_m + 0.04 * 0.33e-3), rel=1e-12)
    k_lo = 2 * 0.12 / 0.33e-3  # eq (25)'s lower side 2 Fv / Te, stated in words, not as a range
    assert k["min"] is None and k["max"] is None and k["unverified"]
    assert (f"eq (25) range {k_lo:.4g} .. {k['value']:.4g} N/m" in k["model"] if k["value"] >= k_lo
            else f"range empty: its upper side {k['value']:.4g} N/m" in k["model"])
    assert k["inputs"]["encoder_resolution_m"] == pytest.approx(delta_m, rel=1e-15)


def test_k_max_row_with_a_coarse_encoder_says_its_range_is_empty():
    """A resolution Delta coarse enough (1.5x the step where the two sides meet, by hand) that
    eq (25)'s upper side falls below 2 Fv / Te: the row says the range is empty."""
    from cad.families.delta.datasheet import k_max_row

    k_lo = 2 * 0.12 / 0.33e-3
    delta_um = 2 * (0.083 + 0.12 * 0.04) / k_lo * 1e6 * 1.5  # Delta putting the upper side below
    k = k_max_row(delta_um)
    assert k["value"] == pytest.approx(2 * (0.083 + 0.12 * 0.04) / (delta_um * 1e-6 + 0.04 * 0.33e-3))
    assert k["value"] < k_lo and "range empty" in k["model"] and k["min"] is None


@pytest.mark.slow  # the Falcon's build (every pair of solids at 125 points), ~45 s
def test_the_falcon_builds_and_its_mjcf_and_firmware_carry_the_knee(tmp_path):
    """The Falcon (g = 22.5 mm) builds clean over its 90 mm cube; its written MJCF (knee
    hinges, rods hinged at the knee) in MuJoCo equals Lambda(x) of eq (1) from the built bodies
    at every grid point to 1e-10 (the rods' spin is held by their hinges: no free spin here,
    unlike g = 0); the firmware's mass model reads the built knee; the datasheet's mode is the
    frame model's; the notes say the motor is not the Falcon's."""
    from cad.device import resolve_device
    from cad.export.sim import mjcf_text
    from cad.families.delta.assembly import assemble
    from cad.families.delta.dynamics import delta_mass_from_bodies, mass_matrix_from_bodies_kg
    from cad.families.delta.sim import sim_model
    from cad.families.delta.structure import first_mode, sections_from_parts
    from cad.massprops.props import MassProps
    from cad.pipeline import family
    from tests.families.delta.test_delta_sim import nullspace_lambda

    d = cad.load_design(ROOT / "designs" / "delta_falcon.toml")
    out = tmp_path / "falcon"
    cad.build_design(d, out, formats="step,mjcf,firmware", fidelity="preview")
    rep = json.loads((out / "report.json").read_text())
    assert rep["overlap_volume_mm3"] == 0.0
    bodies = {k: MassProps(v["mass_kg"], np.asarray(v["com_mm"]) * 1e-3, np.asarray(v["inertia_com_kg_m2"]))
              for k, v in rep["bodies"].items()}
    assert bodies["knee_0"].mass_kg > 0
    dev = resolve_device(d)
    lam0, residual, _, rank = nullspace_lambda((out / "delta_falcon.xml").read_text())
    assert residual < 1e-12 and rank == 12
    for P in d.workspace_points():
        lam = lam0 if np.allclose(P, d.workspace["center_mm"]) else nullspace_lambda(
            mjcf_text(sim_model(d, bodies, dev, P)))[0]
        ref = mass_matrix_from_bodies_kg(d.mechanism, P[None], d.parallelogram_width_mm, bodies,
                                         dev.motor.rotor_inertia_kg_m2)[0]
        assert np.abs(lam - ref).max() < 1e-10 * np.abs(ref).max()
    mass = delta_mass_from_bodies(d.mechanism, bodies, dev.motor.rotor_inertia_kg_m2)
    c = (out / "firmware" / "hapticad_device.c").read_text()
    assert f"M_KNEE = HC_R({mass.knee_kg!r})" in c and mass.knee_kg == bodies["knee_0"].mass_kg
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    inst = assemble(d, "preview").instances  # the knee hinges' drawn parts at the rods' top ends
    sec = sections_from_parts(d.mechanism.effector_radius_mm, d.parallelogram_width_mm, inst, family.kind_props(inst))
    st = first_mode(d.mechanism, np.asarray(d.workspace["center_mm"]), d.parallelogram_width_mm, sec)
    assert rows["first_mode_Hz"]["value"] == pytest.approx(st["first_mode_Hz"], rel=1e-12)
    assert any("not the Falcon's motors" in n for n in rep["datasheet"]["notes"])


def test_an_overlap_in_the_report_is_a_datasheet_miss(shared_build):
    """A tester found a delta built with overlapping solids (a cached or --allow-interference
    build) got a datasheet with the overlap row and no verdict: the row has a limit (<= 0 mm^3,
    cad.datasheet.limits.OVERLAP_LIMIT), a MISS and a warning naming it."""
    import copy

    from cad.datasheet import datasheet

    d, _, rep = shared_build("delta.toml", DELTA_FORMATS, "preview")
    ok = datasheet(d, rep, simulate_wall=False)
    row = next(r for r in ok["rows"] if r["key"] == "overlap_volume_mm3")
    assert row["value"] == 0.0 and not any("overlap" in w for w in ok["warnings"])
    bad = copy.deepcopy(rep)
    bad["interference"]["overlap_volume_mm3"] = 1593.3
    ds = datasheet(d, bad, simulate_wall=False)
    assert not ds["ok"]
    assert [w for w in ds["warnings"] if "overlap" in w and "1593" in w and "<= 0" in w], ds["warnings"]

