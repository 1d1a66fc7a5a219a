"""The forked children of the build driver (:func:`cad.pipeline.run.run_family`): a child's
value is read once through :meth:`cad.pipeline.run.Build.child` (a second read returns it
again without waiting twice, which :meth:`cad.pipeline.forked.Forked.result` refuses), with
its wall time; the same-body check is one child the driver starts for every family and the
family's interference check reads (:meth:`cad.pipeline.run.Build.same_body`), never run a
second time."""

from __future__ import annotations

import os

from cad.assembly import interference as itf
from cad.pipeline import forked
from cad.pipeline.run import Build, timed_call


def test_a_childs_value_is_read_once_with_its_wall_time(tmp_path):
    b = Build(design=None, out_dir=tmp_path, formats=set(), fidelity="preview",
              allow_interference=False)
    parent = os.getpid()
    b.tasks["x"] = forked.start(timed_call(lambda: os.getpid()), "x")
    b.tasks["same_body"] = forked.start(timed_call(lambda: "same-body result"), "same_body")
    pid = b.child("x")
    assert b.child("x") == pid  # read twice: one wait
    assert (pid != parent) == forked.fork_enabled()  # from the child where forking is on
    assert b.same_body() == "same-body result" == b.child("same_body")
    assert set(b.timings) == {"x", "same_body"} and min(b.timings.values()) >= 0.0


def test_the_same_body_check_runs_once_per_build_for_a_family(tmp_path, monkeypatch):
    """The toy family (tests/architecture/toy_family) built in this process (forking off):
    the driver's child runs the same-body check once and the interference check takes its
    result instead of running it again."""
    from tests.architecture.test_toy_family import DESIGN, TOY
    from cad.data import families as registry
    import cad

    monkeypatch.setenv("HAPTICAD_FORK", "0")
    monkeypatch.setitem(registry.FAMILIES, TOY, registry.Family(
        TOY, TOY, "tests.architecture.toy_family.design", "tests.architecture.toy_family",
        ("build", "check", "datasheet")))
    calls = []
    real = itf.same_body_check
    monkeypatch.setattr(itf, "same_body_check", lambda items, *a, **k: calls.append(1) or real(items, *a, **k))
    (tmp_path / "toy.toml").write_text(DESIGN)
    rep = cad.build_design(cad.load_design(tmp_path / "toy.toml"), tmp_path / "out", formats="step")
    assert calls == [1]
    assert rep["interference"]["collisions"] == []
