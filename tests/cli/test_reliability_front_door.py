"""One front door: the work a command will do is bounded at load, opt-ins named (issue 22 §5).

Reproducers of ``shared/cases/reliability/``: ``tolerance-samples-times-angles-unbounded``
(cheap variant: the refusal comes before the design is read, so nothing runs) and
``optimize-script-design-misleading-exit1``. (``cache-cap-zero-means-no-cap`` is in
``tests/unit/io/test_reliability_caches.py``.) References: the limits written out here by hand
(2e6 samples x 401 angles), the metric arrays of the same study evaluated in one batch.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import assert_one_line_error, hapticad

from cad.design import bounds
from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[2]


def test_tolerance_product_of_samples_and_angles_is_refused_at_load(tmp_path):
    """2e6 samples x 1e4 angles: each flag within its bound, their product 2e10 is not; the
    refusal names both flags and comes before the design is read (a missing design file is
    never reached) and before --out is made."""
    out = tmp_path / "o"
    code, _, err = hapticad("tolerance", str(tmp_path / "missing.toml"), "--hole-mm", "0.05",
                            "--samples", "2000000", "--angles", "10000", "--out", str(out))
    assert_one_line_error(code, err, "--samples", "--angles", "2e+10", "8.02e+08")
    assert not out.exists()


def test_work_bound_is_the_largest_run_each_flag_allowed_at_the_default_angles():
    def work(samples, angles):
        return bounds.check_work("tolerance", [("--samples", samples), ("--angles", angles)])

    assert work(2_000_000, 401) == 802_000_000
    with pytest.raises(DesignError, match=r"--samples x --angles"):
        work(2_000_000, 402)
    with pytest.raises(DesignError, match=r"--angles: must be in \[11, 20001\]"):
        work(100, 20002)


@pytest.mark.parametrize(("old", "new", "needles"), [
    ("grid = 11 ", "grid = 100000 ", ("workspace.grid", "1e+10 workspace samples", "1e+06")),
    ("base_mm = [0.0, 400.0, 17]", "base_mm = [0.0, 400.0, 100000]",
     ("optimize", "100000 x 20 x 20 x 121", "4.84e+09", "2e+08")),
])
def test_pantograph_work_is_bounded_by_the_same_table(tmp_path, old, new, needles):
    """The pantograph families' workspace samples and [optimize] pairs go through the same
    :data:`cad.design.bounds.WORK` (one place): one line, exit 2, at load."""
    text = (ROOT / "designs" / "pantograph.toml").read_text(encoding="utf-8")
    assert old in text
    design = tmp_path / "p.toml"
    design.write_text(text.replace(old, new), encoding="utf-8")
    code, _, err = hapticad("optimize", str(design))
    assert_one_line_error(code, err, *needles)


def test_readme_shows_the_work_table():
    """The work-bounds table in the documentation (docs/bounds.md) is the one the code checks."""
    assert bounds.work_table() in (ROOT / "docs" / "bounds.md").read_text(encoding="utf-8")


def test_batch_size_follows_the_angles_and_changes_no_value(monkeypatch):
    """Memory per batch ~ samples x angles: more angles, fewer samples per batch (20001 angles
    at 2048 samples per batch was ~10 GB); the metrics are those of one single batch."""
    from cad.design import load_design
    from cad.kinematics import tolerance as tk

    assert tk.chunk_rows(401) == tk.CHUNK and tk.chunk_rows(20001) * 20001 <= tk.CHUNK * 401
    d = load_design(ROOT / "designs" / "hoeken.toml")
    st = tk.ToleranceStudy(d.linkage, d.phi1_min_rad, d.phi1_max_rad, 5.0,
                           (tk.Tolerance("coupler.A3", 0.05),), angles=1001)
    e = np.random.default_rng(0).normal(0.0, 0.02, size=(23, st.n_vars))
    whole = st.metrics(e)
    assert tk.chunk_rows(1001) >= 23  # one batch
    monkeypatch.setattr(tk, "CHUNK", 50)  # 50 samples per batch at 401 angles -> 20 at 1001
    assert tk.chunk_rows(1001) == 20  # two batches: 20 + 3
    split = st.metrics(e)
    assert whole.keys() == split.keys()
    for k in whole:
        np.testing.assert_array_equal(whole[k], split[k])


def test_optimize_on_a_scripted_design_names_the_opt_in_like_build(tmp_path):
    """No opt-in: exit 2 at load naming ``parts.handle_script`` and ``--allow-scripts`` (it used
    to run the search and exit 1 "no candidate passed")."""
    shutil.copy(ROOT / "designs" / "handle_cq.py", tmp_path)
    text = (ROOT / "designs" / "hoeken_light_brief.toml").read_text(encoding="utf-8")
    assert "\n[parts]\n" in text
    design = tmp_path / "d.toml"
    design.write_text(text.replace("\n[parts]\n", '\n[parts]\nhandle_script = "handle_cq.py"\n'),
                      encoding="utf-8")
    for argv in (("optimize", str(design), "--objective", "min-apparent-mass", "--trials", "2",
                  "--exact-top", "1"), ("build", str(design), "--out", str(tmp_path / "o"))):
        code, _, err = hapticad(*argv)
        assert_one_line_error(code, err, "parts.handle_script", "--allow-scripts", "optimize")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.toml", "handle_cq.py"]


def test_every_test_the_readme_reliability_table_names_exists():
    """The reliability promises table (docs/reliability.md) names only tests that exist."""
    import re

    text = (ROOT / "docs" / "reliability.md").read_text(encoding="utf-8")
    section = text.split("## Reliability promises", 1)[1].split("\n## ", 1)[0]
    named = re.findall(r"`(tests/[\w/]+\.py)::(\w+)`", section)
    assert len(named) >= 15
    for path, name in named:
        assert f"def {name}(" in (ROOT / path).read_text(encoding="utf-8"), (path, name)
