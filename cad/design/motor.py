"""The ``[motor]`` table of a design: the data of the user's own motor (or corrections to the
catalog winding named by ``parts.motor``).

Keys (all optional; a key given replaces the catalog value and is sourced to the design file,
or to ``source`` when given)::

    [motor]
    name = "my-motor"                        # label in the report (default: the catalog key)
    source = "Acme DC-40 data sheet rev B"   # where the values below come from
    torque_constant_mNm_per_A = 30.2
    terminal_resistance_ohm = 0.3
    torque_continuous_mNm = 170.0            # nominal (max. continuous) torque
    torque_peak_mNm = 1000.0                 # drive / motor peak (simulator actuator limit)
    stall_torque_mNm = 2000.0
    current_continuous_A = 5.8
    thermal_resistance_housing_K_per_W = 4.65
    thermal_resistance_winding_K_per_W = 1.93
    no_load_current_mA = 137.0
    rotor_inertia_g_cm2 = 134.0
    mass_g = 480.0

The mounting interface (pilot, bolt circle, shaft) stays the catalog motor's. Every number is
bounded in :mod:`cad.design.bounds` (``motor.*``). No CAD import.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from cad import tolerances as tol
from cad.data.catalog import MOTORS, get_motor
from cad.design.fields import check_text, check_unknown, optional_number
from cad.errors import DesignError

#: numeric keys of [motor] -> MotorSpec field (mass in g in the file, kg in the spec)
NUMERIC = {
    "torque_constant_mNm_per_A": "torque_constant_mNm_per_A",
    "terminal_resistance_ohm": "terminal_resistance_ohm",
    "torque_continuous_mNm": "torque_continuous_mNm",
    "torque_peak_mNm": "torque_peak_mNm",
    "stall_torque_mNm": "stall_torque_mNm",
    "current_continuous_A": "current_continuous_A",
    "thermal_resistance_housing_K_per_W": "thermal_resistance_housing_K_per_W",
    "thermal_resistance_winding_K_per_W": "thermal_resistance_winding_K_per_W",
    "no_load_current_mA": "no_load_current_mA",
    "rotor_inertia_g_cm2": "rotor_inertia_g_cm2",
    "mass_g": "mass_kg",
}
KEYS = ("name", "source", *NUMERIC)


def parse_motor_table(table: dict[str, Any] | None, prefix: str = "motor") -> tuple[tuple[str, Any], ...]:
    """Validated ``[motor]`` overrides as sorted ``(key, value)`` pairs (hashable, cache-keyable).

    Raises DesignError naming ``motor.<key>`` for an unknown key, a non-number or a value
    <= 0 (the bounds of :mod:`cad.design.bounds` were checked at load).
    """
    table = dict(table or {})
    check_unknown(table, KEYS, prefix)
    out: dict[str, Any] = {}
    for k in ("name", "source"):
        if k in table:
            v = table[k]
            if not isinstance(v, str) or not v.strip():
                raise DesignError(f"{prefix}.{k}", f"must be a non-empty string, got {v!r}")
            out[k] = check_text(v, f"{prefix}.{k}").strip()
    for k in NUMERIC:
        v = optional_number(table, k, prefix, None)
        if v is None:
            continue
        if not v > 0:
            raise DesignError(f"{prefix}.{k}", f"must be > 0, got {table[k]!r}")
        out[k] = float(v)
    peak, cont = out.get("torque_peak_mNm"), out.get("torque_continuous_mNm")
    if peak is not None and cont is not None and peak < cont:
        raise DesignError(f"{prefix}.torque_peak_mNm",
                          f"must be >= torque_continuous_mNm ({cont:g}), got {peak:g}")
    return tuple(sorted(out.items()))


_CONTINUOUS_KEYS = ("current_continuous_A", "torque_continuous_mNm", "torque_constant_mNm_per_A",
                    "no_load_current_mA")


def _check_continuous(m, changes: dict, ov: dict) -> None:
    """One continuous limit per motor: the continuous torque T_N must be what the continuous
    current carries, Kt (I_N - I0) <= T_N <= Kt I_N (maxon's relation I_N = T_N / Kt + I0, or
    without the no-load current), to MOTOR_CONTINUOUS_REL; checked when ``[motor]`` gives one
    of them (the catalog's are consistent by derivation). DesignError naming the key given."""
    given = [k for k in _CONTINUOUS_KEYS if k in ov]
    if not given:
        return
    kt = changes.get("torque_constant_mNm_per_A", m.torque_constant_mNm_per_A)
    i_n = changes.get("current_continuous_A", m.current_continuous_A)
    t_n = changes.get("torque_continuous_mNm", m.torque_continuous_mNm)
    i0 = changes.get("no_load_current_mA", m.no_load_current_mA or 0.0) * 1e-3
    if None in (kt, i_n, t_n):
        return
    lo, hi = kt * max(i_n - i0, 0.0), kt * i_n
    r = tol.MOTOR_CONTINUOUS_REL
    if lo * (1 - r) <= t_n <= hi * (1 + r):
        return
    vals = {"current_continuous_A": i_n, "torque_constant_mNm_per_A": kt, "torque_continuous_mNm": t_n}
    said = {k: f"{k} = {v:g}" + ("" if k in ov else f" ({m.key})") for k, v in vals.items()}
    raise DesignError(f"motor.{given[0]}",
                      f"{said['current_continuous_A']} A at {said['torque_constant_mNm_per_A']} mN m/A "
                      f"carries {lo:.4g}..{hi:.4g} mN m continuous, not {said['torque_continuous_mNm']} "
                      "mN m: one continuous limit per motor (give the torque_continuous_mNm and "
                      "current_continuous_A of the same data sheet)")


def _check_peak(m, changes: dict, ov: dict) -> None:
    """continuous <= peak <= stall torque: the drive's peak is what the winding gives at its
    nominal voltage at most (the data sheet's stall torque), and no less than its continuous
    torque; checked when ``[motor]`` gives one of them, against the others it gives and, for
    a table without ``name`` (corrections to the catalog winding), the catalog's; a named
    table is another motor, whose catalog values do not apply. DesignError naming the key."""
    keys = ("torque_continuous_mNm", "torque_peak_mNm", "stall_torque_mNm")
    given = [k for k in keys if k in ov]
    if not given:
        return
    own = "name" in ov
    cont, peak, stall = (changes.get(k, None if own else getattr(m, k)) for k in keys)
    stall_why = "the winding gives no more than its stall torque at nominal voltage"
    pairs = ((cont, "torque_continuous_mNm", stall, "stall_torque_mNm", stall_why),
             (peak, "torque_peak_mNm", stall, "stall_torque_mNm", stall_why),
             (cont, "torque_continuous_mNm", peak, "torque_peak_mNm",
              "a motor's peak torque is at least its continuous torque"))
    for lo, lo_k, hi, hi_k, why in pairs:
        if None not in (lo, hi) and lo > hi and (lo_k in ov or hi_k in ov):
            key = lo_k if lo_k in ov else hi_k
            said = {k: f"{k} = {v:g} mN m" + ("" if k in ov else f" ({m.key})") for k, v in ((lo_k, lo), (hi_k, hi))}
            raise DesignError(f"motor.{key}", f"{said[lo_k]} is above {said[hi_k]}: {why} (mN m "
                                              "from the same data sheet? a N m value would read 1000x small)")


def _check_name(name, key: str) -> None:
    """DesignError (``motor.name``) when ``[motor] name`` is a catalog key other than the motor
    the table describes (``parts.motor``): its rows would be labelled that motor with the
    other's data (a tester's finding)."""
    if name is not None and name != key and name in MOTORS:
        raise DesignError("motor.name", f"{name!r} is a catalog motor, but the [motor] table describes "
                                        f"parts.motor = {key!r} (its data and mount): set parts.motor = "
                                        f"{name!r} to use that motor, or give the table a name of its own")


def resolve_motor(catalog_key: str, overrides: tuple[tuple[str, Any], ...] = (), field: str = "parts.motor"):
    """The :class:`cad.data.catalog.MotorSpec` a design uses: the catalog winding with the
    ``[motor]`` overrides applied, each overridden value sourced to the design file."""
    m = get_motor(catalog_key, field)
    ov = dict(overrides)
    if not ov:
        return m
    src = ov.get("source", "design file [motor] table (user data)")
    changes: dict[str, Any] = {}
    sources = dict(m.sources)
    unverified = set(m.unverified)
    for k, f in NUMERIC.items():
        if k in ov:
            changes[f] = ov[k] * 1e-3 if k == "mass_g" else ov[k]
            sources[f] = f"{src} ([motor] {k})"
            unverified.discard(f)
    if "torque_peak_mNm" not in ov and "stall_torque_mNm" in ov:
        changes["torque_peak_mNm"] = ov["stall_torque_mNm"]
        sources["torque_peak_mNm"] = f"the stall torque of {src}"
        unverified.discard("torque_peak_mNm")
    _check_continuous(m, changes, ov)
    _check_peak(m, changes, ov)
    name = ov.get("name")
    _check_name(name, m.key)
    # unnamed: the catalog motor ordered as such, its line saying which data are the design's
    given = ", ".join(k for k in NUMERIC if k in ov)
    desc = (f"{name} (data of [motor]; mount of {m.key})" if name is not None
            else f"{m.description}; data of [motor]: {given}" if given else m.description)
    return replace(m, **changes, sources=tuple(sorted(sources.items())),
                   unverified=tuple(sorted(unverified)), description=desc,
                   winding=m.winding if name is None else name)


#: MotorSpec field -> the ``[motor]`` key that gives it.
_KEY_OF = {f: k for k, f in NUMERIC.items()}


def check_motor_data(design) -> None:
    """Refuse a design whose motor lacks a value every build reads.

    For each motor of ``design.motor_joints()`` (none: nothing to check) the catalog winding
    ``parts.<field>`` names, with the design's ``[motor]`` overrides (which describe
    ``parts.motor``) and ``parts.motor_rotor_inertia_g_cm2`` applied, every field of
    :data:`cad.data.catalog.MOTOR_BUILD_FIELDS` must have a value: a catalog motor whose public
    sources state only some constants (``maxon-re30``, ``maxon-ec45flat``) builds when the
    design gives the rest. Raises DesignError naming ``parts.<field>`` and the ``[motor]`` keys
    to add."""
    joints = getattr(design, "motor_joints", None)
    for _, fld in (joints() if joints is not None else ()):
        key = getattr(design.parts, fld)
        table = tuple(getattr(design, "motor", ()) or ()) if fld == "motor" else ()
        m = resolve_motor(key, table, f"parts.{fld}")
        missing = [f for f in m.missing_build_fields()
                   if not (f == "rotor_inertia_g_cm2"
                           and getattr(design.parts, "motor_rotor_inertia_g_cm2", None) is not None)]
        if missing:
            keys = ", ".join(_KEY_OF[f] for f in missing)
            where = "[motor]" if fld == "motor" else "the catalog (the [motor] table describes parts.motor)"
            raise DesignError(f"parts.{fld}", f"{key!r}: no public source read states {keys}; give "
                              f"{'them' if len(missing) > 1 else 'it'} in {where} from the data "
                              "sheet of the order number you buy")

