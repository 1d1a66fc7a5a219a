"""``hapticad bench --only wall``: Z-width of the bundled Hoeken (issue 14).

Charts (PNG + SVG in the bench folder):

* ``wall_zwidth`` -- the stable region in the K-B plane (reduced model, K_max by bisection
  for each B), with the Colgate-Schenkel passivity bound and eq (25);
* ``wall_kmax_sampling_encoder`` -- K_max against the sampling period Te and against the
  encoder resolution (counts per crank turn), B = 0, with eq (25) for the same Te / Delta;
* ``wall_error_vs_time`` -- speed against accuracy: K_max of the reduced model at several
  plant sub-steps against its wall time, error relative to the mujoco model (the
  exported MJCF, full closed-loop dynamics) at the paper's Te and Delta.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from cad.bench.common import save_chart
from cad.data.catalog import get_motor
from cad.design import load_design
from cad.dynamics.inertia import InertiaCoefficients
from cad.dynamics.stiffness import StiffnessInputs, stiffness_range_N_per_m
from cad.sim import wall
from cad.sim.device import device_build, read_device_report


def _device():
    root = Path(__file__).resolve().parents[2]
    d = load_design(root / "designs" / "hoeken.toml")
    folder = device_build(d)
    rep = read_device_report(folder, "bench")
    H = InertiaCoefficients(rep["H11_kg_m2"], rep["H12_kg_m2"], rep["H22_kg_m2"], rep["H33_kg_m2"],
                            math.radians(rep["beta2_deg"]))
    tab = wall.device_tables(d, H)
    st = d.stiffness
    counts = 2 * math.pi * abs(tab.J_wall) / st.encoder_resolution_m
    tau = get_motor(rep["motor"]["key"]).torque_peak_mNm * 1e-3
    spec = wall.WallSpec(st.Te_s, counts, st.Fv_N_s_per_m, st.Fs_N, tau, st.xdot_max_m_per_s)
    return d, folder, tab, spec


def _kmax_reduced(tab, spec, B=0.0, substep_s=None):
    f = wall.reduced_stable_of(tab, spec, B, substep_s or wall.SUBSTEP_MAX_S)
    return wall.k_max(f, n_probe=wall.N_PROBE)["K_max_N_per_m"]


def _eq25(spec, tab, Te=None, counts=None):
    delta = tab.delta_m(counts or spec.counts_per_rev)
    return stiffness_range_N_per_m(StiffnessInputs(spec.Fv_N_s_per_m, spec.Fs_N, Te or spec.Te_s,
                                                   delta, spec.v0_m_per_s))[1]


def run(quick: bool, out_dir: Path) -> dict:
    """The wall bench: Z-width, K_max against Te and encoder counts, speed against accuracy.

    Returns the result dict (SI units named in the keys) with ``charts``: the files written
    to ``out_dir``.
    """
    d, folder, tab, spec = _device()
    res: dict = {"design": d.name, "Te_s": spec.Te_s, "encoder_counts_per_rev": spec.counts_per_rev,
                 "encoder_resolution_m": tab.delta_m(spec.counts_per_rev),
                 "eq25_K_max_N_per_m": _eq25(spec, tab), "criterion_counts": wall.AMPLITUDE_COUNTS}

    # 1 Z-width: K_max(B)
    Bs = [0.0, 0.2, 5.0] if quick else [-0.1, -0.05, 0.0, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 20.0, 50.0]
    kB = [_kmax_reduced(tab, spec, B) for B in Bs]
    res["zwidth"] = {"B_N_s_per_m": Bs, "K_max_N_per_m": kB,
                     "passivity_K_max_N_per_m": [wall.passivity_K_max(spec.Fv_N_s_per_m, B, spec.Te_s) for B in Bs]}
    res["charts"] = plot_zwidth(res, spec.Fv_N_s_per_m, out_dir)
    res["charts"] += _sampling_and_encoder(res, tab, spec, quick, out_dir)
    res["charts"] += _speed_accuracy(res, d, folder, tab, spec, quick, out_dir)
    return res


def _sampling_and_encoder(res: dict, tab, spec, quick: bool, out_dir: Path) -> list[str]:
    """K_max against Te and encoder counts (B = 0) into res["sampling"] / res["encoder"];
    the chart files written."""
    from dataclasses import replace

    from matplotlib.figure import Figure

    Tes = [2e-4, 3.3e-4, 1e-3] if quick else [1e-4, 2e-4, 3.3e-4, 5e-4, 1e-3, 2e-3]
    cnts = [1000, spec.counts_per_rev, 20000] if quick else [500, 1000, 2000, spec.counts_per_rev, 10000, 40000, 100000]
    kT = [_kmax_reduced(tab, replace(spec, Te_s=T)) for T in Tes]
    kC = [_kmax_reduced(tab, replace(spec, counts_per_rev=c)) for c in cnts]
    res["sampling"] = {"Te_s": Tes, "K_max_N_per_m": kT, "eq25_K_max_N_per_m": [_eq25(spec, tab, Te=T) for T in Tes]}
    res["encoder"] = {"counts_per_rev": cnts, "K_max_N_per_m": kC,
                      "eq25_K_max_N_per_m": [_eq25(spec, tab, counts=c) for c in cnts]}
    fig = Figure(figsize=(10, 4))
    a1, a2 = fig.subplots(1, 2)
    a1.loglog(np.array(Tes) * 1e3, kT, "o-", label="simulation K_max (reduced)")
    a1.loglog(np.array(Tes) * 1e3, res["sampling"]["eq25_K_max_N_per_m"], "s:", color="tab:red", label="eq (25)")
    a1.loglog(np.array(Tes) * 1e3, [wall.passivity_K_max(spec.Fv_N_s_per_m, 0, T) for T in Tes], "k--", label="passivity")
    a1.set_xlabel("sampling period Te (ms)")
    a2.loglog(cnts, kC, "o-", label="simulation K_max (reduced)")
    a2.loglog(cnts, res["encoder"]["eq25_K_max_N_per_m"], "s:", color="tab:red", label="eq (25)")
    a2.axvline(spec.counts_per_rev, color="gray", lw=0.8, label="paper's Delta = 5.46e-5 m")
    a2.set_xlabel("encoder counts per crank turn")
    for ax in (a1, a2):
        ax.set_ylabel("K_max (N/m)")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Hoeken: largest stable wall against sampling period and encoder resolution (B = 0)")
    fig.tight_layout()
    return save_chart(fig, out_dir, "wall_kmax_sampling_encoder")


def _mujoco_kmax(d, folder: Path, tab, spec, step: float) -> dict:
    """K_max (B = 0) of the mujoco model at time step ``step`` (s), with its wall time."""
    saved = wall.MJ_STEP_MAX_S
    wall.MJ_STEP_MAX_S = step
    try:
        t0 = time.perf_counter()
        plant = wall.MujocoWall(folder / f"{d.name}.xml", tab, spec)
        k = wall.k_max(wall.mujoco_stable_of(plant, 0.0))["K_max_N_per_m"]
        return {"step_s": plant.m.opt.timestep, "K_max_N_per_m": k, "wall_s": time.perf_counter() - t0}
    finally:
        wall.MJ_STEP_MAX_S = saved


def _speed_accuracy(res: dict, d, folder: Path, tab, spec, quick: bool, out_dir: Path) -> list[str]:
    """Speed against accuracy: reduced (plant sub-steps) and mujoco (time steps) against the
    mujoco model at its finest step, into res["speed_accuracy"]; the chart files written."""
    from matplotlib.figure import Figure


    mj_rows = [_mujoco_kmax(d, folder, tab, spec, s) for s in ([1e-4, 2e-5] if quick else [1e-4, 4e-5, 2e-5])]
    ref = mj_rows[-1]["K_max_N_per_m"]
    rows = []
    for sub in ([5e-5, 2e-5] if quick else [3.3e-4, 1e-4, 5e-5, 2e-5, 1e-5]):
        t0 = time.perf_counter()
        k = _kmax_reduced(tab, spec, 0.0, sub)
        rows.append({"substep_s": sub, "K_max_N_per_m": k, "wall_s": time.perf_counter() - t0,
                     "rel_error": abs(k - ref) / ref})
    for r in mj_rows:
        r["rel_error"] = abs(r["K_max_N_per_m"] - ref) / ref
    res["speed_accuracy"] = {"reference": "mujoco model at its finest step", "mujoco": mj_rows, "reduced": rows}
    fig = Figure(figsize=(6.5, 4.5))
    ax = fig.subplots()
    for lab, rr, key, mk in (("reduced (1-DOF, M11(x)): plant sub-step", rows, "substep_s", "o-"),
                             ("mujoco (exported MJCF): time step", mj_rows[:-1], "step_s", "s-")):
        ax.loglog([r["wall_s"] for r in rr], [max(r["rel_error"], 1e-3) for r in rr], mk, label=lab)
        for r in rr:
            ax.annotate(f"{r[key] * 1e6:.0f} us", (r["wall_s"], max(r["rel_error"], 1e-3)), fontsize=7)
    ax.axvline(mj_rows[-1]["wall_s"], color="k", ls="--",
               label=f"reference: mujoco at {mj_rows[-1]['step_s'] * 1e6:.0f} us, K_max {ref:.0f} N/m")
    ax.set_xlabel("wall time of one K_max (s)")
    ax.set_ylabel("|K_max - K_max(ref)| / K_max(ref)  (1e-3 = below)")
    ax.set_title("Speed against accuracy of the wall models (Hoeken, paper Te and Delta)")
    ax.legend(fontsize=7)
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    return save_chart(fig, out_dir, "wall_error_vs_time")


def plot_zwidth(res: dict, Fv: float, out_dir: Path) -> list[str]:
    """The K-B chart from the bench result (B on a categorical axis: it spans signs and decades)."""
    from matplotlib.figure import Figure

    z = res["zwidth"]
    Bs = z["B_N_s_per_m"]
    pos = np.arange(len(Bs))
    kk = np.array([np.nan if k is None else k for k in z["K_max_N_per_m"]])
    fig = Figure(figsize=(7, 4.5))
    ax = fig.subplots()
    ax.fill_between(pos, 100.0, kk, color="tab:green", alpha=0.25, label="stable (simulation, reduced model)")
    ax.plot(pos, kk, "o-", color="tab:green")
    kp = np.array([wall.passivity_K_max(Fv, b, res["Te_s"]) for b in Bs])
    ax.plot(pos[kp > 0], kp[kp > 0], "k--", marker="x",
            label="passivity: Fv > K Te/2 + |B| (Colgate-Schenkel); none for |B| >= Fv")
    ax.axhline(res["eq25_K_max_N_per_m"], color="tab:red", ls=":", label="eq (25) K_max (Diolaiti)")
    ax.axhline(15000, color="tab:blue", ls="-.", lw=0.8, label="measured on the prototype (15000 N/m)")
    ax.set_xticks(pos, [f"{b:g}" for b in Bs])
    ax.set_yscale("log")
    ax.set_ylim(100, 2e5)
    ax.set_xlabel("virtual damping B (N s/m)")
    ax.set_ylabel("wall stiffness K (N/m)")
    ax.set_title(f"Z-width, Hoeken (Te {res['Te_s'] * 1e3:.2f} ms, Delta {res['encoder_resolution_m'] * 1e6:.1f} um)")
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    return save_chart(fig, out_dir, "wall_zwidth")
