"""The contract of ``report.json`` (issue 32 §6): the keys every family's report carries, typed,
and the check that a report keeps to its family's contract before it is published.

Every family's report type (``FamilyPackage.report_type``, a ``TypedDict`` in the family's
package) extends :class:`CommonReport`; the build driver (:mod:`cad.pipeline.run`) writes the
common keys once for every family, the family its own. :func:`problems` compares a report
with its type: a missing key, a value of the wrong JSON type or a key no type declares is a
problem, and the dispatcher publishes nothing (:class:`ReportContractError`). Units are in the
key names (SPEC conventions); frames as each family's page states. No CAD import.
"""


import types
import typing
from typing import NotRequired, TypedDict

from cad.errors import HapticadError


class ReportContractError(HapticadError):
    """A build's report does not keep to its family's contract (a bug: nothing is published)."""


class Body(TypedDict):
    """One moving body's mass properties in its body frame (SI; ``com_mm`` in mm)."""

    mass_kg: float
    com_mm: list
    inertia_com_kg_m2: list
    principal_moments_kg_m2: list


class CommonReport(TypedDict):
    """The keys of every family's ``report.json``.

    name, family, source (the design file's name), fidelity (``--fidelity``); ``bodies``:
    ``{body: Body}`` of every moving body; ``moving_mass_g`` (their sum), ``total_mass_g``
    (the BOM's mass, bought parts with no solid included); ``notes`` (lines for the reader);
    ``bom`` (the rows of ``bom.csv``), ``order`` (``order.csv``'s totals), ``files`` (every
    file of the build, relative paths); ``interference`` (the clash check over the motion),
    ``min_clearance_mm``, ``overlap_volume_mm3``; ``fasteners``, ``tapped_holes``, ``fits``,
    ``part_materials``, ``placement`` (every instance's body and pose); ``datasheet``
    (:mod:`cad.datasheet`), ``device`` (the resolved device every file was made for,
    :mod:`cad.device`), ``build`` (formats, fidelity, allow_interference, build_key)."""

    name: str
    family: str
    source: NotRequired[str]
    fidelity: str
    bodies: dict[str, Body]
    moving_mass_g: float
    total_mass_g: float
    notes: list
    bom: list
    order: dict
    files: list
    interference: dict
    min_clearance_mm: float | None
    overlap_volume_mm3: float | None
    fasteners: dict
    tapped_holes: dict
    fits: dict
    part_materials: dict
    placement: dict
    datasheet: dict
    device: dict
    build: dict


def _json_types(tp) -> tuple[type, ...]:
    """The Python types of the JSON values a type annotation admits."""
    if tp is float:
        return (int, float)
    if tp is type(None):
        return (type(None),)
    origin = typing.get_origin(tp)
    if origin in (typing.Union, types.UnionType):
        return tuple(t for a in typing.get_args(tp) for t in _json_types(a))
    if origin is not None:
        return (origin,)
    if typing.is_typeddict(tp):
        return (dict,)
    return (tp,)


def problems(report: dict, report_type: type = CommonReport) -> list[str]:
    """What in ``report`` (the JSON document) breaks ``report_type`` (a ``TypedDict``
    extending :class:`CommonReport`): missing required keys, values of the wrong JSON type
    (a bool is not a number), keys the type does not declare, and ``bodies`` entries that
    are not :class:`Body`. Empty when it keeps to it."""
    hints = typing.get_type_hints(report_type)
    out = [f"missing key {k!r}" for k in sorted(report_type.__required_keys__) if k not in report]
    out += [f"key {k!r} is not in the contract of {report_type.__name__}"
            for k in sorted(set(report) - set(hints))]
    for k, tp in hints.items():
        if k in report and not _is(report[k], _json_types(tp)):
            out.append(f"{k!r} is {type(report[k]).__name__}, the contract says {tp}")
    for name, body in (report.get("bodies") or {}).items():
        if not isinstance(body, dict) or set(body) != set(Body.__annotations__):
            out.append(f"bodies[{name!r}] is not a Body ({sorted(Body.__annotations__)})")
    return out


def _is(value, json_types: tuple[type, ...]) -> bool:
    return not isinstance(value, bool) or bool in json_types if isinstance(value, json_types) else False


def check(report: dict, report_type: type = CommonReport) -> None:
    """Raise :class:`ReportContractError` naming every problem (:func:`problems`)."""
    bad = problems(report, report_type)
    if bad:
        raise ReportContractError(f"report.json breaks {report_type.__name__}: " + "; ".join(bad[:6]))
