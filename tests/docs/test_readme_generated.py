"""The documentation's measured tables (README.md and docs/**/*.md) are generated from their JSON
(issue 21 §2): regenerated here and compared."""

from __future__ import annotations

import json
import shutil

import pytest

from cad.bench import readme
from cad.errors import DesignError

PAGES = readme.pages()
TEXT = "\n".join(p.read_text(encoding="utf-8") for p in PAGES)
BLOCKS = list(readme.BLOCK.finditer(TEXT))


def test_the_blocks_are_found_in_the_pages():
    """The pages holding blocks are read from docs/ (a block left behind would be found too)."""
    names = {p.relative_to(readme.ROOT).as_posix() for p in PAGES}
    assert "docs/performance.md" in names and all(n == "README.md" or n.startswith("docs/") for n in names)
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        assert readme.stale_block(text) is None and readme.regenerate(text) == text, page


def test_every_generated_block_equals_its_json():
    """A page cannot disagree with its JSON: every block re-rendered from its sources is the
    block as committed (run `python -m cad.bench.readme` after a new measurement)."""
    specs = [m.group("spec") for m in BLOCKS]
    assert len(specs) >= 4 and {s.split()[0] for s in specs} == set(readme.RENDERERS)
    assert readme.stale_block(TEXT) is None
    assert readme.regenerate(TEXT) == TEXT
    assert readme.main(["--check"]) == 0


def test_goal_cells_are_the_json_strings():
    """Second reading, without the renderer: every goal the sources hold (after a `:WORD` filter)
    is in its block with the JSON's own measured text, and each source's date is printed."""
    for m in BLOCKS:
        kind, *srcs = m.group("spec").split()
        body = m.group("body")
        for src in srcs:
            path, _, word = src.partition(":")
            data = json.loads((readme.ROOT / path).read_text())
            assert data["measured"] in body and path in body
            for g in data.get("goals", []) if kind == "goals" else []:
                if not word or word in g["goal"]:
                    assert f"| {g['goal']} |" in body and f"**{g['measured']}**" in body


def test_codesign_block_reads_the_optimum():
    data = json.loads((readme.ROOT / "docs/codesign/hoeken_light_optimize.json").read_text())
    ex = data["best"]["exact"]
    body = next(m.group("body") for m in BLOCKS if m.group("spec").startswith("codesign "))
    assert f"**{ex['M11_min_g']:.2f} – {ex['M11_max_g']:.2f} g**" in body
    assert f"{ex['structure']['first_mode_Hz']:.0f} Hz" in body


def test_math_blocks_read_the_bench():
    data = json.loads((readme.ROOT / "docs/bench/bench_math.json").read_text())
    bodies = {m.group("spec").split()[0]: m.group("body") for m in BLOCKS}
    for name, r in data["voicecoil"]["optimal_gap_by_model"].items():
        assert f"| {name} |" in bodies["voicecoil"] and f"**{r['optimal_gap_mm']:.2f} mm**" in bodies["voicecoil"]
    exact = next(p for p in data["massprops"]["points"] if p["part"] == "bar" and p["method"] == "occt-exact")
    assert f"| occt-exact | default | {1e3 * exact['time_s']:.2f} ms |" in bodies["massprops"]


def test_a_changed_json_changes_the_table_and_an_undated_one_is_refused(tmp_path):
    src = "docs/bench/bench_idle_2026-11-30.json"
    (tmp_path / "docs/bench").mkdir(parents=True)
    data = json.loads((readme.ROOT / src).read_text())
    data["goals"][0]["measured"] = "99.99 s"
    (tmp_path / src).write_text(json.dumps(data))
    body = readme.render_block(f"goals {src}", tmp_path)
    assert "**99.99 s**" in body and "**4.48 s**" not in body
    stale = TEXT.replace("**4.48 s**", "**4.47 s**", 1)
    assert stale != TEXT and readme.stale_block(stale) is not None
    del data["measured"]
    (tmp_path / src).write_text(json.dumps(data))
    with pytest.raises(DesignError, match="measured"):
        readme.render_block(f"goals {src}", tmp_path)
    shutil.rmtree(tmp_path / "docs")
    with pytest.raises(DesignError, match="source"):
        readme.render_block(f"goals {src}", tmp_path)


def test_a_bench_run_is_a_source_as_written(tmp_path):
    """`hapticad bench` records its own date and command, so its bench.json renders as is."""
    from tests.cli_helpers import hapticad

    code, _, err = hapticad("bench", "--quick", "--only", "gii", "--out", tmp_path / "b")
    assert code == 0, err
    data = json.loads((tmp_path / "b" / "bench.json").read_text())
    assert data["command"] == "hapticad bench --quick --only gii"
    body = readme.render_block("goals b/bench.json", tmp_path)
    assert f"measured {data['measured']}" in body and "`hapticad bench --quick --only gii`" in body
    assert f"**{data['goals'][0]['measured']}**" in body


def test_check_and_tolerance_blocks_read_their_captures():
    """Second reading of the captured check / tolerance JSON, and the two agree with each other:
    the tolerance study's nominal M11 is check's M11 of the same design (both from the solids)."""
    bodies = {m.group("spec").split()[0]: m.group("body") for m in BLOCKS
              if m.group("spec").split()[0] != "check" or m.group("spec") == "check docs/check/hoeken.json"}
    chk = json.loads((readme.ROOT / "docs/check/hoeken.json").read_text())
    assert chk["exit_code"] == 1 and chk["command"] == "hapticad check designs/hoeken.toml --json"
    for r in chk["rows"]:
        assert f"| {r['key']} | {r['computed']:.4g} | {r['target_text']} |" in bodies["check"]
    tol = json.loads((readme.ROOT / "docs/tolerance/hoeken_holes_uniform.json").read_text())
    m = tol["metrics"]["dy_max_mm"]
    assert f"{m['mean']:.4f} ± {m['std']:.4f}" in bodies["tolerance"]
    assert tol["inertia_source"] in bodies["tolerance"]
    for k in ("M11_min_g", "M11_max_g"):
        assert tol["metrics"][k]["nominal"] == pytest.approx(chk["computed"][k], rel=1e-9)


def test_hoeken_paper_check_block_reads_its_capture():
    """docs/papers.md's check of designs/hoeken_paper.toml: every target met (exit 0), each row's
    computed value as captured."""
    chk = json.loads((readme.ROOT / "docs/check/hoeken_paper.json").read_text())
    assert chk["exit_code"] == 0 and chk["command"] == "hapticad check designs/hoeken_paper.toml --json"
    body = next(m.group("body") for m in BLOCKS if m.group("spec") == "check docs/check/hoeken_paper.json")
    for r in chk["rows"]:
        assert r["ok"] and f"| {r['key']} | {r['computed']:.4g} | {r['target_text']} |" in body


def test_swap_block_reads_its_capture():
    data = json.loads((readme.ROOT / "docs/swap/hoeken_to_roberts.json").read_text())
    body = next(m.group("body") for m in BLOCKS if m.group("spec").startswith("swap "))
    assert f"| dy_max_mm | {data['old']['dy_max_mm']:.3f} | {data['new']['dy_max_mm']:.3f} |" in body
    assert data["new"]["family"] == "roberts" and data["old"]["stroke_mm"] == pytest.approx(data["new"]["stroke_mm"])


def test_capture_saves_a_command_json_with_its_provenance(tmp_path):
    out = tmp_path / "a" / "analyze.json"
    assert readme.main(["--capture", str(out), "--", "analyze", "designs/hoeken.toml", "--json"]) == 0
    data = json.loads(out.read_text())
    assert data["command"] == "hapticad analyze designs/hoeken.toml --json" and data["exit_code"] == 0
    import cad

    assert data["measured"].endswith("UTC")
    assert data["stroke_mm"] == cad.analyze(cad.load_design("designs/hoeken.toml"))["stroke_mm"]
    assert readme.main(["--capture", str(tmp_path / "b.json"), "--", "analyze", "designs/nope.toml",
                        "--json"]) == 2
    assert not (tmp_path / "b.json").exists()


def test_layer_order_sentence_equals_the_optimum_json():
    """The light-device section says the search settles on the planner's automatic order for
    the Hoeken family: the committed optimum's layer order is the one the page names."""
    data = json.loads((readme.ROOT / "docs/codesign/hoeken_light_optimize.json").read_text())
    order = ", ".join(data["best"]["layer_order"])
    assert f"automatic order ({order}) is also what the search settles on" in " ".join(TEXT.split())


def test_codesign_motor_row_shows_the_run_limit_and_the_current_catalog():
    """The light-design row names the continuous-torque limit the run checked (from the JSON)
    and, where the catalog was corrected afterwards, the catalog's current value
    (independent reference: cad.data.catalog.MOTORS, the data-sheet values)."""
    from cad.data.catalog import MOTORS
    data = json.loads((readme.ROOT / "docs/codesign/hoeken_light_optimize.json").read_text())
    motor = data["best"]["parts"]["motor"]
    used = data["requirements"]["motor_continuous_torque_mNm"][motor]
    now = MOTORS[motor].torque_continuous_mNm
    body = next(m.group("body") for m in BLOCKS if m.group("spec").startswith("codesign "))
    assert f"{used:g} mN·m continuous" in body
    assert (f"catalog now gives {now:g} mN·m" in body) == (abs(now - used) >= 0.05)
    assert f"{data['best']['cheap']['torque_max_mNm']:.1f} mN·m peak" in body
