"""Generated firmware of a built device (issue 26): ``hapticad build DESIGN --formats firmware``.

Pure generation code (numpy; no CAD import). :func:`write_firmware` writes into
``<out>/firmware/``:

* ``hapticad_device.h`` / ``hapticad_device.c`` -- C99, no dynamic allocation, ``double`` or
  ``float`` (``-DHAPTICAD_USE_FLOAT``): encoder counts -> joint angles, forward kinematics
  (four-bar: loop closure on the design's branch, refusing angles outside the crank range;
  pantographs: the 5-bar closed form in the design's working modes), the Jacobian,
  tau = J^T F, force -> motor current with saturation at the continuous / peak limit, gravity
  torques (vertical devices, ``[firmware] plane``), the four-bar's apparent mass;
  (:mod:`cad.firmware.csrc`);
* ``test_vectors.json`` (>= 1000 poses from the numpy model, :mod:`cad.firmware.vectors`)
  and ``test_device.c`` that checks the C code against it;
* ``wall_example/wall_example.ino`` and ``chai3d_device.json`` (:mod:`cad.firmware.extras`);
* four-bars and the 5-bar pantograph: ``identify/`` -- the identification routine, its CSV
  log writer and an example sketch (:mod:`cad.firmware.identify_c`, one motor;
  :mod:`cad.firmware.identify2_c`, two motors; issue 37).

The family's firmware hook chooses the generator (:func:`firmware_files`): the linkages use
:func:`linkage_files`, the PowerMouse its current-to-wrench map
(:mod:`cad.families.powermouse.firmware`).

Every file names the design, its hash and the hapticad version, and states units (SI) and
frames. Inputs: the design, the build's report (mass properties from the solids, the motor
key) and the resolved device (:mod:`cad.device`: motor constants, rotor inertia, encoder).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

FOLDER = "firmware"
FILES = ("hapticad_device.h", "hapticad_device.c", "test_vectors.json", "test_device.c",
         "wall_example/wall_example.ino", "chai3d_device.json")


def firmware_files(design, report: dict, design_hash: str, device=None) -> dict[str, str]:
    """``{relative path: text}`` of every generated file (paths under ``firmware/``) of
    ``design`` built into ``report``: its family's firmware hook
    (:attr:`cad.families.protocol.FamilyPackage.firmware`). Raises DesignError naming
    ``--formats`` for a family without firmware."""
    from cad.errors import DesignError
    from cad.families import family_package

    hook = family_package(design.family).firmware
    if hook is None:
        raise DesignError("--formats", f"firmware is not written for {design.family!r} designs")
    return hook(design, report, design_hash, device)


def linkage_model(design):
    """The :class:`cad.firmware.model.KinematicModel` the design's family gives
    (:attr:`cad.families.protocol.FamilyPackage.firmware_model`). Raises DesignError naming
    ``--formats`` for a family without one."""
    from cad.errors import DesignError
    from cad.families import family_package

    hook = family_package(design.family).firmware_model
    if hook is None:
        raise DesignError("--formats", f"firmware is not written for {design.family!r} designs")
    return hook(design)


def _datasheet_row(report: dict, key: str) -> dict | None:
    """The row ``key`` of the report's datasheet, or None."""
    return next((r for r in (report.get("datasheet") or {}).get("rows", []) if r.get("key") == key), None)


def _datasheet_forces(report: dict) -> dict | None:
    """The datasheet's continuous and peak force in every direction (worst over the stroke or
    the workspace: the one figure the CHAI3D file states), or None without both rows."""
    rows = [_datasheet_row(report, k) for k in ("continuous_force_N", "peak_force_N")]
    if any(r is None or r.get("value") is None for r in rows):
        return None
    return {"continuous_N": float(rows[0]["value"]), "peak_N": float(rows[1]["value"]),
            "source": "the datasheet's continuous_force_N / peak_force_N (worst over the stroke or "
                      "the workspace, every direction)"}


def _datasheet_step_m(report: dict) -> float | None:
    """The datasheet's ``resolution_um`` (worst over the workspace) in m, or None."""
    r = _datasheet_row(report, "resolution_um")
    return float(r["value"]) * 1e-6 if r is not None and r.get("value") is not None else None


def linkage_files(design, report: dict, design_hash: str, device=None) -> dict[str, str]:
    """The firmware of a linkage (joint encoders, motors on joints) through its family's
    kinematic model (:func:`linkage_model`): ``{relative path: text}`` under ``firmware/``
    (module docstring); the motor and encoder facts are ``device``'s
    (:class:`cad.device.ResolvedDevice`, resolved from ``design`` when None)."""
    import cad
    from cad.firmware import csrc, extras, reference, vectors
    from cad.firmware.device import device_spec

    spec = device_spec(design, report, design_hash, cad.__version__, device,
                       linkage_model(design))
    rows, summary = vectors.rows(spec, design)
    q_ok = np.array([r[1 + 2 * spec.n_joints: 1 + 3 * spec.n_joints] for r in rows if r[0] == 0])
    wall = extras.wall_numbers(spec, design, _datasheet_step_m(report), _datasheet_row(report, "eq25_K_max_N_per_m"))
    forces = _datasheet_forces(report) or extras.max_forces_N(spec, q_ok)
    layout = ["status", f"counts[{spec.n_joints}]", f"q_from_counts_rad[{spec.n_joints}]",
              f"q_rad[{spec.n_joints}]", f"F[{spec.n_task}]", f"X[{spec.n_task}]",
              f"J[{spec.n_task}x{spec.n_joints}] row-major", f"tau_Nm[{spec.n_joints}]",
              f"tau_gravity_Nm[{spec.n_joints}]", "apparent_mass_kg",
              f"M[{spec.n_task}x{spec.n_task}] row-major (kg; twin theta: kg m, kg m^2)"]
    doc = {
        "generator": f"hapticad {spec.version}", "design": spec.name, "family": spec.family,
        "design_hash": spec.design_hash, "units": "SI (m, rad, N, N m, kg)",
        "frame": csrc.banner(spec, "").split("Frame: ", 1)[1].split(".\n", 1)[0],
        "status_codes": reference.STATUS, "layout": layout, "summary": summary,
        "encoder": {"counts_per_rev": spec.encoder_counts_per_rev,
                    "direction": list(spec.encoder_direction),
                    "zero_rad": list(spec.encoder_zero_rad)},
        "gravity_m_s2": spec.gravity_m_s2, "wall": wall,
    }
    text = json.dumps(doc, indent=1, sort_keys=True)
    text = text[:-2] + ',\n "rows": [\n' + ",\n".join(
        "  [" + ", ".join(repr(v) for v in r) + "]" for r in rows) + "\n ]\n}\n"
    p = f"{FOLDER}/"
    ident = {} if spec.model.identify is None else {
        p + k: v for k, v in spec.model.identify(design, report, spec).items()}
    return ident | {
        p + "hapticad_device.h": csrc.header(spec), p + "hapticad_device.c": csrc.source(spec),
        p + "test_vectors.json": text,
        p + "test_device.c": csrc.banner(spec, "test_device.c") + vectors.TEST_PROGRAM,
        p + "wall_example/wall_example.ino": extras.sketch(spec, wall),
        p + "chai3d_device.json": extras.chai3d_json(spec, design, wall, forces, extras.rope_row(report)),
    }


def write_firmware(design, report: dict, out_dir: Path, design_hash: str, device=None) -> list[str]:
    """Write :func:`firmware_files` into ``out_dir`` atomically; return the relative paths."""
    return write_files(out_dir, firmware_files(design, report, design_hash, device))


def write_files(out_dir: Path, files: dict[str, str]) -> list[str]:
    """Write ``{relative path: text}`` into ``out_dir`` atomically; the sorted paths."""
    from cad.io.atomic import write_text_atomic

    for rel, text in files.items():
        write_text_atomic(Path(out_dir) / rel, text)
    return sorted(files)
