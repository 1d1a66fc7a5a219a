"""Which command accepts which design family: one table, used for the hints of refusals
and checked against the commands x families table of docs/commands.md (tests/docs/test_readme.py); derived
from the one family registry, :mod:`cad.data.families`.

No CAD imports; the family names are those of ``[mechanism] family``.
"""

from __future__ import annotations

from cad.data import families as _registry

FOUR_BARS = _registry.names("four-bar")
PANTOGRAPHS = _registry.names("pantograph") + _registry.names("twin-pantograph") + \
    _registry.names("haptic-pen")
FAMILY_GROUPS = _registry.groups()

#: command -> the design families it accepts (commands that take no design are absent).
COMMAND_FAMILIES: dict[str, tuple[str, ...]] = _registry.command_families()


refusal = _registry.refusal  # the one text, shared with cad.api (cad.data.families)

NO_DESIGN_COMMANDS = _registry.NO_DESIGN_COMMANDS


def markdown_table() -> str:
    """The commands x families table (docs/commands.md), from :data:`COMMAND_FAMILIES`."""
    cols = list(FAMILY_GROUPS)
    lines = ["| command | " + " | ".join(cols) + " |", "|---|" + "---|" * len(cols)]
    for cmd, fams in COMMAND_FAMILIES.items():
        cells = ["yes" if set(FAMILY_GROUPS[g]) <= set(fams) else "–" for g in cols]
        lines.append(f"| `{cmd}` | " + " | ".join(cells) + " |")
    return "\n".join(lines)
