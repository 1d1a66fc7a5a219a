import os

# One BLAS thread per test process (as the CLI sets, cad/cli/entry.py): the suite runs on two
# xdist workers on two cores, and OpenBLAS's own threads in each worker oversubscribe them and
# spin on the small solves the frame and Jacobian tests make (measured on this 2-core machine
# under load: the delta structure and stress tests 24.2 s -> 13.6 s). Set before numpy loads
# (nothing imports it before this file); subprocesses inherit it.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

from hypothesis import HealthCheck, settings  # noqa: E402 - after the thread limits above

# derandomized (same examples every run); no timing health checks: a loaded 2-core machine
# must not turn a slow example into a failure (performance is measured by `hapticad bench`)
settings.register_profile("ci", deadline=None, derandomize=True, max_examples=60,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


import pytest  # noqa: E402


@pytest.hookimpl(wrapper=True)
def pytest_make_collect_report(collector):
    """Collect with a first ``import build123d`` routed as a build routes it
    (:func:`cad.parts.lazy_import.routed_first_import`: without scikit-learn, which
    build123d's STL converter imports at its top): test modules that import build123d at
    their top (tests/cli/test_massprops_cli.py and four more) no longer load scikit-learn in
    every worker (measured: 0.5 s CPU of each worker's collection). Nothing is imported when
    no module asks for build123d."""
    from cad.parts.lazy_import import routed_first_import

    with routed_first_import():
        return (yield)

#: Bundled designs of the non-four-bar families (tests/families/test_family_builds.py and others).
FAMILY_DESIGNS = {
    "pantograph": "pantograph.toml",
    "twin-pantograph": "haptic_mouse.toml",
    "powermouse": "powermouse.toml",
}


#: Formats of the shared builds below (tests that rebuild them elsewhere pass the same set).
FAMILY_FORMATS = ("step", "stl", "dxf", "glb", "firmware", "drawings")
HOEKEN_SIM_FORMATS = ("mjcf", "urdf", "stl", "step", "firmware")
#: The simulator builds (preview fidelity) of the bundled 5-bars and the PowerMouse, read by
#: tests/unit/export/test_sim_fivebar_powermouse.py, tests/unit/export/test_sim_export.py and
#: tests/regressions/test_outputs_agree.py through ``shared_build(name, SIM_FORMATS[name],
#: "preview")``: one build per design and run where each module made its own with a subset of
#: these formats (the formats are written independently of each other: a format more does not
#: change the others' files).
SIM_FORMATS = {
    "pantograph.toml": ("mjcf", "urdf", "stl", "firmware"),
    "haptic_mouse.toml": ("mjcf", "urdf", "stl", "firmware"),
    "powermouse.toml": ("mjcf", "stl", "firmware"),
}
#: The bundled delta's shared build (preview): STEP for tests/families/delta/test_delta_build.py
#: and tests/unit/assembly/test_assembly_steps.py, the MJCF and its meshes for
#: tests/families/delta/test_delta_identify.py (its ``--build-dir``), the DXFs, drawings, 3MF
#: and step pictures for the read-back tests the other families' builds feed
#: (tests/families/test_family_fits.py, tests/unit/export/test_drawings.py,
#: tests/unit/report/test_report_html.py, tests/unit/report/test_step_views.py through
#: :func:`delta_build`); one delta build (the slowest bundled design to build) instead of two.
DELTA_FORMATS = ("step", "mjcf", "stl", "dxf", "drawings", "3mf")
#: The bundled haptic pen's shared build (inertia): the firmware for
#: tests/families/pen/test_pen_firmware.py, STEP (assembly and parts) for
#: tests/regressions/test_tryit_t23.py; one build where each made its own.
PEN_FORMATS = ("firmware", "step")
#: The bundled capstan designs' shared builds (preview) where two modules read one:
#: tests/unit/assembly/test_capstan_fastening_steps.py (assembly.md, report.json: written by
#: every build) with tests/families/pantograph/test_pantograph_capstan.py (MJCF, meshes,
#: firmware) and with tests/regressions/test_outputs_agree.py's capstan Hoeken (firmware, MJCF);
#: one build each where every module made its own.
CAPSTAN_FORMATS = {
    "pantograph_capstan.toml": ("firmware", "mjcf", "stl"),
    "hoeken_capstan.toml": ("firmware", "mjcf"),
}


@pytest.fixture(scope="session")
def family_builds(shared_builds):
    """One build per non-four-bar family, shared by the test modules and both xdist workers
    (:func:`shared_build`): ``{family: (design, out_dir, report)}`` at the cheap ``inertia``
    fidelity (plain bearing rings, 12 PowerMouse poses), every format; ``report`` is its
    ``report.json`` read back. Read-only for tests."""
    got = shared_builds([(fn, FAMILY_FORMATS, "inertia") for fn in FAMILY_DESIGNS.values()])
    return dict(zip(FAMILY_DESIGNS, got, strict=True))


@pytest.fixture(scope="session")
def delta_build(shared_build):
    """The bundled delta's shared build (:data:`DELTA_FORMATS`, preview): ``(design, out_dir,
    report)`` as :func:`family_builds`' entries. Read-only for tests."""
    return shared_build("delta.toml", DELTA_FORMATS, "preview")


def family_build(request, fam: str):
    """``(design, out_dir, report)`` of ``fam``: the delta's :func:`delta_build` or the other
    families' :func:`family_builds` entry, built only when a test asks (``request``: the
    test's pytest request)."""
    if fam == "delta":
        return request.getfixturevalue("delta_build")
    return request.getfixturevalue("family_builds")[fam]


@pytest.fixture(scope="session")
def hoeken_sim_build(shared_build):
    """The bundled Hoeken built with the simulator formats and STEP (preview fidelity: same
    mass properties as inertia), shared by tests/unit/export/test_sim_export.py, tests/unit/sim/test_wall.py,
    tests/families/fourbar/test_fourbar_set_screw.py (its assembly.step), tests/unit/firmware/test_firmware.py
    and both xdist workers (:func:`shared_build`): ``(design, out_dir, report, report)``, the
    report read back from report.json (twice: the tuple's historical shape). Read-only."""
    d, out, rep = shared_build("hoeken.toml", HOEKEN_SIM_FORMATS, "preview")
    return d, out, rep, rep


@pytest.fixture(scope="session")
def shared_build(tmp_path_factory):
    """``shared_build(name, formats, fidelity)`` -> ``(design, out_dir, report)``: the bundled
    design ``designs/<name>`` built once per test run with exactly ``formats`` at ``fidelity``
    (``report``: its ``report.json`` read back), shared by every test module and both xdist
    workers (the first caller builds under a file lock in the run's common temporary folder,
    the others wait and read the same files). The folder is read-only for tests: a test that
    edits or rebuilds an output builds its own. ``wait=False``: None at once when another
    worker is building it (:func:`shared_builds`)."""
    import fcntl
    import json
    from pathlib import Path

    from cad.design import load_design
    from cad.pipeline import build_design

    root = Path(__file__).resolve().parents[1]
    common = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        common = common.parent  # pytest-N/popen-gwK -> pytest-N: one folder for the whole run
    common = common / "shared_builds"
    common.mkdir(exist_ok=True)

    def build(name: str, formats, fidelity: str, wait: bool = True):
        fmts = sorted(set(formats))
        key = f"{Path(name).stem}-{fidelity}-{'+'.join(fmts)}"
        out, done = common / key / "out", common / f"{key}.done"
        d = load_design(root / "designs" / name)
        with (common / f"{key}.lock").open("w") as lock:
            try:  # released when the file closes
                fcntl.flock(lock, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
            except BlockingIOError:
                return None  # wait=False: another worker is building it
            if not done.is_file():
                build_design(d, out, set(fmts), fidelity=fidelity, use_cache=False)
                done.write_text("built\n")
        return d, out, json.loads((out / "report.json").read_text())

    return build


@pytest.fixture(scope="session")
def shared_builds(shared_build):
    """``shared_builds([(name, formats, fidelity), ...])`` -> ``[(design, out_dir, report)]``:
    :func:`shared_build` of each, but every one that no other worker is building is built
    first (a lock taken without waiting), then the rest are waited for: two workers asking
    for the same builds at once build them side by side instead of one waiting out each."""

    def builds(specs):
        specs = list(specs)
        for spec in specs:
            shared_build(*spec, wait=False)
        return [shared_build(*spec) for spec in specs]

    return builds
