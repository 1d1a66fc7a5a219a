"""The kinematic model a family gives the firmware generator (:mod:`cad.firmware`).

A linkage family's package builds one :class:`KinematicModel` per kinematic layout (the
four-bar: :mod:`cad.families.fourbar.firmware`; the 5-bar and the twin pantograph:
:mod:`cad.families.pantograph.firmware`) and passes it to :func:`cad.firmware.linkage_files`.
The generator's generic code -- the numpy reference (:mod:`cad.firmware.reference`), the test
vectors, the C header and common code, the wall sketch, the CHAI3D file -- calls these hooks
and never asks which family it serves.

Conventions of every hook: joint angles ``q`` (N, n_joints) rad; task coordinates X
(N, n_task) m (the twin's theta in rad); the device frame of the model's :attr:`frame`;
status codes of :data:`cad.firmware.reference.STATUS` (rows not ok carry zeros).

No CAD imports.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

import numpy as np

Hook = Callable[..., Any]


def perp(v: np.ndarray) -> np.ndarray:
    """(..., 2) vectors turned by +90 degrees about z."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def rot(a, c) -> np.ndarray:
    """The body-frame vector ``c`` (2,) turned by the angles ``a`` (N,) rad: (N, 2)."""
    ca, sa = np.cos(a), np.sin(a)
    return np.stack([ca * c[0] - sa * c[1], sa * c[0] + ca * c[1]], axis=-1)


@dataclasses.dataclass(frozen=True)
class SpecParams:
    """What a model reads off a built design for the :class:`cad.firmware.spec.DeviceSpec`:
    ``params`` (the C constants, m / rad / mode signs), ``q_home_rad``, ``bodies``
    (``{name: Body}`` from report.json), ``n_joints``, ``n_task``; ``gravity_m_s2``: the
    device's own gravity vector (a spatial device, e.g. the delta's (0, 0, -g)), None: from
    the design's ``[firmware] plane`` (:func:`cad.firmware.spec.gravity_vector`)."""

    params: dict
    q_home_rad: tuple[float, ...]
    bodies: dict
    n_joints: int
    n_task: int
    gravity_m_s2: tuple[float, ...] | None = None


@dataclasses.dataclass(frozen=True)
class KinematicModel:
    """One kinematic layout's hooks (module docstring for the conventions).

    kind : the layout's name in the generated files (``fourbar``, ``fivebar``, ``twin``).
    frame : the device frame sentence of every banner.
    spec_params : ``(design, report, device) -> SpecParams``.
    forward : ``(spec, q) -> (X, status)``.
    jacobian : ``(spec, q) -> dX/dq (N, n_task, n_joints)``.
    com_rates : ``(spec, q) -> (ok (N,), {body: (r_G (N, 2) m, dr_G/dq (N, 2, n_joints))})``.
    mass_matrix : ``(spec, q_ok, X_ok) -> M (n_ok, n_task, n_task)`` kg at the ok rows.
    c_source : ``spec -> str``: the layout's part of ``hapticad_device.c``.
    poses_ok : ``(spec, design, rng, n) -> q``: in-range test poses.
    poses_bad : ``(spec, q_ok, rng, n) -> q``: poses the C code must refuse.
    workspace_radius_m : ``(spec, design) -> float`` (the CHAI3D file).
    force_jacobian : ``(spec, q) -> (N, 2, n_joints)``: joint torques to handle force map for
        the force limits (None: the translational rows of ``jacobian``).
    joint_torques : ``(spec, q, F) -> tau (N, n_joints)`` (None: tau = J^T F).
    gravity_extra : ``(spec, q, g) -> (tau (N, n_joints), ok (N,))``: gravity of bodies
        ``com_rates`` leaves out (None: none).
    apparent_mass_kg : ``(spec, q_ok) -> (n_ok,)``: the scalar mass along the path (None:
        the C code refuses ``hc_apparent_mass``).
    force_scale : factor of each task-force column of the test vectors (None: all 1).
    wall_normal : ``(spec, q_home (1, n_joints)) -> (2,)`` the wall sketch's normal (None: +x).
    senses_rotation : the task has a rotation the device senses and renders (CHAI3D).
    identify : ``(design, report, spec) -> {file: text}``: the identification routine's files
        under ``firmware/`` (None: not generated).
    identification : the :class:`cad.sim.identify_kits.IdentifyKit` of ``hapticad identify``
        and ``bench-log`` (None: the layout is not identified).
    n_translation : the first task coordinates that are handle translations (m): the encoder
        step and the force limits read these rows of the Jacobian (2: planar; the delta 3).
    header_extra : C declarations of the layout's own functions in ``hapticad_device.h``
        (the delta's ``hc_inverse``).
    workspace_note : the CHAI3D file's note on ``m_workspaceRadius`` (None: the planar one).
    """

    kind: str
    frame: str
    spec_params: Hook
    forward: Hook
    jacobian: Hook
    com_rates: Hook
    mass_matrix: Hook
    c_source: Hook
    poses_ok: Hook
    poses_bad: Hook
    workspace_radius_m: Hook
    force_jacobian: Hook | None = None
    joint_torques: Hook | None = None
    gravity_extra: Hook | None = None
    apparent_mass_kg: Hook | None = None
    force_scale: tuple[float, ...] | None = None
    wall_normal: Hook | None = None
    senses_rotation: bool = False
    identify: Hook | None = None
    identification: Any = None
    n_translation: int = 2
    header_extra: str = ""
    workspace_note: str | None = None
