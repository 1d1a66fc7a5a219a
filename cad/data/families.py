"""The one family registry: every design family, its schema module, its layout package and
the commands that accept it. Everything that dispatches on ``[mechanism] family`` reads
this table (design loading, the build pipeline, the datasheet, the CLI refusals and the
commands x families table (docs/commands.md)). A new family is one row here and one
``cad/families/<package>/`` package (see docs/architecture.md).

No CAD imports.
"""

from __future__ import annotations

from dataclasses import dataclass

from cad.errors import DesignError

#: Commands that take a design, in the order of the commands x families table (docs/commands.md).
DESIGN_COMMANDS = ("analyze", "synth", "swap", "check", "fit", "build", "gii", "optimize",
                   "tolerance", "sweep", "wall", "render", "datasheet", "identify", "bench-log")
#: Commands that read no design file (they take a STEP/STL file, flags, or nothing).
NO_DESIGN_COMMANDS = ("massprops", "voicecoil", "bench", "cache")

_FOURBAR_CMDS = ("analyze", "synth", "swap", "check", "fit", "build", "optimize", "tolerance",
                 "sweep", "wall", "render", "datasheet", "identify", "bench-log")
_PANTOGRAPH_CMDS = ("check", "fit", "build", "gii", "optimize", "render", "datasheet")
#: The 5-bar, the twin pantograph and the pen also run identify and bench-log (issue 37).
_FIVEBAR_CMDS = _PANTOGRAPH_CMDS + ("identify", "bench-log")


@dataclass(frozen=True)
class Family:
    """One row of the registry.

    name : ``[mechanism] family`` of a design file.
    group : the column of the commands x families table (four-bars share one).
    design_module : the module owning the schema (``parse(raw, source) -> design``).
    package : the family package ``cad.families.<package>`` (or a full module path) whose
        ``FAMILY`` (:class:`cad.families.protocol.FamilyPackage`) gives every hook: build,
        datasheet rows, targets, optimiser, firmware, simulator.
    commands : the ``hapticad`` commands that accept its designs.
    why_not : ``(command, reason)`` pairs: why a command does not take the family, where
        that is a property of the device (said in the refusal), not work still to do.
    """

    name: str
    group: str
    design_module: str
    package: str | None
    commands: tuple[str, ...]
    why_not: tuple[tuple[str, str], ...] = ()

    @property
    def package_module(self) -> str:
        """The importable module of :attr:`package`."""
        return self.package if "." in self.package else f"cad.families.{self.package}"


#: The PowerMouse senses no position: its firmware maps coil currents to the flotor's wrench
#: (cad/families/powermouse/firmware.py), so there are no encoder counts to log or identify.
_NO_POSITION = ("the PowerMouse's firmware reads no position: no encoder, its coil currents map "
                "to the flotor's wrench, so a log has no counts to identify from")
_POWERMOUSE_WHY_NOT = (("identify", _NO_POSITION), ("bench-log", _NO_POSITION))


def _fourbar(name: str) -> Family:
    return Family(name, "four-bar", "cad.design.fourbar", "fourbar", _FOURBAR_CMDS)


FAMILIES: dict[str, Family] = {
    f.name: f
    for f in (
        _fourbar("hoeken"),
        _fourbar("roberts"),
        _fourbar("chebyshev"),
        _fourbar("chebyshev-v"),
        _fourbar("custom"),
        Family("pantograph", "pantograph", "cad.design.pantograph", "pantograph",
               _FIVEBAR_CMDS),
        Family("twin-pantograph", "twin-pantograph", "cad.design.pantograph", "pantograph",
               _FIVEBAR_CMDS),
        Family("haptic-pen", "haptic-pen", "cad.families.pen.design", "pen", _FIVEBAR_CMDS),
        Family("powermouse", "powermouse", "cad.design.powermouse", "powermouse",
               ("check", "fit", "build", "render", "datasheet"), why_not=_POWERMOUSE_WHY_NOT),
        Family("delta", "delta", "cad.families.delta.design", "delta",
               ("check", "fit", "build", "gii", "optimize", "render", "datasheet", "identify", "bench-log")),
    )
}


def family(name: str) -> Family:
    """The registry row of ``name``; KeyError for an unknown family (the design loader
    turns that into a DesignError naming ``mechanism.family``)."""
    return FAMILIES[name]


def names(group: str | None = None) -> tuple[str, ...]:
    """Family names, in registry order (of one ``group`` when given)."""
    return tuple(n for n, f in FAMILIES.items() if group is None or f.group == group)


def groups() -> dict[str, tuple[str, ...]]:
    """``{group: family names}`` in registry order (the table's columns)."""
    out: dict[str, tuple[str, ...]] = {}
    for f in FAMILIES.values():
        out[f.group] = out.get(f.group, ()) + (f.name,)
    return out


def command_families() -> dict[str, tuple[str, ...]]:
    """``{command: the family names it accepts}`` for every design command."""
    return {c: tuple(n for n, f in FAMILIES.items() if c in f.commands) for c in DESIGN_COMMANDS}


def refusal(command: str, family: str) -> str:
    """``"<command> works on ... designs; for a <family> design use: hapticad a, hapticad b"``:
    the reason of the DesignError (``mechanism.family``) a command gives a family it does not
    take (the CLI and :mod:`cad.api` raise the same one)."""
    accepts = command_families()
    fams = set(accepts.get(command, ()))
    cols = [g for g, members in groups().items() if set(members) <= fams]
    others = [c for c, f in accepts.items() if family in f and c != command]
    hint = ", ".join(f"hapticad {c}" for c in others) or "no design command"
    why = dict(FAMILIES[family].why_not).get(command) if family in FAMILIES else None
    return (f"{command} works on {' / '.join(cols)} designs" + (f" ({why})" if why else "")
            + f"; for a {family} design use: {hint}")


def require(command: str, family: str) -> None:
    """Raise :class:`cad.errors.DesignError` (``mechanism.family``, :func:`refusal`) when
    ``command`` does not accept designs of ``family``."""
    if family not in command_families().get(command, ()):

        raise DesignError("mechanism.family", refusal(command, family))
