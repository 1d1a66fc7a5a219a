"""The toy family's schema: ``[mechanism] family = "toy-slider"``, ``block_mm = [x, y, z]``,
``travel_mm``; optional ``[targets]`` (``moving_mass_g``)."""

from __future__ import annotations

from dataclasses import dataclass, field

from cad.design.fields import require_table
from cad.design.targets import parse_targets
from cad.errors import DesignError


@dataclass(frozen=True)
class ToyDesign:
    name: str
    family: str
    block_mm: tuple[float, float, float]
    travel_mm: float
    targets: tuple = ()
    source: str = "<design>"
    raw: dict = field(default_factory=dict, compare=False)


def parse(raw: dict, source: str = "<design>") -> ToyDesign:
    """The design, DesignError naming a bad field."""
    mech = require_table(raw, "mechanism", "")
    block = tuple(float(v) for v in mech.get("block_mm", (20.0, 10.0, 8.0)))
    if len(block) != 3 or min(block) <= 0:
        raise DesignError("mechanism.block_mm", f"expected three lengths > 0 mm, got {block}")
    targets = parse_targets(raw.get("targets", {}), "targets", ("moving_mass_g",))
    return ToyDesign(str(raw.get("name", "toy")), mech["family"], block,
                     float(mech.get("travel_mm", 30.0)), targets, source, raw)
