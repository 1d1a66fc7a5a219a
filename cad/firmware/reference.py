"""hapticad's own numpy model of a :class:`~cad.firmware.spec.DeviceSpec`: the values the
generated C code is tested against (test vectors), through the spec's kinematic model
(:class:`cad.firmware.model.KinematicModel`, built on :mod:`cad.kinematics` by the family).

Every function is vectorized over N joint-angle rows ``q`` (N, n_joints) rad and returns
SI values in the device frame: ``forward`` -> (X (N, n_task) m [rad], status (N,)),
``jacobian`` -> dX/dq (N, n_task, n_joints), ``joint_torques`` -> tau (N, n_joints) N m for a
task force/wrench F (N, n_task), ``gravity_torques`` -> tau_g (N, n_joints) N m, the motor
torques that hold the device against gravity (= dV/dq), ``mass_matrix`` -> M (N, n_task,
n_task), the task-space mass matrix for feed-forward (kg; the twin's theta entries kg m and
kg m^2).
Status codes are those of the C code (:data:`STATUS`); rows that are not ok carry zeros.
"""

from __future__ import annotations

import numpy as np

#: C status codes (HC_OK ...), shared by the generator and the reference.
STATUS = {"HC_OK": 0, "HC_ERR_RANGE": 1, "HC_ERR_CLOSURE": 2, "HC_ERR_SINGULAR": 3,
          "HC_ERR_MODE": 4, "HC_ERR_CRANK": 5}


def _q(q) -> np.ndarray:
    return np.atleast_2d(np.asarray(q, dtype=float))


def forward(spec, q) -> tuple[np.ndarray, np.ndarray]:
    """(X (N, n_task), status (N,)) at joint angles ``q``."""
    return spec.model.forward(spec, _q(q))


def jacobian(spec, q) -> np.ndarray:
    """dX/dq (N, n_task, n_joints)."""
    return spec.model.jacobian(spec, _q(q))


def joint_torques(spec, q, F) -> np.ndarray:
    """tau = J^T F, or the model's own map (the twin: least-norm torques)."""
    q, F = _q(q), _q(F)
    if spec.model.joint_torques is not None:
        return spec.model.joint_torques(spec, q, F)
    return np.einsum("nij,ni->nj", jacobian(spec, q), F)


def com_rates(spec, q):
    """(ok (N,), {body: (r_G (N,2) m, dr_G/dq (N,2,n) m/rad)}) of the bodies whose COM moves
    with the joints only."""
    return spec.model.com_rates(spec, _q(q))


def gravity_torques(spec, q) -> np.ndarray:
    """Motor torques that hold the device against gravity, dV/dq (N, n_joints) N m (zeros for
    a horizontal device); bodies the COM rates leave out through the model's
    ``gravity_extra``."""
    q = _q(q)
    tau = np.zeros((len(q), spec.n_joints))
    if spec.gravity_m_s2 is None:
        return tau
    g = np.asarray(spec.gravity_m_s2)
    ok, rates = com_rates(spec, q)
    for name, (_, dr) in rates.items():
        tau -= spec.bodies[name].mass_kg * np.einsum("i,nij->nj", g, dr)
    if spec.model.gravity_extra is not None:
        extra, ok_extra = spec.model.gravity_extra(spec, q, g)
        tau += extra
        ok &= ok_extra
    return np.where(ok[:, None], tau, 0.0)


def mass_matrix(spec, q) -> np.ndarray:
    """Task mass matrix (N, n_task, n_task) at the ok rows of ``q`` (zeros elsewhere), the
    model's (four-bar: Hoeken paper eq 22; pantographs: :mod:`cad.kinematics`)."""
    q = _q(q)
    X, status = forward(spec, q)
    ok = status == 0
    M = np.zeros((len(q), spec.n_task, spec.n_task))
    if ok.any():
        M[ok] = spec.model.mass_matrix(spec, q[ok], X[ok])
    return M
