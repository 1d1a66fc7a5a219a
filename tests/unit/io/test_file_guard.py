"""Issue 22 §2 and §5: every file hapticad reads passes one guard (:mod:`cad.io.guard`), and an
error line cuts long values to a readable length (:func:`cad.cli.app.readable`).

Each reproducer of ``shared/cases/reliability/`` named below is one test here:
``toml-deep-nesting-recursionerror``, ``outdir-hostile-manifest-hang``,
``wall-build-dir-damaged-report-traceback``, ``error-line-echoes-megabytes``; plus the STEP file
whose deep nesting crashed ``massprops`` with a segmentation fault, and cache entries that are
not regular files of bounded size. Checks that would hang if the guard regressed (a FIFO, a
device) run in a subprocess with a timeout.
"""

from __future__ import annotations

import hashlib
import json
import os
import random
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad

from cad.cli.app import LINE_MAX_CHARS, WORD_MAX_CHARS, readable
from cad.errors import FileDamaged, FileRefused
from cad.io import guard
from cad.tolerances import NESTING_MAX_DEPTH, READ_MAX_BYTES

ROOT = Path(__file__).resolve().parents[3]
DESIGNS = ROOT / "designs"
BOX_STEP = ROOT / "tests" / "cases" / "step-solid-plus-surfaces" / "box_plus_face.step"
POINT = "#12 = CARTESIAN_POINT('',(0.,0.,0.));"


def _python(code: str, timeout: float = 60) -> subprocess.CompletedProcess:
    """Run ``code`` in a fresh interpreter (a regression hangs there, not in the suite)."""
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, timeout=timeout, cwd=ROOT)


def _cli(args: list[str], cwd: Path, timeout: float = 60) -> subprocess.CompletedProcess:
    """The real console entry point in a subprocess (signals installed, as a user runs it)."""
    return subprocess.run([sys.executable, "-m", "cad.cli.entry", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout, cwd=cwd)


# ---------------------------------------------------------------- the nesting scan


def _json_depth(obj) -> int:
    """Depth of a parsed JSON value (a second method: the parser's own tree)."""
    if isinstance(obj, dict):
        return 1 + max((_json_depth(v) for v in obj.values()), default=0)
    if isinstance(obj, list):
        return 1 + max((_json_depth(v) for v in obj), default=0)
    return 0


def _random_json(rng: random.Random, depth: int):
    if depth == 0 or rng.random() < 0.2:
        return rng.choice([1, 2.5, None, True, "a[b{c", '"]}', "\\", "x"])
    if rng.random() < 0.5:
        return [_random_json(rng, depth - 1) for _ in range(rng.randint(0, 3))]
    return {f"k{i}]": _random_json(rng, depth - 1) for i in range(rng.randint(0, 3))}


def test_json_scan_depth_equals_the_parsed_tree_depth():
    """Seeded documents whose strings hold brackets and escaped quotes: the bracket scan
    (strings skipped) gives exactly the depth of the tree ``json.loads`` builds."""
    rng = random.Random(22)
    for _ in range(300):
        doc = _random_json(rng, rng.randint(0, 12))
        text = json.dumps(doc, indent=rng.choice([None, 1]))
        assert guard.nesting_depth(text.encode(), "json") == _json_depth(doc), text


def test_toml_and_step_scans_skip_strings_and_comments():
    toml = b'a = "[[[[\\" [[["\nb = \'[[[[\'\nc = """\n[[[[ \\""" ]]"""\nd = [[1], [2]] # [[[[[[\n[t]\n'
    assert guard.nesting_depth(toml, "toml") == 2
    step = b"#1 = A('it''s (((( ', ((1.,2.)), /* (((((( */ (3.));"
    assert guard.nesting_depth(step, "step") == 3
    assert guard.nesting_depth(b"x = " + b"[" * 50_000 + b"]" * 50_000, "toml") == 50_000
    # an unterminated string is consumed once: linear time, depth from what precedes it
    assert guard.nesting_depth(b'x = [[ """' + b'"""' * 100_000, "toml") == 2
    # an unterminated string ending in a backslash: the scan must not backtrack (a pattern
    # that did took seconds at 24 characters, ~2^n); 100 000 characters end at once
    for syntax, text in (("json", b'[["' + b"a" * 100_000 + b"\\"),
                         ("toml", b'x = [["' + b"a" * 100_000 + b"\\"),
                         ("toml", b'x = [["""' + b"a" * 100_000 + b"\\"),
                         ("step", b"#1 = A((('" + b"a" * 100_000 + b"'")):
        assert guard.nesting_depth(text, syntax) == (3 if syntax == "step" else 2), syntax


# ---------------------------------------------------------------- the file checks


def test_regular_file_size_and_kind_checks(tmp_path):
    small = tmp_path / "m.json"
    small.write_text('{"files": []}')
    assert guard.load_json(small, "manifest", "--out") == {"files": []}
    link = tmp_path / "link.json"
    link.symlink_to(small)
    assert guard.load_json(link, "manifest", "--out") == {"files": []}  # links resolved
    big = tmp_path / "big.toml"
    with open(big, "wb") as fh:  # sparse: refused from its size, never read
        fh.truncate(READ_MAX_BYTES["design"] + 1)
    cases = {
        big: f"is {(1 << 20) + 1} bytes, over the limit of {1 << 20} bytes (1 MiB) for a design file",
        tmp_path: "is a folder",
        tmp_path / "none.json": "does not exist",
        Path("/dev/zero"): "is a character device",
    }
    dangling = tmp_path / "dangling"
    dangling.symlink_to(tmp_path / "gone")
    cases[dangling] = "symbolic link to a missing file"
    loop = tmp_path / "loop"
    loop.symlink_to(loop)
    cases[loop] = "symbolic link loop"
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    cases[fifo] = "is a FIFO (named pipe)"
    for path, why in cases.items():
        with pytest.raises(FileRefused) as exc:
            guard.read_bytes(path, "design", "design")
        assert why in str(exc.value) and str(path) in str(exc.value), str(exc.value)
        assert not isinstance(exc.value, FileDamaged)
    bad = tmp_path / "bad.json"
    bad.write_text('{"files": [')
    with pytest.raises(FileDamaged, match="is not valid JSON"):
        guard.load_json(bad, "manifest", "--out")


# ---------------------------------------------------------------- reproducers


@pytest.mark.parametrize("nest", [("[", "]"), ("{a=", "}")], ids=["arrays", "inline-tables"])
def test_toml_deep_nesting_is_one_line(tmp_path, nest):
    """Reproducer toml-deep-nesting-recursionerror: 50 000 nested arrays or inline tables
    were a RecursionError traceback in every command; now one line naming the file."""
    d = tmp_path / "d.toml"
    d.write_text((DESIGNS / "hoeken.toml").read_text()
                 + "\n[analysis]\nx = " + nest[0] * 50_000 + "1" + nest[1] * 50_000 + "\n")
    code, _, err = hapticad("analyze", d)
    assert_one_line_error(code, err, "design:", str(d), "nesting too deep", "50000 levels",
                          f"limit is {NESTING_MAX_DEPTH}")


@pytest.mark.parametrize("hostile", ["fifo", "dev-zero"])
def test_hostile_manifest_refused_at_once(tmp_path, hostile):
    """Reproducer outdir-hostile-manifest-hang: ``--out`` whose manifest.json is a FIFO hung
    ``build`` forever; a link to /dev/zero exhausted memory. Refused at once (exit 2, --out)."""
    out = tmp_path / "fo"
    out.mkdir()
    if hostile == "fifo":
        os.mkfifo(out / "manifest.json")
    else:
        (out / "manifest.json").symlink_to("/dev/zero")
    r = _cli(["build", DESIGNS / "hoeken.toml", "--fidelity", "inertia", "--formats", "step",
              "--out", out], tmp_path)
    assert_one_line_error(r.returncode, r.stderr, "--out:", "manifest.json", "not a regular file")
    assert sorted(os.listdir(out)) == ["manifest.json"]


def test_manifest_listing_a_device_or_outside_path_is_not_up_to_date(tmp_path):
    """Reproducer outdir-hostile-manifest-hang, third case: a manifest listing /dev/zero (0
    bytes) hung the up-to-date check hashing it. Now such a manifest is a mismatch (the build
    is redone), and no listed path outside the folder or not a regular file is opened."""
    out = tmp_path / "lo"
    out.mkdir()
    (out / "a.txt").write_text("a")
    fifo = out / "p"
    os.mkfifo(fifo)
    rows = [{"path": "a.txt", "sha256": hashlib.sha256(b"a").hexdigest(), "bytes": 1}]
    cases = [{"path": "/dev/zero", "sha256": "0" * 64, "bytes": 0},
             {"path": "../lo/a.txt", "sha256": "0" * 64, "bytes": 1},
             {"path": "p", "sha256": "0" * 64, "bytes": 0}]
    for row in cases:
        (out / "manifest.json").write_text(json.dumps({"files": [row, *rows]}))
        r = _python(f"""
            from cad.export.manifest import verify_manifest
            from cad.io.outdir import foreign_entry
            print(verify_manifest({str(out)!r}), foreign_entry(__import__('pathlib').Path({str(out)!r})))
            """)
        assert r.returncode == 0, r.stderr
        assert r.stdout.split()[0] == "None", (row, r.stdout)
    # the FIFO inside the folder is named, not hashed
    assert "('p', 'a FIFO (named pipe), not a regular file')" in r.stdout


def test_shared_folder_manifest_fifo_refused(tmp_path):
    """``render --out`` (a shared folder): a FIFO ``manifest.json`` is refused naming it,
    at once, before anything is built or written."""
    os.mkfifo(tmp_path / "manifest.json")
    r = _python(f"""
        from pathlib import Path
        from cad.errors import DesignError
        from cad.io.outdir import check_shared_files
        try:
            check_shared_files(Path({str(tmp_path)!r}), ["hoeken.png"])
        except DesignError as exc:
            print(exc)
        """)
    assert r.returncode == 0, r.stderr
    assert "--out:" in r.stdout and "manifest.json exists and is not a plain file: it is a FIFO" in r.stdout


def _device_folder(tmp_path: Path, **changes) -> Path:
    """A ``wall --build-dir`` folder with report.json holding what wall reads (the bundled
    Hoeken's linkage), changed by ``changes`` (a value None removes the key)."""
    from cad.design import load_design

    d = load_design(DESIGNS / "hoeken.toml")
    rep = {"name": d.name, "motor": {"key": "maxon-re35"}, **d.resolved_linkage(),
           "H11_kg_m2": 1e-5, "H12_kg_m2": 1e-6, "H22_kg_m2": 1e-6, "H33_kg_m2": 1e-6,
           "beta2_deg": 0.0}
    for k, v in changes.items():
        if v is None:
            rep.pop(k)
        else:
            rep[k] = v
    folder = tmp_path / "bd"
    folder.mkdir()
    (folder / "report.json").write_text(json.dumps(rep))
    (folder / f"{d.name}.xml").write_text("<mujoco/>")
    return folder


@pytest.mark.parametrize(("changes", "needle"), [
    ({"H11_kg_m2": None}, "H11_kg_m2 must be a finite number, it is missing"),
    ({"H12_kg_m2": "abc"}, "H12_kg_m2 must be a finite number, got 'abc'"),
    ({"motor": "x"}, "motor.key must be a string"),
    ({"beta2_deg": True}, "beta2_deg must be a finite number"),
], ids=["missing", "string", "motor", "bool"])
def test_wall_build_dir_damaged_report_is_one_line(tmp_path, changes, needle):
    """Reproducer wall-build-dir-damaged-report-traceback: a report.json without a key or with
    a string was a KeyError/TypeError traceback; now one line naming --build-dir and the key."""
    folder = _device_folder(tmp_path, **changes)
    code, _, err = hapticad("wall", DESIGNS / "hoeken.toml", "--build-dir", folder)
    assert_one_line_error(code, err, "--build-dir:", str(folder / "report.json"), needle)


def test_wall_build_dir_report_not_json_or_fifo(tmp_path):
    folder = _device_folder(tmp_path)
    (folder / "report.json").write_text('{"name": ')
    code, _, err = hapticad("wall", DESIGNS / "hoeken.toml", "--build-dir", folder)
    assert_one_line_error(code, err, "--build-dir:", "is not valid JSON")
    (folder / "report.json").unlink()
    os.mkfifo(folder / "report.json")
    r = _cli(["wall", DESIGNS / "hoeken.toml", "--build-dir", folder], tmp_path)
    assert_one_line_error(r.returncode, r.stderr, "--build-dir:", "is a FIFO")


@pytest.mark.parametrize(("xml", "needle"), [
    ("<mujoco/>", "Invalid name 'crank'"), ("<mujoco", "XML parse error"),
    ("<mujoco>" + "<worldbody>" + "<body>" * 100_000, "XML parse error"),
], ids=["empty-model", "truncated", "deep"])
def test_wall_build_dir_damaged_mjcf_is_one_line(tmp_path, xml, needle):
    """``wall --build-dir DIR --model mujoco`` with an MJCF that mujoco cannot load, or that
    lacks the crank joint the wall drives: one line naming the file, not a traceback."""
    folder = _device_folder(tmp_path)
    (folder / "hoeken.xml").write_text(xml)
    code, _, err = hapticad("wall", DESIGNS / "hoeken.toml", "--build-dir", folder, "--model", "mujoco")
    assert_one_line_error(code, err, "MJCF:", str(folder / "hoeken.xml"), needle)


def test_error_line_cuts_a_megabyte_name(tmp_path):
    """Reproducer error-line-echoes-megabytes: a 1 MB name was echoed whole into the error
    line; now the line keeps the field, the reason and both ends of the value, within the cap."""
    d = tmp_path / "d.toml"
    d.write_text((DESIGNS / "hoeken.toml").read_text()
                 .replace('name = "hoeken"', 'name = "' + "x" * 1_000_000 + '"'))
    code, _, err = hapticad("analyze", d)
    assert_one_line_error(code, err, "name: must be a plain folder name", "characters cut")
    assert len(err) <= LINE_MAX_CHARS + 1


def test_error_line_of_a_huge_list_is_short(tmp_path):
    """The same reproducer's second case: a 2-million-element array; its design is over the
    1 MiB design limit, refused from its size before it is parsed."""
    d = tmp_path / "d.toml"
    d.write_text((DESIGNS / "hoeken.toml").read_text().replace(
        "[mechanism]", "[mechanism]\nl1_mm = [" + "0," * 2_000_000 + "]\n", 1))
    code, _, err = hapticad("analyze", d)
    assert_one_line_error(code, err, "design:", "bytes (1 MiB) for a design file")
    assert len(err) <= LINE_MAX_CHARS + 1


def test_readable_keeps_both_ends_and_counts_the_cut():
    word = "".join(random.Random(5).choice("abcdef") for _ in range(10_000))
    line = readable(f"hapticad: error: name: got {word!r}; use a short name")
    assert line.startswith("hapticad: error: name: got '" + word[:100])
    assert line.endswith(word[-60:] + "'; use a short name")
    cut = int(line.split("...[")[1].split(" characters cut]")[0])
    kept = line.split("...[")[0].split("got ")[1] + line.split(" characters cut]...")[1].split("; use")[0]
    assert cut + len(kept) == len(word) + 2  # every character is kept or counted (quotes too)
    assert max(len(w) for w in line.split()) <= WORD_MAX_CHARS + 40
    many = readable("hapticad: error: x: got [" + "0, " * 100_000 + "]; the fix")
    assert len(many) <= LINE_MAX_CHARS + 40 and many.endswith("]; the fix")
    assert readable("short line\nsecond") == "short line second"


def _deep_step(tmp_path: Path, n: int) -> Path:
    text = BOX_STEP.read_text()
    assert POINT in text
    p = tmp_path / f"deep{n}.step"
    p.write_text(text.replace(POINT, "#12 = CARTESIAN_POINT(''," + "(" * n + "0." + ")" * n + ");", 1))
    return p


def test_deep_step_refused_before_occt(tmp_path):
    """A STEP point nested 100 000 parentheses deep crashed ``massprops`` with a segmentation
    fault inside OCCT's reader; the pre-scan refuses it in one line naming the file."""
    p = _deep_step(tmp_path, 100_000)
    code, _, err = hapticad("massprops", p)
    assert_one_line_error(code, err, "FILE:", str(p), "nesting too deep", "100001 levels")


def _long_id_step(tmp_path: Path, digits: int) -> Path:
    text = BOX_STEP.read_text()
    assert text.count("#12 ") == 1 and ",#12," in text
    p = tmp_path / f"id{digits}.step"
    p.write_text(text.replace("#12 ", "#" + "9" * digits + " ").replace(",#12,", ",#" + "9" * digits + ","))
    return p


def test_step_entity_id_too_long_refused_before_occt(tmp_path):
    """A 12-digit entity id crashed OCCT's reader (segmentation fault); the pre-scan refuses
    it. A 9-digit id is read: the box's 6000 mm^3 (10 x 20 x 30 mm, closed form)."""
    p = _long_id_step(tmp_path, 12)
    code, _, err = hapticad("massprops", p)
    assert_one_line_error(code, err, "FILE:", str(p), "an entity id of 12 digits, the limit is 9")
    code, out, err = hapticad("massprops", _long_id_step(tmp_path, 9), "--json")
    assert code == 0, err
    assert json.loads(out)["volume_mm3"] == pytest.approx(6000.0, rel=1e-9)


@pytest.mark.parametrize("cause", ["nesting", "entity-id"])
def test_occt_crash_in_the_child_is_one_line(tmp_path, monkeypatch, cause):
    """Without the pre-scan such files still cannot take the command down: OCCT reads them
    in a forked child, whose segmentation fault becomes one error line naming the file."""
    p = _deep_step(tmp_path, 100_000) if cause == "nesting" else _long_id_step(tmp_path, 30)
    monkeypatch.setattr(guard, "check_step", lambda path, field: None)
    monkeypatch.delenv("HAPTICAD_FORK", raising=False)
    code, _, err = hapticad("massprops", p)
    assert_one_line_error(code, err, "FILE:", str(p), "made OCCT's STEP reader crash (signal 11)")


def test_step_read_in_the_child_keeps_its_warnings(tmp_path):
    """The forked read returns the child's warnings (a free face ignored) and the same mass
    properties as the box alone: 10 x 20 x 30 mm = 6000 mm^3 (closed form)."""
    code, out, err = hapticad("massprops", BOX_STEP, "--density", "1000", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["volume_mm3"] == pytest.approx(6000.0, rel=1e-9)
    assert any("ignored 1 face" in w for w in doc["warnings"]), doc["warnings"]


@pytest.mark.parametrize("entry", ["fifo", "dev-zero", "folder", "huge"])
def test_cache_entry_not_a_bounded_regular_file_is_a_miss(tmp_path, entry):
    """Cache entries that are not regular files of bounded size hung or exhausted memory:
    each cache's reader now treats them as a miss (None), at once."""
    r = _python(f"""
        import os
        from pathlib import Path
        from cad.io import derived_cache
        from cad.parts import part_props, shape_cache
        from cad.tolerances import READ_MAX_BYTES
        root = Path({str(tmp_path)!r})
        out = []
        for name, read in (("d.bin", derived_cache._read), ("s.brep", shape_cache._read),
                           ("p.json", lambda p: part_props._read(p, "k"))):
            p = root / name
            (root / (name + ".sha256")).write_text("0" * 64)
            if {entry!r} == "fifo":
                os.mkfifo(p)
            elif {entry!r} == "dev-zero":
                p.symlink_to("/dev/zero")
            elif {entry!r} == "folder":
                p.mkdir()
            else:
                with open(p, "wb") as fh:
                    fh.truncate(READ_MAX_BYTES["cache"] + 1)
            out.append(read(p))
        print(out)
        """)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[None, None, None]"
