"""Every part instance of the twin pantograph's assembly reaches its body's meshes in the MJCF
(tester finding: the capstan twin's proximal bodies carried their drums' mass but not their
drums' or axles' meshes, the meshes being listed by hand per link type).

References, independent of the code under test: the MJCF read back by MuJoCo
(``mujoco.MjModel.from_xml_path``, its own forward kinematics at the written home pose) against
the assembly model's instances (:func:`cad.families.pantograph.placement.assembly`, a second
method): the set of (body, geom, mesh) equals the set of (body, instance, kind) of every
instance with a solid, and each geom's world pose is the assembly's ``tf_world_body @
tf_body_part`` (mm -> m).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.conftest import SIM_FORMATS

ROOT = Path(__file__).resolve().parents[3]


def _mjcf_geoms(xml: Path) -> dict:
    """``{geom name: (body, mesh, 4x4 world m of the part's STL frame)}`` of the MJCF at its
    written pose (qpos0)."""
    import mujoco

    m = mujoco.MjModel.from_xml_path(str(xml))
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    out = {}
    for g in range(m.ngeom):
        T, M, R = np.eye(4), np.eye(4), np.zeros(9)
        T[:3, :3] = d.geom_xmat[g].reshape(3, 3)
        T[:3, 3] = d.geom_xpos[g]
        # MuJoCo moves a mesh geom's frame to the mesh's inertial frame (mesh_pos, mesh_quat in
        # the part's STL frame): the part's frame is the geom's times the inverse of that
        mujoco.mju_quat2Mat(R, m.mesh_quat[m.geom_dataid[g]])
        M[:3, :3], M[:3, 3] = R.reshape(3, 3), m.mesh_pos[m.geom_dataid[g]]
        T = T @ np.linalg.inv(M)
        body = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(m.geom_bodyid[g]))
        out[mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g)] = (
            "ground" if body == "world" else body,
            mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_MESH, int(m.geom_dataid[g])), T)
    return out


def _assembly_instances(design, fidelity: str) -> dict:
    """``{instance name: (body, kind, 4x4 world m)}`` of every instance with a solid."""
    from cad.families.pantograph.layout import layout
    from cad.families.pantograph.placement import assembly

    inst, tfs, _home, _holes = assembly(design, layout(design), fidelity)
    out = {}
    for i in inst:
        if i.kind.made and i.kind.listed:
            T = tfs[i.body] @ i.tf_body_part
            T[:3, 3] *= 1e-3
            out[i.name] = (i.body, i.kind.name, T)
    return out


def _check_meshes_are_the_instances(design, xml: Path, fidelity: str) -> dict:
    geoms, want = _mjcf_geoms(xml), _assembly_instances(design, fidelity)
    assert {(b, n, k) for n, (b, k, _) in geoms.items()} == {(b, n, k) for n, (b, k, _) in want.items()}
    for name, (_b, _k, T) in want.items():
        np.testing.assert_allclose(geoms[name][2][:3, 3], T[:3, 3], atol=1e-9, err_msg=name)
        np.testing.assert_allclose(geoms[name][2][:3, :3], T[:3, :3], atol=1e-9, err_msg=name)
    return geoms


def test_direct_mouse_mjcf_meshes_are_the_assembly_instances(shared_build):
    """The bundled direct twin (designs/haptic_mouse.toml): every instance with a solid is one
    geom of its body, at the assembly's world pose."""
    d, out, _ = shared_build("haptic_mouse.toml", SIM_FORMATS["haptic_mouse.toml"], "preview")
    geoms = _check_meshes_are_the_instances(d, out / f"{d.name}.xml", "preview")
    assert not any("drum" in k for _b, k, _T in geoms.values())  # no capstan, no drum


@pytest.mark.slow
def test_capstan_twin_proximal_bodies_carry_their_drums_and_axles(tmp_path):
    """designs/twin_pantograph_capstan.toml: each of the four proximal bodies has a geom whose
    mesh is its own drum (``<group>_capstan_drum_<side>``) and one whose mesh is the proximal
    axle, and the whole MJCF's geoms are the assembly's instances with a solid."""
    from cad.design import load_design
    from cad.pipeline import build_design

    d = load_design(ROOT / "designs" / "twin_pantograph_capstan.toml")
    build_design(d, tmp_path, {"mjcf", "stl"}, fidelity="preview", use_cache=False)
    geoms = _check_meshes_are_the_instances(d, tmp_path / f"{d.name}.xml", "preview")
    for grp in ("crank", "knob"):
        for side in ("left", "right"):
            body = f"{grp}_proximal_{side}"
            meshes = {k for b, k, _T in geoms.values() if b == body}
            assert {f"{grp}_capstan_drum_{side}", "proximal_axle"} <= meshes, (body, meshes)
