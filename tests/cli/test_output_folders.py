"""A command owns only what it wrote (issue 11 items 1, 8, 9): ``--out`` of every command.

Folders (``build``, ``bench``): replaced whole only when everything in them is listed in
their ``manifest.json`` with the same sha256; anything else -> exit 2 naming the folder
and the foreign entry, nothing touched. Files (``swap``, ``synth``, ``fit``): never the
input design, never a folder; replacing a file is said. Every check reads the disk back.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad
from tests.conftest import FAMILY_FORMATS, HOEKEN_SIM_FORMATS

ROOT = Path(__file__).resolve().parents[2]
MOUSE = ROOT / "designs" / "haptic_mouse.toml"  # the quickest family to build
HOEKEN = ROOT / "designs" / "hoeken.toml"


def _tree(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (hidden ones too) with its bytes."""
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file() or p.is_symlink()
    }


def _build(cwd: Path, design: Path, out: str | None = None, *extra: str) -> tuple[int, str, str]:
    old = Path.cwd()
    os.chdir(cwd)
    try:
        args = ["build", str(design), "--fidelity", "preview", "--formats", "stl", "--json"]
        return hapticad(*args, *(["--out", out] if out else []), *extra)
    finally:
        os.chdir(old)


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """One real build of the twin-pantograph mouse into ``W/exports/haptic-mouse``
    (umask 022) and one of the same design from another folder (umask 027)."""
    base = tmp_path_factory.mktemp("owned")
    runs = {}
    for sub, mask in (("W", 0o022), ("V/deeper", 0o027)):
        cwd = base / sub
        cwd.mkdir(parents=True)
        shutil.copy(MOUSE, cwd / "mouse.toml")
        old = os.umask(mask)
        try:
            code, out, err = _build(cwd, Path("mouse.toml") if sub == "W" else cwd / "mouse.toml")
        finally:
            os.umask(old)
        assert code == 0, err
        runs[sub] = (cwd, json.loads(out))
    return runs


def _out(run) -> Path:
    cwd, rep = run
    return cwd / "exports" / "haptic-mouse"


def test_build_output_lists_every_file_and_honours_the_umask(built):
    out = _out(built["W"])
    doc = json.loads((out / "manifest.json").read_text())
    on_disk = {p for p in _tree(out) if p != "manifest.json"}
    assert {r["path"] for r in doc["files"]} == on_disk
    for r in doc["files"]:
        assert hashlib.sha256((out / r["path"]).read_bytes()).hexdigest() == r["sha256"]
    # umask 022 -> 0644 files, 0755 folder; umask 027 -> 0640, 0750 (not mkstemp's 0600/0700)
    assert {(out / p).stat().st_mode & 0o777 for p in _tree(out)} == {0o644}
    assert out.stat().st_mode & 0o777 == 0o755
    out2 = _out(built["V/deeper"])
    assert {(out2 / p).stat().st_mode & 0o777 for p in _tree(out2)} == {0o640}
    assert out2.stat().st_mode & 0o777 == 0o750


def test_same_design_from_two_folders_gives_identical_bytes(built):
    """Typed relative in one folder, absolute in the other: every file byte-identical, and no
    absolute path of the machine in any text file."""
    a, b = _tree(_out(built["W"])), _tree(_out(built["V/deeper"]))
    assert a.keys() == b.keys()
    assert [k for k in a if a[k] != b[k]] == []
    for k, data in a.items():
        if k.endswith((".json", ".md", ".csv")):
            assert str(built["W"][0]) not in data.decode(), k


def test_rebuild_replaces_only_its_own_folder(built, tmp_path):
    cwd = tmp_path
    shutil.copytree(built["W"][0], cwd, dirs_exist_ok=True)
    out = cwd / "exports" / "haptic-mouse"
    (out / "bom.csv").unlink()  # a missing file of ours is no obstacle
    code, _, err = _build(cwd, Path("mouse.toml"), None, "--no-cache")
    assert code == 0, err
    assert (out / "bom.csv").is_file() and _tree(out).keys() == _tree(_out(built["W"])).keys()
    assert [p.name for p in (cwd / "exports").iterdir()] == ["haptic-mouse"]  # no temp debris


@pytest.mark.parametrize(
    ("make", "needle"),
    [
        (lambda out: (out / "notes.txt").write_text("mine"), "notes.txt (not listed"),
        (lambda out: (out / ".ssh").mkdir() or (out / ".ssh" / "id_rsa").write_text("k"), ".ssh/"),
        (lambda out: (out / "Documents").mkdir(), "Documents/"),
        (lambda out: (out / "bom.csv").write_text("edited by hand"), "bom.csv (changed"),
        (lambda out: (out / "link").symlink_to("bom.csv"), "link (a symbolic link"),
        (lambda out: (out / "manifest.json").unlink(), "(not listed"),
    ],
    ids=["foreign-file", "hidden-folder", "empty-folder", "edited-file", "symlink", "no-manifest"],
)
def test_build_refuses_a_folder_holding_anything_foreign(built, tmp_path, make, needle):
    shutil.copytree(built["W"][0], tmp_path, dirs_exist_ok=True)
    out = tmp_path / "exports" / "haptic-mouse"
    make(out)
    before = _tree(tmp_path)
    code, _, err = _build(tmp_path, Path("mouse.toml"), None, "--no-cache")
    assert_one_line_error(code, err, "--out", "exports/haptic-mouse", needle)
    assert _tree(tmp_path) == before
    assert sorted(p.name for p in (tmp_path / "exports").iterdir()) == ["haptic-mouse"]


def test_build_out_never_touches_user_data(tmp_path):
    home = tmp_path / "home"
    (home / ".ssh").mkdir(parents=True)
    (home / ".ssh" / "id_rsa").write_text("key")
    (home / "Documents").mkdir()
    shutil.copy(MOUSE, home / "mouse.toml")
    before = _tree(tmp_path)
    # the home folder itself, the folder holding the design, an existing file, '.', '..'
    cases = [
        (tmp_path, str(home), "home holds"),
        (home, ".", "current folder"),
        (home / "Documents", "..", "current folder"),
        (home, "mouse.toml", "is a file"),
        (tmp_path, "home", "holds the design file mouse.toml"),
    ]
    for cwd, out, needle in cases:
        code, _, err = _build(cwd, home / "mouse.toml", out)
        assert_one_line_error(code, err, "--out", needle)
        assert _tree(tmp_path) == before, out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["home"]


def test_a_refused_build_creates_nothing(tmp_path):
    """Refused inside the builder (crank angle outside the range): no exports/ left behind."""
    shutil.copy(HOEKEN, tmp_path / "h.toml")
    code, _, err = _build(tmp_path, Path("h.toml"), None, "--phi1-deg", "999")
    assert_one_line_error(code, err, "--phi1-deg")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.toml"]
    code, _, err = _build(tmp_path, Path("h.toml"), "deep/er/out", "--phi1-deg", "999")
    assert_one_line_error(code, err, "--phi1-deg")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.toml"]


def _cli(cwd: Path, *args: str) -> tuple[int, str, str]:
    old = Path.cwd()
    os.chdir(cwd)
    try:
        return hapticad(*args)
    finally:
        os.chdir(old)


@pytest.mark.parametrize("cmd", ["swap", "synth", "fit", "optimize"])
def test_design_writers_never_overwrite_the_input(tmp_path, cmd):
    shutil.copy(HOEKEN, tmp_path / "h.toml")
    (tmp_path / "same.toml").hardlink_to(tmp_path / "h.toml")
    (tmp_path / "sym.toml").symlink_to("h.toml")
    (tmp_path / "folder").mkdir()
    extra = {"swap": ["--to", "roberts"], "synth": [], "fit": ["--target", "H11_kg_m2=3e-5",
                                                              "--free", "parts.handle_height_mm"],
             "optimize": ["--objective", "min-apparent-mass", "--trials", "5"]}[cmd]
    before = _tree(tmp_path)
    for out, needle in (("h.toml", "is the input design"), ("./h.toml", "is the input design"),
                        ("same.toml", "is the input design"), ("sym.toml", "is the input design"),
                        (str(tmp_path / "h.toml"), "is the input design"), ("folder", "is a folder")):
        code, _, err = _cli(tmp_path, cmd, "h.toml", *extra, "--out", out, "--json")
        assert_one_line_error(code, err, "--out", needle)
        assert _tree(tmp_path) == before, (cmd, out)


def test_swap_says_when_it_replaces_a_file(tmp_path):
    shutil.copy(HOEKEN, tmp_path / "h.toml")
    target = tmp_path / "r.toml"
    code, out, err = _cli(tmp_path, "swap", "h.toml", "--to", "roberts", "--out", "r.toml")
    assert code == 0, err
    out = " ".join(out.split())  # rich wraps lines
    assert "wrote r.toml" in out and "replaced" not in out
    first = target.read_bytes()
    code, out, err = _cli(tmp_path, "swap", "h.toml", "--to", "roberts", "--out", "r.toml")
    assert code == 0 and "replaced r.toml" in " ".join(out.split()), err
    code, out, err = _cli(tmp_path, "swap", "h.toml", "--to", "roberts", "--out", "r.toml", "--json")
    assert code == 0 and json.loads(out)["replaced"] is True, err
    assert target.read_bytes() == first
    assert (tmp_path / "h.toml").read_bytes() == HOEKEN.read_bytes()


def test_synth_says_when_it_replaces_a_file(tmp_path):
    shutil.copy(HOEKEN, tmp_path / "h.toml")
    (tmp_path / "s.toml").write_text("# an older file\n")
    code, out, err = _cli(tmp_path, "synth", "h.toml", "--out", "s.toml")
    assert code == 0, err
    assert "replaced s.toml" in out
    from cad.design import load_design

    assert load_design(tmp_path / "s.toml").family == "custom"
    assert (tmp_path / "h.toml").read_bytes() == HOEKEN.read_bytes()


def test_bench_out_refuses_foreign_folders(tmp_path):
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "mine.txt").write_text("x")
    before = _tree(tmp_path)
    for out, needle in (("b", "b holds mine.txt"), (".", "current folder")):
        code, _, err = _cli(tmp_path, "bench", "--quick", "--only", "kinematics", "--out", out)
        assert_one_line_error(code, err, "--out", needle)
    assert _tree(tmp_path) == before


def test_powermouse_chart_is_the_same_bytes_every_time(tmp_path):
    """The Fig. 8 chart of the PowerMouse build: no date, no random SVG ids (read back as XML)."""
    import xml.etree.ElementTree as ET

    from cad.design import load_design
    from cad.families.powermouse.build import fig8_chart

    d = load_design(ROOT / "designs" / "powermouse.toml")
    for sub in ("a", "b"):
        fig8_chart(d, 5.0, tmp_path / sub)
    for name in ("actuator_fig8.svg", "actuator_fig8.png"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name
    root = ET.parse(tmp_path / "a" / "actuator_fig8.svg").getroot()
    assert not [e for e in root.iter() if e.tag.endswith("}date")]
    assert any(e.get("id", "").startswith("p") for e in root.iter())  # clip paths do exist


@pytest.mark.slow
@pytest.mark.parametrize("design", ["hoeken.toml", "powermouse.toml"])
def test_four_bar_and_powermouse_from_two_folders_are_identical(tmp_path, design):
    """As the twin-pantograph test above, for the other two builders (slow: two full builds)."""
    trees = []
    for sub, typed in (("a", "relative"), ("b/c", "absolute")):
        cwd = tmp_path / sub
        cwd.mkdir(parents=True)
        shutil.copy(ROOT / "designs" / design, cwd / "d.toml")
        path = Path("d.toml") if typed == "relative" else cwd / "d.toml"
        code, _, err = _build(cwd, path)
        assert code == 0, err
        (out,) = (cwd / "exports").iterdir()
        trees.append(_tree(out))
        assert json.loads((out / "report.json").read_text()).get("source") == "d.toml"
    assert trees[0].keys() == trees[1].keys()
    assert [k for k in trees[0] if trees[0][k] != trees[1][k]] == []


def test_four_bar_build_in_a_second_process_and_folder_is_byte_identical(hoeken_sim_build, tmp_path):
    """Default-suite variant of the two slow claims above (cross-process, two folders) for the
    four-bar: the session's in-process preview build of designs/hoeken.toml and a fresh
    ``python -m cad build`` process, run from another folder on a copy typed relative, same
    fidelity and formats, no cache: every file byte-identical."""
    import subprocess
    import sys

    _, first, _, _ = hoeken_sim_build
    cwd = tmp_path / "elsewhere" / "deeper"
    cwd.mkdir(parents=True)
    shutil.copy(HOEKEN, cwd / "hoeken.toml")
    r = subprocess.run([sys.executable, "-m", "cad", "build", "hoeken.toml", "--fidelity", "preview",
                        "--formats", ",".join(HOEKEN_SIM_FORMATS), "--no-cache", "--out", "o", "--json"],
                       cwd=cwd, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    a, b = _tree(first), _tree(cwd / "o")
    assert a.keys() == b.keys() and {"assembly.step", "parts/crank.stl", "hoeken.xml"} <= a.keys()
    assert [k for k in a if a[k] != b[k]] == []


def test_powermouse_build_in_a_second_process_and_folder_is_byte_identical(family_builds, tmp_path):
    """As the four-bar test above, for the PowerMouse: the session's in-process build
    (``family_builds``: inertia fidelity, STEP/STL/DXF/glb) against a fresh process run from
    another folder on a copy typed relative: every file byte-identical."""
    import subprocess
    import sys

    _, first, _ = family_builds["powermouse"]
    cwd = tmp_path / "other"
    cwd.mkdir()
    shutil.copy(ROOT / "designs" / "powermouse.toml", cwd / "powermouse.toml")  # report.json: "source"
    r = subprocess.run([sys.executable, "-m", "cad", "build", "powermouse.toml", "--fidelity", "inertia",
                        "--formats", ",".join(FAMILY_FORMATS), "--no-cache", "--out", "o", "--json"],
                       cwd=cwd, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stderr
    a, b = _tree(first), _tree(cwd / "o")
    assert a.keys() == b.keys() and {"assembly.step", "rig/assembly.step"} <= a.keys()
    assert [k for k in a if a[k] != b[k]] == []
