"""Which command accepts which design family: one table, used for the hints of refusals
and checked against the README's commands x families table (tests/test_readme.py).

No CAD imports; the family names are those of ``[mechanism] family``.
"""

from __future__ import annotations

FOUR_BARS = ("hoeken", "roberts", "chebyshev", "chebyshev-v", "custom")
PANTOGRAPHS = ("pantograph", "twin-pantograph", "haptic-pen")
FAMILY_GROUPS = {"four-bar": FOUR_BARS, "pantograph": ("pantograph",),
                 "twin-pantograph": ("twin-pantograph",), "haptic-pen": ("haptic-pen",),
                 "powermouse": ("powermouse",)}

#: command -> the design families it accepts (commands that take no design are absent).
COMMAND_FAMILIES: dict[str, tuple[str, ...]] = {
    "analyze": FOUR_BARS,
    "synth": FOUR_BARS,
    "swap": FOUR_BARS,
    "check": FOUR_BARS + PANTOGRAPHS,
    "fit": FOUR_BARS + PANTOGRAPHS,
    "build": FOUR_BARS + ("pantograph", "twin-pantograph", "powermouse"),
    "gii": PANTOGRAPHS,
    "optimize": FOUR_BARS + PANTOGRAPHS,
    "tolerance": FOUR_BARS,
    "sweep": FOUR_BARS,
    "wall": FOUR_BARS,
    "render": FOUR_BARS + ("pantograph", "twin-pantograph", "powermouse"),
    "datasheet": FOUR_BARS + ("pantograph", "twin-pantograph", "powermouse"),
}


def refusal(command: str, family: str) -> str:
    """``"<command> works on ... designs; for a <family> design use: hapticad a, hapticad b"``."""
    groups = [g for g, fams in FAMILY_GROUPS.items()
              if set(fams) <= set(COMMAND_FAMILIES.get(command, ()))]
    others = [c for c, fams in COMMAND_FAMILIES.items() if family in fams and c != command]
    hint = ", ".join(f"hapticad {c}" for c in others) or "no design command"
    return f"{command} works on {' / '.join(groups)} designs; for a {family} design use: {hint}"


#: Commands that read no design file (they take a STEP/STL file, flags, or nothing).
NO_DESIGN_COMMANDS = ("massprops", "voicecoil", "bench", "cache")


def markdown_table() -> str:
    """The README's commands x families table, from :data:`COMMAND_FAMILIES`."""
    cols = list(FAMILY_GROUPS)
    lines = ["| command | " + " | ".join(cols) + " |", "|---|" + "---|" * len(cols)]
    for cmd, fams in COMMAND_FAMILIES.items():
        cells = ["yes" if set(FAMILY_GROUPS[g]) <= set(fams) else "–" for g in cols]
        lines.append(f"| `{cmd}` | " + " | ".join(cells) + " |")
    return "\n".join(lines)
