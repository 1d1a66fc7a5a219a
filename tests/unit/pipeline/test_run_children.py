"""The further forked children of the build driver (:class:`cad.pipeline.run.Stages`
``children`` / ``children_after_props``): a child's value is read once through
:meth:`cad.pipeline.run.Build.child` (a second read returns it again without waiting twice,
which :meth:`cad.pipeline.forked.Forked.result` refuses), its files are listed, a plain
child (exports, views) returns its value as is."""

from __future__ import annotations

import os

from cad.pipeline import forked
from cad.pipeline.run import Build, timed_call


def test_a_further_childs_value_is_read_once_and_its_files_listed(tmp_path):
    b = Build(design=None, out_dir=tmp_path, formats=set(), fidelity="preview",
              allow_interference=False)
    parent = os.getpid()
    b.tasks["x"] = forked.start(timed_call(lambda: (["a.png"], os.getpid())), "x")
    b.further.add("x")
    b.tasks["y"] = forked.start(timed_call(lambda: ["y.step"]), "y")
    pid = b.child("x")
    assert b.child("x") == pid  # read twice: one wait
    assert (pid != parent) == forked.fork_enabled()  # from the child where forking is on
    assert b.files == ["a.png"]
    assert b.child("y") == ["y.step"] and b.files == ["a.png"]  # not a further child
    assert set(b.timings) == {"x", "y"} and min(b.timings.values()) >= 0.0
