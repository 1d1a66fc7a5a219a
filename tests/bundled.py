"""The bundled designs a regression test builds: the shared filter of
``tests/regressions/test_outputs_agree.py`` and ``test_bought_instances.py``."""

from __future__ import annotations

import functools
import tomllib
from pathlib import Path

from cad.data import families as registry

DESIGNS = Path(__file__).resolve().parents[1] / "designs"


@functools.cache  # the design files do not change during a run: both modules above ask
def buildable(p: Path) -> bool:
    """The family takes ``build`` and the design passes its pre-CAD refusals (a delta whose
    knee layout clashes over its workspace: refused in one line, tested in
    tests/families/delta/test_delta_build.py)."""
    from cad.design import load_design
    from cad.errors import DesignError
    from cad.pipeline import family_of

    if "build" not in registry.FAMILIES[tomllib.loads(p.read_text())["mechanism"]["family"]].commands:
        return False
    d = load_design(p)
    try:
        family_of(d).check_options(d, "preview", None, set())
    except DesignError:
        return False
    return True
