"""Read a build's written files back and compare what they say with the resolved device
(issue 32 item 2: "a build that finds its own outputs disagreeing fails loudly rather than
publishing").

Each reader parses the file as a user's tool would (``csv`` for ``bom.csv`` / ``order.csv``,
a regex over the C header's ``#define`` lines, ``json`` for ``chai3d_device.json``,
``test_vectors.json`` and ``report.json``, ``xml.etree`` for the MJCF), never the objects the
writers held. :func:`output_facts` returns what the files state; :func:`check_outputs` raises
:class:`OutputsDisagree` naming the file, the fact and both values at the first mismatch.

Pure Python (csv, json, re, xml): no CAD import.
"""

from __future__ import annotations

import csv
import json
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

from cad.actuators.capstan import series_stiffness
from cad.errors import HapticadError
from cad.firmware.extras import rope_row
from cad.io.escape import csv_cell
from cad.tolerances import OUTPUT_AGREE_REL

#: The encoder's counts per turn in a BOM description ("... 3837 counts/rev ...").
COUNTS_RE = re.compile(r"(\d+) counts/rev")
#: The datasheet resolution row's count ("(2 pi / 3837 counts)", "2 pi / 4000 counts per joint").
RESOLUTION_COUNTS_RE = re.compile(r"2 pi / (\d+) counts")
# The MJCF motor force range of every motor is its peak torque through its transmission
# (rotary motors; the pantograph families' ``[actuators]`` stays the GII's normalisation, eq 3).


class OutputsDisagree(HapticadError):
    """A written file states another value of a device fact than the resolved device (exit 2)."""


def _define(text: str, name: str) -> str | None:
    m = re.search(rf"^#define {name} (.+)$", text, re.M)
    return None if m is None else m.group(1).strip()


def header_facts(text: str) -> dict:
    """``HC_ENCODER_DEFAULT`` counts, ``HC_KT_NM_PER_A``, ``HC_CURRENT_CONTINUOUS_A``,
    ``HC_CURRENT_PEAK_A`` of a generated ``hapticad_device.h`` (SI), None when absent; and
    ``<key>_joints``: the lists of ``HC_*_JOINTS`` (a device whose motors differ), or None."""
    out: dict = {}
    enc = _define(text, "HC_ENCODER_DEFAULT")
    m = re.match(r"\{\s*(\d+)L", enc or "")
    out["encoder_counts_per_rev"] = int(m.group(1)) if m else None
    for key, name in (("kt_Nm_per_A", "HC_KT_NM_PER_A"), ("current_continuous_A", "HC_CURRENT_CONTINUOUS_A"),
                      ("current_peak_A", "HC_CURRENT_PEAK_A")):
        v = re.match(r"HC_R\(([^)]+)\)", _define(text, name) or "")
        out[key] = float(v.group(1)) if v else None
        arr = _define(text, name + "_JOINTS")  # motors that differ: one value per joint
        out[key + "_joints"] = (None if arr is None else
                                [float(x) for x in re.findall(r"HC_R\(([^)]+)\)", arr)])
    return out


def bom_encoders(path: Path) -> list[tuple[int | None, int]]:
    """(counts per turn or None, quantity) of every ``encoder`` line of ``bom.csv`` (column
    ``part``) or ``order.csv`` (column ``parts``, its designation states the counts)."""
    with path.open(newline="", encoding="utf-8") as f:
        rows = [r for r in csv.DictReader(f)
                if r.get("part") == "encoder" or "encoder" in (r.get("parts") or "").split()]
    out = []
    for r in rows:
        m = COUNTS_RE.search(r.get("description") or r.get("designation") or "")
        out.append((int(m.group(1)) if m else None, int(float(r.get("quantity") or 0))))
    return out


def mjcf_motors(path: Path) -> dict[str, dict]:
    """``{joint: {"armature": kg m^2, "forcerange": N m}}`` of every motor of an MJCF file; the
    force range at the joint: the motor's ``forcerange`` times its ``gear`` (a capstan's n)."""
    root = ET.parse(path).getroot()
    arm = {j.get("name"): float(j.get("armature", 0.0)) for j in root.iter("joint")}
    out = {}
    for m in root.iter("motor"):
        j = m.get("joint")
        if j is None:  # a force actuator at a site (the PowerMouse's coils): no joint, no armature
            continue
        hi = float((m.get("forcerange") or "0 0").split()[-1])
        gear = float((m.get("gear") or "1").split()[0])
        out[j] = {"armature": arm.get(j), "forcerange": hi * gear}
    return out


def _datasheet_counts(report: dict) -> int | None:
    for r in (report.get("datasheet") or {}).get("rows", []):
        if r.get("key") == "resolution_um":
            m = RESOLUTION_COUNTS_RE.search(r.get("model") or "")
            return int(m.group(1)) if m else None
    return None


def _mjcf_files(out: Path) -> list[Path]:
    return [p for p in sorted(out.rglob("*.xml")) if p.read_text(encoding="utf-8")[:400].find("<mujoco") >= 0]


def _encoder_facts(out: Path, facts: list) -> None:
    for name in ("bom.csv", "order.csv"):
        if (out / name).is_file():
            lines = bom_encoders(out / name)
            facts += [(name, "encoder counts/rev", counts, "encoder") for counts, _ in lines]
            total = sum(q for _, q in lines)
            facts.append((name, "encoders ordered", total, "n_encoders"))
    fw = out / "firmware"
    if (fw / "hapticad_device.h").is_file():
        h = header_facts((fw / "hapticad_device.h").read_text(encoding="utf-8"))
        facts.append(("firmware/hapticad_device.h", "HC_ENCODER_DEFAULT counts/rev", h["encoder_counts_per_rev"],
                      "encoder"))
        for k, name in (("kt_Nm_per_A", "HC_KT_NM_PER_A"), ("current_continuous_A", "HC_CURRENT_CONTINUOUS_A"),
                        ("current_peak_A", "HC_CURRENT_PEAK_A")):
            if h[k + "_joints"] is None:
                facts.append(("firmware/hapticad_device.h", name, h[k], k))
                continue
            facts.append(("firmware/hapticad_device.h", f"{name}_JOINTS entries", len(h[k + "_joints"]),
                          "n_motors"))
            facts += [("firmware/hapticad_device.h", f"{name}_JOINTS[{i}]", v, f"{k}:{i}")
                      for i, v in enumerate(h[k + "_joints"])]
    for rel, keys in (("chai3d_device.json", ("encoder_counts_per_rev",)),
                      ("test_vectors.json", ("encoder", "counts_per_rev"))):
        if (fw / rel).is_file():
            doc = json.loads((fw / rel).read_text(encoding="utf-8"))
            for k in keys:
                doc = doc.get(k) if isinstance(doc, dict) else None
            facts.append((f"firmware/{rel}", "encoder counts/rev", doc, "encoder"))


def output_facts(out: Path) -> list[tuple[str, str, object, str]]:
    """Every device fact the files in ``out`` state: ``(file, fact, value, device key)``;
    device key one of ``encoder``, ``n_encoders``, ``kt_Nm_per_A``, ``current_continuous_A``,
    ``current_peak_A``, ``motor_key``, ``rotor_inertia_g_cm2``, ``armature:<joint>``,
    ``forcerange:<joint>``."""
    out = Path(out)
    facts: list = []
    _encoder_facts(out, facts)
    if (out / "report.json").is_file():
        rep = json.loads((out / "report.json").read_text(encoding="utf-8"))
        if "datasheet" in rep:
            facts.append(("report.json", "datasheet resolution_um counts/rev", _datasheet_counts(rep), "encoder"))
        mot = rep.get("motor")
        if isinstance(mot, dict):
            facts.append(("report.json", "motor.key", mot.get("key"), "motor_key"))
            if "rotor_inertia_g_cm2" in mot:
                facts.append(("report.json", "motor.rotor_inertia_g_cm2", mot["rotor_inertia_g_cm2"],
                              "rotor_inertia_g_cm2"))
    for p in _mjcf_files(out):
        rel = p.relative_to(out).as_posix()
        for joint, v in mjcf_motors(p).items():
            facts.append((rel, f"armature of joint {joint}", v["armature"], f"armature:{joint}"))
            facts.append((rel, f"forcerange of motor on {joint}", v["forcerange"], f"forcerange:{joint}"))
    return facts


def device_values(device) -> dict:
    """The resolved device's value of every key of :func:`output_facts`."""
    vals: dict = {}
    if device.encoders:
        vals["encoder"] = device.encoder.counts_per_rev
        vals["n_encoders"] = len(device.encoders)
    if device.motors:
        m = device.motor
        vals.update(kt_Nm_per_A=m.kt_Nm_per_A, current_continuous_A=m.spec.current_continuous_A,
                    current_peak_A=m.current_peak_A, motor_key=m.catalog_key,
                    rotor_inertia_g_cm2=m.spec.rotor_inertia_g_cm2, n_motors=len(device.motors))
        for i, j in enumerate(device.motors):  # each joint's motor (a header with one per joint)
            vals.update({f"kt_Nm_per_A:{i}": j.kt_Nm_per_A, f"current_peak_A:{i}": j.current_peak_A,
                         f"current_continuous_A:{i}": j.spec.current_continuous_A})
        if len({(j.catalog_key, j.name, j.spec) for j in device.motors}) > 1:
            # motors that differ: one header value for every joint disagrees with some joint
            vals.update(kt_Nm_per_A="one per joint", current_continuous_A="one per joint",
                        current_peak_A="one per joint")
    for t, m in zip(device.transmissions, device.motors, strict=True):
        vals[f"armature:{m.joint}"] = device.joint_rotor_inertia_kg_m2(m.joint)  # n^2 (J_m + J_c)
        if m.spec.torque_peak_mNm is not None:
            vals[f"forcerange:{m.joint}"] = m.spec.torque_peak_mNm * 1e-3 * t.ratio
    return vals


def _same(a, b) -> bool:
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        return math.isclose(float(a), float(b), rel_tol=OUTPUT_AGREE_REL, abs_tol=0.0)
    return a == b


def disagreements(device, out: Path) -> list[str]:
    """One line per fact a file in ``out`` states differently from ``device`` (empty: agree)."""
    want = device_values(device)
    bad = []
    for file, fact, got, key in output_facts(out):
        if key not in want:
            continue
        if not _same(got, want[key]):
            bad.append(f"{file}: {fact} = {got!r}, the resolved device (report.json device) has {want[key]!r}")
    if "encoder" in want and (Path(out) / "bom.csv").is_file() and not bom_encoders(Path(out) / "bom.csv"):
        bad.append(f"bom.csv: no encoder line, the resolved device has {len(device.encoders)} encoder(s) of "
                   f"{want['encoder']} counts/rev")
    return bad


# ------------------------------------------------- files against each other (issue 32 item 2)
#: A printed part's process text in bom.csv ("FDM print PLA: ...", "printed"): its stock is
#: filament (docs/ordering.md); a wound coil's ("wound ..."): wire.
PRINTED_PROCESS_RE = re.compile(r"^(fdm )?print", re.I)
#: Start of a laser-cut part's stock (cad.export.order.NESTED_STOCK): no order line of its own.
NESTED_STOCK_PREFIX = "nested on "
SVG_NS = "{http://www.w3.org/2000/svg}"


def _csv_rows(path: Path) -> list[dict]:
    with path.open(newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def drawing_facts(path: Path) -> dict[str, str]:
    """``{"part": ..., "stock": ..., "process": ..., "quantity": ...}`` of one drawing sheet
    (``drawings/<part>.svg``): the title block's ``key: value`` texts (xml.etree), the first
    of each key, the backslash before a dollar sign (cad.io.escape.mathtext) undone."""
    out: dict[str, str] = {}
    for t in ET.parse(path).getroot().iter(SVG_NS + "text"):
        key, sep, value = "".join(t.itertext()).partition(": ")
        if sep and key in ("part", "stock", "process", "quantity") and key not in out:
            out[key] = value.replace(r"\$", "$")
    return out


def _drawing_stock(out: Path, bom: dict, bad: list) -> None:
    """Every sheet of every ``drawings/`` folder under ``out`` states the stock of its part in
    the ``bom.csv`` beside that folder."""
    for folder in sorted(p for p in out.rglob("drawings") if p.is_dir()):
        rows = bom if folder.parent == out else (
            {r["part"]: r for r in _csv_rows(folder.parent / "bom.csv")}
            if (folder.parent / "bom.csv").is_file() else None)
        if rows is None:
            continue
        for svg in sorted(folder.glob("*.svg")):
            d = drawing_facts(svg)
            rel = svg.relative_to(out).as_posix()
            row = rows.get(d.get("part", svg.stem))
            if row is None:
                bad.append(f"{rel}: part {d.get('part')!r} has no bom.csv line")
            elif d.get("stock") != row["stock"]:
                bad.append(f"{rel}: stock = {d.get('stock')!r}, bom.csv has {row['stock']!r}")


def _order_stock(out: Path, bom: dict, bad: list) -> None:
    """Every made part of ``bom.csv`` is ordered in ``order.csv`` as its stock (a nested
    laser-cut part: not at all, its sheet is), in the form its process asks for."""
    order: dict[str, list[dict]] = {}
    for r in _csv_rows(out / "order.csv"):
        for part in (r.get("parts") or "").split():
            order.setdefault(part, []).append(r)
    for name, row in bom.items():
        if row.get("made_or_bought") != "made":
            continue
        lines = [o for o in order.get(name, []) if o["group"].startswith("stock:")]
        stock = row["stock"]
        if stock.startswith(NESTED_STOCK_PREFIX):
            if lines:
                bad.append(f"order.csv: {name} is ordered as {lines[0]['designation']!r}, bom.csv "
                           f"says it is {stock!r}")
            continue
        got = [o["designation"] for o in lines]
        if got != [stock]:
            bad.append(f"order.csv: stock of {name} = {got!r}, bom.csv has {stock!r}")
        form = stock.split(" ", 1)[0]
        proc = row.get("process") or ""
        want = ("filament" if PRINTED_PROCESS_RE.search(proc) else
                "wire" if proc.lower().startswith("wound") else None)
        if (want or form) in ("filament", "wire") and form != want:
            bad.append(f"order.csv: {name} is ordered as {form} stock ({stock!r}), its bom.csv "
                       f"process is {proc!r}")


#: An ISO 286 fit at the end of a fit text ("spacer bore 8 H7", "journal 8 js5").
ISO_FIT_RE = re.compile(r" \d+(?:\.\d+)? [A-Za-z]{1,2}\d{1,2}$")


def _printed_fits(bom: dict, bad: list) -> None:
    """No printed part of ``bom.csv`` states an ISO 286 fit: a print holds its process's
    tolerance (cad.printing.printed_fit), not H7."""
    for name, row in bom.items():
        if row.get("made_or_bought") == "made" and PRINTED_PROCESS_RE.search(row.get("process") or ""):
            iso = [f for f in (row.get("fits") or "").split("; ") if ISO_FIT_RE.search(f)]
            if iso:
                bad.append(f"bom.csv: printed part {name} states the ISO 286 fit {iso[0]!r}: a print "
                           "holds its process tolerance, not an ISO class")


#: An instance of ``assembly.step``: its PRODUCT entity, named after the part instance.
STEP_PRODUCT_RE = re.compile(r"PRODUCT\('((?:[^']|'')*)'")


def step_instances(path: Path) -> list[str]:
    """The product names of a STEP file (regex over its ``PRODUCT('name', ...)`` entities;
    ``''`` unescaped): in ``assembly.step`` one per part instance, and the assembly itself."""
    return [m.replace("''", "'") for m in STEP_PRODUCT_RE.findall(path.read_text(encoding="utf-8",
                                                                                errors="replace"))]


def _bought_counts(out: Path, bom: dict, bad: list) -> None:
    """Every bought ``bom.csv`` line with solids orders as many as ``assembly.step`` holds
    (instances mapped to kinds by report.json ``placement``); ``order.csv`` orders, per
    designation, what those lines sum to (nothing bought twice, e.g. rings inside a pin)."""
    rep_path, step = out / "report.json", out / "assembly.step"
    if not (rep_path.is_file() and step.is_file()):
        return
    placed = ((json.loads(rep_path.read_text(encoding="utf-8")).get("placement") or {})
              .get("instances") or {})
    count: dict[str, int] = {}
    for name in step_instances(step):
        if name in placed:
            kind = placed[name].get("kind")
            count[kind] = count.get(kind, 0) + 1
    want: dict[str, int] = {}
    for name, row in bom.items():
        if row.get("made_or_bought") != "bought":
            continue
        q = int(float(row.get("quantity") or 0))
        if name in count and count[name] != q:
            bad.append(f"bom.csv: {name} quantity = {q}, assembly.step holds {count[name]} instance(s)")
        des = row.get("designation") or name
        want[des] = want.get(des, 0) + q
    if not (out / "order.csv").is_file():
        return
    got: dict[str, int] = {}
    for r in _csv_rows(out / "order.csv"):
        if r.get("group") != "total" and not r.get("group", "").startswith("stock:"):
            got[r["designation"]] = got.get(r["designation"], 0) + int(float(r.get("quantity") or 0))
    for des, q in got.items():
        if des in want and q != want[des]:
            bad.append(f"order.csv: {des} quantity = {q}, bom.csv lines sum to {want[des]}")


def file_disagreements(out: Path) -> list[str]:
    """One line per fact two written files in ``out`` state differently: the stock of each
    made part on its drawing, in ``bom.csv`` and in ``order.csv``; the process in ``bom.csv``
    against the stock form ordered (printed: filament, wound: wire) and against its fits (a
    printed part states no ISO 286 fit); the quantity of each bought part against its
    instances in ``assembly.step`` and against what ``order.csv`` orders; the wall stiffness of
    ``chai3d_device.json`` and the wall sketch against the datasheet's eq (25) K_max, and its
    largest force against the datasheet's continuous force."""
    out = Path(out)
    bad: list[str] = []
    if not (out / "bom.csv").is_file():
        return bad
    bom = {r["part"]: r for r in _csv_rows(out / "bom.csv")}
    _drawing_stock(out, bom, bad)
    _printed_fits(bom, bad)
    _bought_counts(out, bom, bad)
    if (out / "order.csv").is_file():
        _order_stock(out, bom, bad)
    _wall_stiffness(out, bad)
    _max_force(out, bad)
    return bad


def _max_force(out: Path, bad: list) -> None:
    """``chai3d_device.json``'s ``m_maxLinearForce`` is the datasheet's ``continuous_force_N``
    (the force in every direction, worst over the stroke or the workspace)."""
    chai_p, rep_p = out / "firmware" / "chai3d_device.json", out / "report.json"
    if not (chai_p.is_file() and rep_p.is_file()):
        return
    chai, rep = json.loads(chai_p.read_text()), json.loads(rep_p.read_text())
    force = next((r for r in rep.get("datasheet", {}).get("rows", []) if r["key"] == "continuous_force_N"), None)
    if force is not None and force.get("value") is not None and "m_maxLinearForce" in chai and not math.isclose(
            chai["m_maxLinearForce"], force["value"], rel_tol=OUTPUT_AGREE_REL):
        bad.append(f"chai3d_device.json m_maxLinearForce = {chai['m_maxLinearForce']:.6g} N, the "
                   f"datasheet's continuous_force_N {force['value']:.6g} N")


def _wall_stiffness(out: Path, bad: list) -> None:
    """The firmware's wall K (``WALL_K_N_PER_M`` of the sketch) is the datasheet's
    ``eq25_K_max_N_per_m`` unless the design sets ``[firmware] wall_stiffness_N_per_m``; the
    ``chai3d_device.json`` ``m_maxLinearStiffness`` is that eq (25) K_max, with a capstan in
    series with the datasheet's ropes' stiffness at the handle
    (:func:`cad.firmware.extras.chai3d_stiffness`)."""
    chai_p, rep_p = out / "firmware" / "chai3d_device.json", out / "report.json"
    if not (chai_p.is_file() and rep_p.is_file()):
        return
    chai, rep = json.loads(chai_p.read_text()), json.loads(rep_p.read_text())
    row = next((r for r in rep.get("datasheet", {}).get("rows", []) if r["key"] == "eq25_K_max_N_per_m"), None)
    if row is None or row.get("value") is None:
        return
    rope = rope_row(rep)
    want = row["value"] if rope is None else float(series_stiffness(row["value"], rope["value"]))
    what = "eq25_K_max_N_per_m" if rope is None else f"eq25_K_max_N_per_m in series with {rope['key']}"
    if not math.isclose(chai["m_maxLinearStiffness"], want, rel_tol=OUTPUT_AGREE_REL):
        bad.append(f"chai3d_device.json m_maxLinearStiffness = {chai['m_maxLinearStiffness']:.6g} N/m, the "
                   f"datasheet's {what} {want:.6g} N/m")
    ino = out / "firmware" / "wall_example" / "wall_example.ino"
    if ino.is_file() and "wall_stiffness_N_per_m" not in ino.read_text():
        k = float(_define(ino.read_text(), "WALL_K_N_PER_M"))
        if not math.isclose(k, row["value"], rel_tol=OUTPUT_AGREE_REL):
            bad.append(f"wall_example.ino WALL_K_N_PER_M = {k:.6g} N/m, the datasheet's eq25_K_max_N_per_m "
                       f"{row['value']:.6g} N/m")


#: bom.csv prints a mass with 2 decimals (g): half a unit of the last digit.
BOM_MASS_ABS_G = 0.005 + 1e-9


def motor_disagreements(device, out: Path) -> list[str]:
    """One line per ``bom.csv`` motor line (group ``motors``) that names no motor of the
    resolved device (its BOM description, :meth:`cad.data.catalog.MotorSpec.bom_description`)
    or states another mass than that motor's (a ``[motor]`` table's name and mass)."""
    path = Path(out) / "bom.csv"
    if not device.motors or not path.is_file():
        return []

    # bom.csv writes a text cell a spreadsheet could read as a formula with a leading "'"
    want = {csv_cell(m.spec.bom_description()): m.spec.mass_kg for m in device.motors}
    bad = []
    for r in _csv_rows(path):
        if r.get("group") != "motors":
            continue
        desc = r.get("description", "")
        if desc not in want:
            bad.append(f"bom.csv: motor line {desc!r}, the resolved device (report.json device) has "
                       f"{' / '.join(sorted(want))!r}")
        elif want[desc] is not None and abs(float(r["mass_g"]) - want[desc] * 1e3) > BOM_MASS_ABS_G:
            bad.append(f"bom.csv: mass of motor {desc!r} = {r['mass_g']} g, the resolved device has "
                       f"{want[desc] * 1e3:g} g")
    return bad


def check_outputs(device, out: Path) -> None:
    """Raise :class:`OutputsDisagree` (one line: file, fact, both values) when a written file
    in ``out`` disagrees with ``device`` (:func:`disagreements`, :func:`motor_disagreements`)
    or with another written file (:func:`file_disagreements`); list the further mismatches' count."""
    bad = disagreements(device, out) + motor_disagreements(device, out) + file_disagreements(out)
    if bad:
        more = f" (and {len(bad) - 1} more)" if len(bad) > 1 else ""
        raise OutputsDisagree(f"outputs disagree, nothing published: {bad[0]}{more}")
