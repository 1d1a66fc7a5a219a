"""The PowerMouse as an MJCF model (:mod:`cad.export.sim`): a free flotor driven by its six
Lorentz coils (isotropy paper §5-6).

World = the PowerMouse's frame (metres; origin the cube centre at the centre pose, the
stator's axes, z up). One body, ``flotor``, with a ``<freejoint>`` (the levitated flotor has
no mechanical joint: 3 translations + 3 rotations; the motion range ``[motion]`` is kept by
the controller and the stops, not by the model) and its mass properties from the solids
(flotor frame = world at the centre pose, exactly ``report.json`` ``flotor``). Sites: ``centre``
(the cube centre), ``com`` (the flotor's COM) and one per coil, ``coil_<face>`` at the coil's
centre (mid-plane). Actuators ``coil_<face>``: a force at the coil's site along its force
direction (:func:`cad.actuators.powermouse.coil_layout`; MJCF ``<motor site gear>``), control
and range in N: +- the eq (8)-(9) actuator force at ``[actuator] peak_power_W``
(``report.json`` ``actuator.peak_force_N``). Per ampere-turn the coil gives
``report.json`` ``gain_N_per_ampere_turn`` N (the wrench map's columns). Gravity stays MuJoCo's
default (-9.81 m/s^2 along z): a controller levitates the flotor, as on the device.
"""

from __future__ import annotations

import numpy as np

from cad.actuators import powermouse as pm
from cad.data.materials import get_material
from cad.export.sim import SimBody, SimMesh, SimModel, SimMotor


def sim_model(design, model, flotor_mp, actuator: dict) -> SimModel:
    """SimModel of the PowerMouse at its centre pose (module docstring).

    ``model``: the build's :class:`cad.assembly.model.AssemblyModel` (bodies ``flotor`` and
    ``ground``, mm); ``flotor_mp``: the flotor's MassProps (flotor frame, SI); ``actuator``:
    the report's ``actuator`` dict (``peak_force_N``: one coil's force at peak power, N).
    """
    g = model.extra.geometry
    made = {i.kind.name for i in model.instances if i.kind.made and i.kind.listed}

    def meshes(body):
        return tuple(SimMesh(i.name, f"{i.kind.name}.stl", i.tf_body_part[:3, 3] * 1e-3,
                             i.tf_body_part[:3, :3], (*get_material(i.kind.material).color_rgb, 1.0))
                     for i in model.instances if i.body == body and i.kind.name in made)

    coils = pm.coil_layout(g.coil_plane_half_mm)
    sites = {"centre": np.zeros(3), "com": np.asarray(flotor_mp.com_m, dtype=float)}
    sites |= {f"coil_{c.face}": np.asarray(c.centre_mm, dtype=float) * 1e-3 for c in coils}
    T = np.asarray(model.tf_world_body["flotor"], dtype=float)
    flotor = SimBody(name="flotor", parent="world", pos_m=T[:3, 3] * 1e-3, rot=T[:3, :3], joint="flotor",
                     joint_ref_rad=0.0, mass_kg=float(flotor_mp.mass_kg), com_m=np.asarray(flotor_mp.com_m),
                     inertia_com_kg_m2=np.asarray(flotor_mp.inertia_com_kg_m2), meshes=meshes("flotor"),
                     sites=sites, joint_type="free")
    f_peak = float(actuator["peak_force_N"])
    motors = tuple(SimMotor(f"coil_{c.face}", "", f_peak, site=f"coil_{c.face}",
                            direction=tuple(float(x) for x in c.force_dir)) for c in coils)
    return SimModel(
        name=design.name, bodies=(flotor,), world_meshes=meshes("ground"), loops=(), motors=motors,
        meshdir="parts",
        comment=(f"hapticad PowerMouse '{design.name}': world = cube centre at the centre pose (m); free "
                 f"flotor; coil actuators in N, +-{f_peak!r} N = one coil at peak_power_W "
                 f"{design.actuator.peak_power_W!r} W (eq 8-9)"),
    )
