"""Assembly steps generated from the assembly model (issue 25 §4; no CAD import).

Input: the :class:`cad.parts.PartInstance` list of a build -- each instance's body (and
``other_body`` for a bearing's inner ring) and, for screws, pins and threaded tips, its
:class:`cad.assembly.fasteners.Fastener` record (what it clamps, head side first, and the
hole it engages, ``"<part>:<feature>"``). Output: ordered steps, each placing new part
instances, every listed instance exactly once.

Order (:func:`assembly_steps`):

1. the stages of a ``plan`` (``[(title, [instance name patterns])]``, fnmatch), or by
   default one stage per body (``ground`` first, then the bodies as they appear): its
   instances that are not joint hardware;
   (joint hardware: a joint fastener's clamped revolution or bought parts -- spacers,
   bearings, washers -- and a bought hole part, its nut or retaining ring);
   with it, the set screws (:data:`SET_SCREW`) of the parts it puts on a shaft (a capstan on
   its motor shaft, a hub on its axle), each with its tightening and thread locker
   (:func:`set_screw_check`): a part on a shaft is fixed in the step that puts it there;
2. after each stage, every fastener whose clamped parts and hole part are all in place,
   identical ones (same designation, clamped kinds and hole part) as one step;
3. the joints: one step per fastener that joins two bodies (a shoulder screw or pin), its
   whole stack (spacers, bearing, washer, nut or retaining ring) placed with it and the
   parts fitted on it (a plain pin's upper retaining ring), then a
   check that the bodies turn freely about it;
4. what is left (a fastener whose parts never came together) in a last step, said so;
   then the builder's final checks.

Names resolve to an instance name, else to the instances of that kind name.
"""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass, field


@dataclass
class Step:
    """One step: ``title``, the instances it places (``new``: instance names, in order),
    fastener lines and the checks to make (text)."""

    title: str
    new: list[str] = field(default_factory=list)
    fasteners: list[str] = field(default_factory=list)
    checks: list[str] = field(default_factory=list)


def _listed(instances) -> list:
    return [i for i in instances if i.kind.listed]


def _resolve(name: str, by_name: dict, by_kind: dict) -> list:
    if name in by_name:
        return [by_name[name]]
    return by_kind.get(name, [])


def _needs(inst, by_name: dict, by_kind: dict) -> list:
    """Instances a fastener needs in place: what it clamps and the part of its hole."""
    f = inst.fastener
    out = []
    for n in (*f.clamps, f.hole.split(":", 1)[0]):
        out += _resolve(n, by_name, by_kind)
    return [i for i in out if i.name != inst.name]


def _bodies(insts) -> set:
    return {b for i in insts for b in (i.body, i.other_body) if b is not None}


def _joint_fasteners(instances, by_name, by_kind) -> list:
    """Fasteners whose stack spans two bodies (shoulder screws, pins)."""
    out = []
    for i in _listed(instances):
        if i.fastener is None:
            continue
        if len(_bodies([i, *_needs(i, by_name, by_kind)])) >= 2:
            out.append(i)
    return out


def _default_plan(instances) -> list[tuple[str, list[str]]]:
    bodies = list(dict.fromkeys(["ground", *(i.body for i in instances)]))
    return [(f"{b}: its parts", [i.name for i in instances if i.body == b and i.fastener is None])
            for b in bodies]


def fastener_line(inst, designation: str) -> str:
    """``"`pin_A2`: ISO 7379 M6-1 x 20 (length 20 mm), clamps a, b; into `nut_A2` (5.2 mm
    engaged)"``."""
    f = inst.fastener
    clamps = ", ".join(f.clamps) if f.clamps else "nothing (a threaded tip)"
    return (f"`{inst.name}`: {designation} (length {f.length_mm:g} mm), "
            f"clamps {clamps}; into `{f.hole}` ({f.engagement_mm:g} mm engaged)")


#: The fastener kind that fixes a part on a shaft (ISO 4026 set screw, point on the shaft).
SET_SCREW = "ISO 4026"


def set_screw_check(names) -> str:
    """The check of a step that puts parts on shafts with their set screws ``names``: each
    tightened, its thread locked, before the shaft carries a load or a rope is wound on it."""
    return (f"{', '.join(names)}: a drop of medium-strength (removable) thread locker on the thread, "
            "the point tightened hard on the shaft in this step, before anything is wound on the part "
            "or the shaft is loaded (a loose set screw lets the part slip on the shaft)")


def assembly_steps(instances, designation, plan=None, final_checks=()) -> list[Step]:
    """Ordered :class:`Step` list (see the module doc). ``designation(kind) -> str`` names a
    part for the fastener lines (the BOM designation); ``plan``: optional stages
    ``[(title, [patterns])]`` or ``[(title, [patterns], [checks])]``; ``final_checks``:
    texts of the last step."""
    listed = _listed(instances)
    by_name = {i.name: i for i in instances}
    by_kind: dict[str, list] = {}
    for i in instances:
        by_kind.setdefault(i.kind.name, []).append(i)
    joints = _joint_fasteners(instances, by_name, by_kind)
    joint_names = {j.name for j in joints}
    hardware = set()  # a joint's stack: placed with its pin, not with a body
    for j in joints:
        hardware |= {n.name for c in j.fastener.clamps for n in _resolve(c, by_name, by_kind)
                     if n.kind.revolution or not n.kind.made}
        hardware |= {n.name for n in _resolve(j.fastener.hole.split(":", 1)[0], by_name, by_kind)
                     if not n.kind.made}
        hardware |= set(j.fastener.fitted)
    placed = {i.name for i in instances if not i.kind.listed}  # inside a bought item
    steps: list[Step] = []

    def take(names) -> list[str]:
        new = [n for n in names if n not in placed]
        placed.update(new)
        return new

    def fasten() -> None:
        groups: dict[tuple, list] = {}
        for i in listed:
            if i.fastener is None or i.name in placed | joint_names | reserved:
                continue
            if all(n.name in placed for n in _needs(i, by_name, by_kind)):
                hole = i.fastener.hole.split(":")[0]
                hole = by_name[hole].kind.name if hole in by_name else hole
                key = (designation(i.kind), i.fastener.clamps, hole)
                groups.setdefault(key, []).append(i)
        for (des, clamps, part), insts in groups.items():
            s = Step(f"fasten {', '.join(clamps) or part} with {len(insts)} x {des} into {part}")
            s.new = take([i.name for i in insts])
            s.fasteners = [fastener_line(i, des) for i in insts]
            steps.append(s)

    stages = plan or _default_plan(listed)
    reserved = {i.name for i in listed for st in stages  # placed by a stage, not by fasten()
                if any(fnmatch.fnmatchcase(i.name, p) for p in st[1])}
    def set_screws(new: list[str]) -> list[str]:
        """The set screws of the parts ``new`` puts on a shaft, all they need in place."""
        return [i.name for i in listed if i.fastener is not None and i.fastener.kind == SET_SCREW
                and i.name not in placed | joint_names
                and {n.name for n in _resolve(i.fastener.hole.split(":", 1)[0], by_name, by_kind)} & set(new)
                and all(n.name in placed for n in _needs(i, by_name, by_kind))]

    for title, patterns, *checks in stages:
        names = [i.name for i in listed if i.name not in hardware
                 and any(fnmatch.fnmatchcase(i.name, p) for p in patterns)]
        new = take(names)
        screws = take(set_screws(new))
        new += screws
        reserved -= set(new)
        if new or plan:
            steps.append(Step(title, new, [fastener_line(by_name[n], designation(by_name[n].kind))
                                           for n in new if by_name[n].fastener is not None],
                              (list(checks[0]) if checks else []) + [set_screw_check(screws)] * bool(screws)))
        fasten()
    for j in joints:
        if j.name in placed:
            continue
        stack = [n.name for n in _needs(j, by_name, by_kind)]
        s = Step(f"joint {j.name}: {designation(j.kind)}", take([*stack, j.name, *j.fastener.fitted]))
        s.fasteners = [fastener_line(j, designation(j.kind))]
        bodies = sorted(_bodies([j, *_needs(j, by_name, by_kind)]))
        s.checks = [f"{' and '.join(bodies)} turn freely about {j.name}, no axial play"]
        steps.append(s)
        fasten()
    left = [i.name for i in listed if i.name not in placed]
    if left:
        steps.append(Step("not placed by the rules above (check the model)", take(left)))
    steps.append(Step("final checks", [], [], list(final_checks)))
    return steps


def assembly_md(title: str, steps: list[Step], describe, images=None) -> str:
    """``assembly.md`` text: numbered steps, one bullet per instance placed
    (``- `name` (kind): description``; ``describe(name) -> (kind, text)``); ``images``:
    ``{step number from 1: relative path}`` of the exploded views, linked under their
    step's heading (:mod:`cad.report.step_views`)."""
    images = images or {}
    lines = [f"# Assembly: {title}", "",
             "Generated from the assembly model (part instances, bodies, fastener records: "
             "`cad/assembly/steps.py`); every part instance is placed in exactly one step.", ""]
    if images:
        lines += ["Each picture shows the parts already assembled in grey and the parts the "
                  "step adds in colour, moved out along the step's insertion axis (a thin "
                  "line from where each one goes).", ""]
    for k, s in enumerate(steps, 1):
        lines += [f"## Step {k}: {s.title}", ""]
        if k in images:
            lines += [f"![step {k}: exploded view]({images[k]})", ""]
        for n in s.new:
            kind, text = describe(n)
            lines.append(f"- `{n}` ({kind}): {text}")
        lines += [f"- fastener {f}" for f in s.fasteners]
        lines += [f"- check: {c}" for c in s.checks]
        lines.append("")
    return "\n".join(lines)
