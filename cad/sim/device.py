"""``hapticad wall``: the device from its solids (the simulator build) and the Z-width report.

The device model of both wall models is the design's simulator build
(``hapticad build DESIGN --formats mjcf`` at preview fidelity, whose mass properties equal
the inertia fidelity's): ``report.json`` gives H11..H33 for the reduced model and the MJCF the
mujoco model. It is built into ``<cache>/sim/<name>/`` (``$HAPTICAD_CACHE_DIR`` or
``~/.cache/hapticad``; a temporary folder when the cache is off) and reused while the design
and the code are unchanged (the build cache), or read from ``build_dir``. A damaged saved
model (a file that no longer matches its ``manifest.json``) is a miss: removed and rebuilt;
a cache that cannot be written (full disk) gives a private temporary folder instead.
"""

from __future__ import annotations

import math
import os
import tempfile
import time
from pathlib import Path

from cad.device import resolve_device
from cad.errors import DesignError, HapticadError


def _cache_root() -> Path | None:
    from cad.parts.shape_cache import cache_dir

    d = cache_dir()
    return None if d is None else d.parent / "sim"


#: The numbers ``wall`` reads from a build's ``report.json`` (:func:`read_device_report`).
REPORT_NUMBERS = ("l1_mm", "l2_mm", "l3_mm", "le_mm", "H11_kg_m2", "H12_kg_m2", "H22_kg_m2",
                  "H33_kg_m2", "beta2_deg")


def read_device_report(folder: Path, field: str) -> dict:
    """``folder/report.json`` through :func:`cad.io.guard.load_json`, with every value ``wall``
    uses checked: ``name`` and ``motor.key`` strings, :data:`REPORT_NUMBERS` finite numbers.
    Anything else is :class:`cad.errors.FileRefused` (field ``field``) naming the file and the
    first missing or wrong key, never a KeyError/TypeError traceback (issue 22 §2)."""
    from cad.errors import FileRefused
    from cad.io import guard

    path = Path(folder) / "report.json"
    rep = guard.load_json(path, "report", field)
    fix = "; rebuild it: hapticad build DESIGN --formats mjcf --out DIR"

    def bad(key: str, want: str, got) -> FileRefused:
        seen = "it is missing" if got is None else f"got {got!r}"
        return FileRefused(field, path, f"is not a hapticad build report: {key} must be {want}, "
                           f"{seen}{fix}")

    if not isinstance(rep, dict):
        raise FileRefused(field, path, f"is not a hapticad build report (not a JSON object){fix}")
    motor = rep.get("motor")
    for key, val in (("name", rep.get("name")), ("motor.key", motor.get("key") if isinstance(motor, dict) else None)):
        if not isinstance(val, str):
            raise bad(key, "a string", val)
    for key in REPORT_NUMBERS:
        val = rep.get(key)
        if isinstance(val, bool) or not isinstance(val, (int, float)) or not math.isfinite(val):
            raise bad(key, "a finite number", val)
    return rep


def device_build(design, build_dir: Path | None = None) -> Path:
    """Folder holding ``report.json`` and ``<name>.xml`` of the design (module docstring)."""
    if build_dir is not None:
        build_dir = Path(build_dir)
        rep_path = build_dir / "report.json"
        if not (os.path.lexists(rep_path) and os.path.lexists(build_dir / f"{design.name}.xml")):
            raise DesignError("--build-dir", f"{build_dir} holds no report.json and {design.name}.xml "
                              "(run hapticad build DESIGN --formats mjcf --out DIR first)")
        from cad.io import guard

        rep = read_device_report(build_dir, "--build-dir")
        guard.check_file(build_dir / f"{design.name}.xml", "mjcf", "--build-dir")
        want = design.resolved_linkage()
        if rep.get("name") != design.name or any(
            abs(rep.get(k, math.inf) - want[k]) > 1e-9 for k in ("l1_mm", "l2_mm", "l3_mm", "le_mm")
        ):
            raise DesignError("--build-dir", f"{build_dir} is a build of another design than {design.name!r}")
        return build_dir
    from cad.io import cache_faults

    root = _cache_root()
    if root is not None and cache_faults.writable():
        out = root / design.name
        _drop_if_damaged(out)
        try:
            _build_sim(design, out)
            return out
        except HapticadError:
            raise
        except Exception as exc:  # noqa: BLE001 - full disk (OSError, OCCT's RuntimeError):
            cache_faults.write_failed("the simulator model", exc)  # built in a private folder
    out = Path(tempfile.mkdtemp(prefix="hapticad-wall-"))
    _build_sim(design, out)
    return out


def _build_sim(design, out: Path) -> None:
    from cad.pipeline import build_design

    build_design(design, out, {"mjcf", "stl"}, fidelity="preview", allow_interference=True,
                 simulate_wall=False)  # the wall command simulates itself


def _drop_if_damaged(entry: Path) -> None:
    """Remove the cache entry ``sim/<name>/`` when its files no longer match its
    ``manifest.json`` (a damaged model is a miss: rebuilt, said once). The whole folder is a
    cache entry hapticad made (:mod:`cad.io.cache_limit` removes it whole too)."""
    import shutil

    from cad.design import bounds
    from cad.export.manifest import verify_manifest

    if not os.path.lexists(entry) or (entry.is_dir() and not entry.is_symlink()
                                      and verify_manifest(entry) is not None):
        return
    if entry.is_dir() and not entry.is_symlink():
        shutil.rmtree(entry, ignore_errors=True)
    else:
        entry.unlink()
    bounds.warn(f"cache: the saved simulator model {entry} was damaged (its files do not match "
                "its manifest.json); rebuilt")


def wall_inputs(design) -> tuple[dict, str]:
    """(Fv, Fs, Te, Delta, xdot, counts) of the wall and where they come from: the design's
    ``[stiffness]`` table, else its encoder (``parts.encoder`` / ``encoder_counts_per_rev``)
    and the datasheet's Coulomb friction estimate at no load (:mod:`cad.families.fourbar.datasheet`)."""
    from cad.families.fourbar.datasheet import friction, lever, stiffness_inputs

    _, Jx, pose, a2, a3 = lever(design)
    if design.stiffness is not None:
        return stiffness_inputs(design, Jx, None)
    m = resolve_device(design).joint_motor("crank")  # through a capstan: n K_t I_0
    Fm, _ = friction(design, m, Jx, pose, a2, a3)
    if Fm is None:
        raise DesignError("stiffness", f"no [stiffness] table and no friction data for {m.key} (torque constant "
                          "and no-load current): add [stiffness] or those [motor] keys")
    return stiffness_inputs(design, Jx, float(Fm.max()))


def wall_report(design, *, K: float | None = None, B: float = 0.0, Te_s: float | None = None,
                counts_per_rev: float | None = None, model: str = "reduced",
                build_dir: Path | None = None) -> dict:
    """Everything ``hapticad wall --json`` prints (docs/simulation.md "Virtual wall")."""
    from cad.dynamics.inertia import InertiaCoefficients
    from cad.families.fourbar.datasheet import eq25_K_max
    from cad.sim import wall

    t0 = time.perf_counter()
    s, src = wall_inputs(design)
    folder = device_build(design, build_dir)
    rep = read_device_report(folder, "--build-dir" if build_dir is not None else "wall")
    H = InertiaCoefficients(rep["H11_kg_m2"], rep["H12_kg_m2"], rep["H22_kg_m2"], rep["H33_kg_m2"],
                            math.radians(rep["beta2_deg"]))
    from cad.families.fourbar.sim import motor_torque_Nm

    tau = motor_torque_Nm(resolve_device(design).joint_motor("crank"))  # n tau_peak at the crank
    tab = wall.device_tables(design, H)
    Te = s["Te"] if Te_s is None else Te_s
    counts = s["counts"] if counts_per_rev is None else counts_per_rev
    spec = wall.WallSpec(Te, counts, s["Fv"], s["Fs"], tau, s["xdot"])
    delta = tab.delta_m(counts)
    if model == "reduced":
        stable_of, n_probe = wall.reduced_stable_of(tab, spec, B), wall.N_PROBE
        km = wall.k_max_estimate(stable_of)
    else:
        plant = wall.MujocoWall(folder / f"{design.name}.xml", tab, spec)
        stable_of, n_probe = wall.mujoco_stable_of(plant, B), 1
        km = wall.k_max(stable_of, n_probe=n_probe)
    out = {
        "design": design.name, "model": model, "B_N_s_per_m": B, "Te_s": Te,
        "encoder_counts_per_rev": counts, "encoder_resolution_m": delta,
        "Fv_N_s_per_m": s["Fv"], "Fs_N": s["Fs"], "tau_max_Nm": tau, "inputs": src,
        "hand_force_N": spec.hand_N, "v0_m_per_s": spec.v0_m_per_s,
        "M11_wall_g": float(tab.at(tab.a, tab.phi_wall) / tab.J_wall**2 * 1e3),
        "K_max_stable_N_per_m": km["K_max_N_per_m"],
        "K_first_unstable_N_per_m": km["K_unstable_N_per_m"],
        "eq25_K_max_N_per_m": eq25_K_max({**s, "Te": Te, "delta": delta}),
        "passivity_K_max_N_per_m": wall.passivity_K_max(s["Fv"], B, Te),
        "criterion": (f"stable: peak-to-peak of the handle's path coordinate over the last "
                      f"{wall.WINDOW_S:g} s of {wall.T_SIM_S:g} s below {wall.AMPLITUDE_COUNTS:g} "
                      f"encoder steps, after hitting the wall at v0 with a {spec.hand_N:g} N push"),
        "bisection": {"K_lo_N_per_m": wall.K_LO_N_PER_M, "K_hi_N_per_m": wall.K_HI_N_PER_M,
                      "rtol": wall.K_RTOL, "probes_per_round": n_probe,
                      "simulations": km["simulations"]},
        "K_max_sampling_error_rel": km.get("sampling_error_rel"),
        "K_band_N_per_m": [km.get("K_first_unstable_N_per_m"), km.get("K_last_stable_N_per_m")],
        "K_max_method": ("threshold with the fewest exceptions over a fine K grid around a bisection "
                         f"(step {wall.K_GRID_STEP:g}; {km.get('probes')} probes, {km.get('exceptions')} "
                         "exceptions; stability is intermittent near K_max)") if model == "reduced"
                        else f"bisection in log K to {wall.K_RTOL:g}",
    }
    if K is not None:
        if model == "reduced":
            t, xs, *_ = wall.simulate_reduced(tab, spec, K, B)
            amp = float(wall.amplitude_m(t, xs)[0])
        else:
            t, x, _ = plant.run(K, B)
            amp = float(wall.amplitude_m(t, x[:, None])[0])
        out["K_N_per_m"] = K
        out["stable"] = bool(amp < wall.AMPLITUDE_COUNTS * delta)
        out["amplitude_counts"] = amp / delta
    out["wall_s"] = time.perf_counter() - t0
    return out
