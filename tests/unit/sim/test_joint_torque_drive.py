"""The MuJoCo plants (the 1-DOF bench, the joint benches, the wall) drive a joint motor whose
MJCF ``gear`` is a capstan's n with the joint torque / n: MuJoCo applies gear x ctrl at the
joint (its own ``qfrc_actuator`` is the reference), and the joint's torque bound is the
actuator's range times n. Before this the 1-DOF bench and the wall gave n^2 instead of n."""

from __future__ import annotations

import types

import numpy as np
import pytest

from cad.sim import mj

mujoco = pytest.importorskip("mujoco")

GEAR = 4.25
TAU_MAX = 0.8  # N m at the joint

MJCF = f"""<mujoco>
  <option gravity="0 0 0" timestep="0.0005"/>
  <worldbody>
    <body name="crank_link">
      <joint name="crank" type="hinge" axis="0 0 1"/>
      <geom type="capsule" fromto="0 0 0 0.05 0 0" size="0.005" mass="0.02"/>
      <site name="handle" pos="0.05 0 0"/>
    </body>
  </worldbody>
  <actuator>
    <motor name="m" joint="crank" gear="{GEAR}" ctrllimited="true" ctrlrange="-1 1"
           forcelimited="true" forcerange="-1 1"/>
  </actuator>
</mujoco>
"""


@pytest.fixture
def mjcf(tmp_path):
    p = tmp_path / "one.xml"
    p.write_text(MJCF)
    return p


def _joint_torque(m, d) -> float:
    mujoco.mj_forward(m, d)
    return float(d.qfrc_actuator[mj.joint_dof(m, "crank")])


def test_helper_reads_the_gear_and_bounds_the_joint_torque(mjcf):
    m, d = mj.load(mjcf)
    assert mj.joint_torque_drive(m, 0, TAU_MAX) == GEAR
    np.testing.assert_allclose(m.actuator_forcerange[0], [-TAU_MAX / GEAR, TAU_MAX / GEAR], rtol=1e-15)
    d.ctrl[0] = 10.0  # beyond the range: MuJoCo clamps the actuator force, the joint sees n x that
    assert _joint_torque(m, d) == pytest.approx(TAU_MAX, rel=1e-12)


def test_bench_plant_applies_the_commanded_crank_torque(mjcf):
    from cad.sim.bench import _MujocoPlant

    tr = {"mass_factor": 1.0, "rotor_kg_m2": 1e-5, "b_Nm_s_per_rad": 0.0, "Tc_Nm": 0.0,
          "gravity_scale": 1.0, "offset_Nm": 0.0}
    plant = _MujocoPlant(mjcf, tr, -10.0, 10.0, TAU_MAX)
    plant.advance(0.3, 1e-3)
    assert _joint_torque(plant.m, plant.d) == pytest.approx(0.3, rel=1e-12)
    plant.advance(5.0, 1e-3)  # saturates at the crank's bound, not n times it
    assert _joint_torque(plant.m, plant.d) == pytest.approx(TAU_MAX, rel=1e-12)


def test_wall_plant_applies_the_commanded_crank_torque(mjcf):
    from cad.sim.wall import MujocoWall, WallSpec

    spec = WallSpec(1e-3, 4096.0, 0.0, 0.0, TAU_MAX, 0.1)
    wall = MujocoWall(mjcf, types.SimpleNamespace(x_axis=(1.0, 0.0)), spec)
    wall.apply(-0.25)
    assert _joint_torque(wall.m, wall.d) == pytest.approx(-0.25, rel=1e-12)
    wall.apply(-3.0)
    assert _joint_torque(wall.m, wall.d) == pytest.approx(-TAU_MAX, rel=1e-12)
