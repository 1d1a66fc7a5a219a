"""Every fastener of a capstan build is fastened in some step of its ``assembly.md`` (a tester's
finding: the capstans' set screws were listed in step 1 and never tightened), read back from the
build folders of the five capstan families (5-bar, twin, four-bar, delta, the pen: slow).

``assembly.md`` is parsed here (``## Step k`` headings, ``- `name` (kind): description``
bullets, ``- fastener `name`: ...`` lines, ``- check: ...`` lines) and compared with
``report.json``'s fastener records (what each clamps, the hole it engages): a screw, set screw
or nut listed in a step is fastened in that step or a later one (its fastener line there, or a
check naming it: the rope's anchor, tensioner and lock nut in the winding steps); a capstan's
set screw in the very step that puts the capstan on its motor shaft, with its thread locker,
before any rope is wound.
"""

from __future__ import annotations

import re

import pytest

_BULLET = re.compile(r"^- `([^`]+)` \(([^)]+)\): (.*)$")
_FASTENER_LINE = re.compile(r"^- fastener `([^`]+)`: ")
#: A bullet's description that makes it a fastener (the BOM's words for ISO 4762, 4026, 4032, 7379).
_FASTENER_TEXT = re.compile(r"^(socket head cap screw|set screw|hex nut|shoulder screw) ISO \d+ ")

#: The haptic pen's (six capstans, a slow build) shares tests/families/pen/test_pen_full_capstan_build.py's.
CAPSTAN_DESIGNS = ("pantograph_capstan.toml", "twin_pantograph_capstan.toml", "hoeken_capstan.toml",
                   "delta_capstan.toml", pytest.param("haptic_pen_capstan.toml", marks=pytest.mark.slow))


def parse_steps(text: str) -> list[dict]:
    """``[{"title", "parts": {name: description}, "fastened": {names}, "lines": [fastener line],
    "checks": [text]}]``."""
    steps: list[dict] = []
    for line in text.splitlines():
        if line.startswith("## Step "):
            steps.append({"title": line.split(": ", 1)[1], "parts": {}, "fastened": set(), "lines": [],
                          "checks": []})
        elif not steps:
            continue
        elif m := _FASTENER_LINE.match(line):
            steps[-1]["fastened"].add(m.group(1))
            steps[-1]["lines"].append(line)
        elif m := _BULLET.match(line):
            steps[-1]["parts"][m.group(1)] = m.group(3)
        elif line.startswith("- check: "):
            steps[-1]["checks"].append(line[len("- check: "):])
    return steps


def _named(name: str, text: str) -> bool:
    return re.search(rf"(?<![\w.]){re.escape(name)}(?![\w.])", text) is not None


def fastening_step(steps: list[dict], name: str, listed_at: int) -> int | None:
    """The first step at or after ``listed_at`` that fastens ``name``: its fastener line, a
    fastener line into it (a joint's nut) or a check that names it."""
    for k in range(listed_at, len(steps)):
        s = steps[k]
        if name in s["fastened"] or any(f"into `{name}`" in x for x in s["lines"]) \
                or any(_named(name, c) for c in s["checks"]):
            return k
    return None


@pytest.fixture(scope="module", params=CAPSTAN_DESIGNS)
def capstan_build(request, shared_build):
    """``(steps, report)`` of one bundled capstan design (preview fidelity; assembly.md and
    report.json are written by every build, so the formats are another module's where it reads
    the same design's build: tests/conftest.py ``CAPSTAN_FORMATS``, else none)."""
    from tests.conftest import CAPSTAN_FORMATS

    pen = request.param == "haptic_pen_capstan.toml"  # the pen build test's formats: one shared build
    fmts = ("firmware", "mjcf", "step", "stl") if pen else CAPSTAN_FORMATS.get(request.param, ())
    _, out, rep = shared_build(request.param, fmts, "preview")
    return parse_steps((out / "assembly.md").read_text(encoding="utf-8")), rep


def test_every_listed_fastener_has_a_fastening_step(capstan_build):
    steps, rep = capstan_build
    listed = {n: (k, d) for k, s in enumerate(steps) for n, d in s["parts"].items() if _FASTENER_TEXT.search(d)}
    assert len(listed) >= len(rep["fasteners"]) > 0
    loose = [n for n, (k, _) in listed.items() if fastening_step(steps, n, k) is None]
    assert loose == []
    # every fastener record of report.json has its fastener line in the step that lists it
    for name in rep["fasteners"]:
        k, _ = listed[name]
        assert name in steps[k]["fastened"], (name, steps[k]["title"])


def test_capstan_set_screws_fastened_where_the_capstan_goes_on_the_shaft(capstan_build):
    steps, rep = capstan_build
    step_of = {n: k for k, s in enumerate(steps) for n in s["parts"]}
    wind = min(k for k, s in enumerate(steps) if any(c.startswith("wind the rope") for c in s["checks"]))
    capstans = [n for k, s in enumerate(steps) for n, d in s["parts"].items()
                if re.match(r"capstan \d+(\.\d+)? mm pitch", d) and "motor shaft" in d]
    assert capstans
    for c in capstans:
        screws = [n for n, f in rep["fasteners"].items() if f["hole"] == f"{c}:set_screw"]
        assert len(screws) == 1, (c, screws)
        s, f = screws[0], rep["fasteners"][screws[0]]
        assert f["kind"] == "ISO 4026" and rep["tapped_holes"][f["hole"]]["part"] == c
        k = step_of[c]
        assert step_of[s] == k and s in steps[k]["fastened"] and k < wind, (c, s, steps[k]["title"])
        assert any(_named(s, ch) and "thread locker" in ch for ch in steps[k]["checks"])


def test_each_rope_names_its_own_anchor_tensioner_and_nut(capstan_build):
    """One winding and one tensioning check per rope, naming parts the steps place."""
    steps, rep = capstan_build
    placed = {n for s in steps for n in s["parts"]}
    checks = [c for s in steps for c in s["checks"]]
    winds = [c for c in checks if c.startswith("wind the rope")]
    anchors = sorted(n for n in placed if re.search(r"capstan_anchor(_\d+)?_1$", n))
    assert len(winds) == len(anchors) == sum(1 for n in placed if "capstan_tensioner_nut" in n)
    for a in anchors:
        assert sum(_named(a, c) for c in winds) == 1, a
