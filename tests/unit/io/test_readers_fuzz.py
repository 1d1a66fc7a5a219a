"""Seeded fuzzing of every file reader (issue 22 §2 proof): no traceback, no crash, no hang
under a memory cap.

For each kind of file hapticad reads -- a design (``analyze``), an output folder's
``manifest.json`` (``build --out``), a build's ``report.json`` (``wall --build-dir``), an STL
and a STEP file (``massprops``) -- a seeded generator makes damaged and hostile variants of a
good file: truncated at a random byte, random bytes flipped, brackets nested far past the limit
at a random place, huge counts (an STL header claiming 2^32 - 1 triangles, a 100 000-element
array, a 30-digit STEP entity id), random binary garbage, an empty file, a sparse file over the
size limit, a FIFO, a link to a device (``/dev/zero``, ``/dev/urandom``, ``/dev/null``), a
dangling link, a link loop, a folder.

All cases of a kind run through the CLI (:func:`cad.cli.app.run`) in ONE subprocess whose
address space is capped (``RLIMIT_AS``) and which is killed after a timeout; it reports one
JSON line per case as it finishes, so a crash or a hang names the case it happened in. The
property, for every case: the subprocess finishes (no hang, no segmentation fault, no
MemoryError), nothing escapes ``run`` (no traceback), the exit code is 0, 1 or 2, and on 2
stderr is exactly one ``hapticad: error:`` line -- naming the file when the file itself is
refused for what it is (a FIFO, a device, a link, over the limit).
"""

from __future__ import annotations

import json
import os
import random
import resource
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from cad.tolerances import READ_MAX_BYTES

ROOT = Path(__file__).resolve().parents[3]
DESIGN = ROOT / "designs" / "hoeken.toml"
CASES = ROOT / "tests" / "cases"

#: Address-space cap of the fuzzing subprocess: ~3x what it needs with OCCT loaded (VmPeak
#: 0.95 GB after a STEP and an STL massprops, measured); a reader that slurps /dev/zero or
#: parses a huge file whole dies on it (MemoryError) instead of swapping.
MEMORY_CAP_BYTES = 3 << 30
TIMEOUT_S = 120
N_CASES = 24

_DRIVER = textwrap.dedent("""
    import contextlib, io, json, sys, traceback
    from cad.cli.app import run
    if sys.argv[2] == "warm-occt":  # forked STEP readers inherit OCCT instead of importing it
        import OCP.STEPCAFControl, OCP.BRepGProp  # noqa: F401
    for i, argv in enumerate(json.load(open(sys.argv[1]))):
        out, err = io.StringIO(), io.StringIO()
        escaped = None
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = run(argv)
            except BaseException as exc:  # noqa: BLE001 - reported: it is the failure
                code, escaped = None, "".join(traceback.format_exception(exc))
        print(json.dumps({"i": i, "code": code, "stderr": err.getvalue(), "escaped": escaped}),
              flush=True)
""")

_DEVICES = ("/dev/zero", "/dev/urandom", "/dev/null")
_HOSTILE = ("fifo", "device", "dangling", "loop", "folder", "oversize")
_DAMAGE = ("truncate", "flip", "nest", "huge", "garbage", "empty")


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_CAP_BYTES, MEMORY_CAP_BYTES))


#: Where nesting goes in: a value position of each syntax, and the value's own brackets.
_NEST = {
    "design": (rb"\n", b"\nfz = ", [(b"[", b"]"), (b"{a=", b"}")], b"1", b"\n"),
    "manifest": (rb'": ', b"", [(b"[", b"]"), (b'{"a":', b"}")], b"1", b', "fz": '),
    "report": (rb'": ', b"", [(b"[", b"]"), (b'{"a":', b"}")], b"1", b', "fz": '),
    "step": (rb"\('',", b"", [(b"(", b")")], b"0.", b","),
}


def _nest(rng: random.Random, data: bytes, kind: str) -> bytes:
    """Brackets nested 65, 1000 or 50 000 deep, closed or not, at a value position (where a
    parser recurses into them) or, one case in four, at a random byte."""
    import re

    depth = rng.choice([65, 1000, 50_000])
    if kind == "stl" or rng.random() < 0.25:
        o, c = (b"solid ", b"") if kind == "stl" else rng.choice(_NEST[kind][2])
        at = rng.randrange(len(data) + 1)
        return data[:at] + o * depth + (c * depth if rng.random() < 0.5 else b"") + data[at:]
    where, lead, pairs, inner, tail = _NEST[kind]
    o, c = rng.choice(pairs)
    at = rng.choice([m.end() for m in re.finditer(where, data)])
    closed = rng.random() < 0.75
    value = lead + o * depth + inner + (c * depth + tail if closed else b"")
    return data[:at] + value + data[at:]


def _huge(rng: random.Random, data: bytes, kind: str) -> bytes:
    if kind == "stl":
        if data.lstrip().lower().startswith(b"solid"):  # ASCII: many empty facets
            return data.replace(b"endsolid", b"facet normal 0 0 0\nendfacet\n" * 100_000 + b"endsolid")
        return data[:80] + rng.choice([0xFFFFFFFF, 10**9, 0]).to_bytes(4, "little") + data[84:]
    if kind == "step":
        return data.replace(b"#12 ", b"#" + b"9" * 30 + b" ", 1).replace(b",#12,", b",#" + b"9" * 30 + b",")
    many = b"[" + b"0," * 100_000 + b"0]"
    if kind == "design":
        return data.replace(b"[mechanism]", b"[mechanism]\nl1_mm = " + many, 1)
    return data.replace(b'"files": [', b'"files": [' + b"0," * 100_000, 1) if kind == "manifest" \
        else data.replace(b'"H11_kg_m2": ', b'"H11_kg_m2": ' + many + b', "x": ', 1)


def _damaged(rng: random.Random, data: bytes, kind: str, how: str) -> bytes:
    if how == "truncate":
        return data[: rng.randrange(len(data))]
    if how == "flip":
        b = bytearray(data)
        for _ in range(rng.randint(1, 8)):
            b[rng.randrange(len(b))] = rng.randrange(256)
        return bytes(b)
    if how == "nest":
        return _nest(rng, data, kind)
    if how == "huge":
        return _huge(rng, data, kind)
    if how == "garbage":
        return rng.randbytes(rng.randint(1, 5000))
    return b""


def _plant(rng: random.Random, target: Path, good: bytes, kind: str, how: str) -> None:
    """Write the case ``how`` at ``target`` (a file, or a hostile non-file)."""
    if how == "fifo":
        os.mkfifo(target)
    elif how == "device":
        target.symlink_to(rng.choice(_DEVICES))
    elif how == "dangling":
        target.symlink_to(target.with_name("gone"))
    elif how == "loop":
        target.symlink_to(target)
    elif how == "folder":
        target.mkdir()
    elif how == "oversize":
        limit = READ_MAX_BYTES["design" if kind == "design" else kind]
        with open(target, "wb") as fh:
            fh.write(good)
            fh.truncate(limit + 1)
    else:
        target.write_bytes(_damaged(rng, good, kind, how))


def _report_folder(case: Path) -> tuple[Path, bytes]:
    """A ``wall --build-dir`` folder: ``hoeken.xml`` and a good report.json of ANOTHER design
    (so a report that survives the damage is refused after it was read, never simulated)."""
    case.mkdir()
    (case / "hoeken.xml").write_text("<mujoco/>")
    rep = {"name": "other", "motor": {"key": "m"}, "l1_mm": 25.0, "l2_mm": 62.5, "l3_mm": 62.5,
           "le_mm": 125.0, "H11_kg_m2": 1e-5, "H12_kg_m2": 1e-6, "H22_kg_m2": 1e-6,
           "H33_kg_m2": 1e-6, "beta2_deg": 0.0, "curves": {"phi1_deg": [[0.0, 1.0]]}}
    return case, json.dumps(rep, indent=1).encode()


def _manifest_folder(case: Path) -> tuple[Path, bytes]:
    """An ``--out`` folder holding an unlisted file (so every variant is refused quickly)."""
    case.mkdir()
    (case / "junk.txt").write_text("mine")
    doc = {"files": [{"path": "a.step", "sha256": "0" * 64, "bytes": 3}], "build_key": "k"}
    return case, json.dumps(doc, indent=2).encode()


def _cases(kind: str, tmp: Path) -> list[tuple[str, list[str], Path]]:
    """``[(how, argv, the fuzzed file)]``, seeded per kind."""
    rng = random.Random(f"issue22-{kind}")
    hows = [*_HOSTILE, *_DAMAGE] + [rng.choice(_DAMAGE) for _ in range(N_CASES - 12)]
    out = []
    for i, how in enumerate(hows):
        case = tmp / f"c{i:02d}"
        if kind == "manifest":
            folder, good = _manifest_folder(case)
            target, argv = folder / "manifest.json", ["build", str(DESIGN), "--fidelity",
                                                      "inertia", "--formats", "step", "--out", str(folder)]
        elif kind == "report":
            folder, good = _report_folder(case)
            target, argv = folder / "report.json", ["wall", str(DESIGN), "--build-dir", str(folder)]
        else:
            case.mkdir()
            src = {"design": DESIGN,
                   "stl": rng.choice([CASES / "stl-header-count" / "box_ok.stl",
                                      CASES / "stl-far-from-origin" / "box10x20x30_at_0.stl"]),
                   "step": CASES / "step-solid-plus-surfaces" / "box_plus_face.step"}[kind]
            good = src.read_bytes()
            target = case / src.name
            argv = ["analyze", str(target)] if kind == "design" else ["massprops", str(target), "--json"]
        _plant(rng, target, good, kind, how)
        out.append((how, argv, target))
    return out


@pytest.mark.parametrize("kind", ["design", "manifest", "report", "stl", "step"])
def test_file_readers_survive_seeded_damage(tmp_path, kind):
    cases = _cases(kind, tmp_path)
    argv_file = tmp_path / "argv.json"
    argv_file.write_text(json.dumps([argv for _, argv, _ in cases]))
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "HAPTICAD_CACHE_DIR": str(tmp_path / "cache")}
    env.pop("HAPTICAD_FORK", None)  # the default: massprops reads STEP in a forked child
    try:
        r = subprocess.run([sys.executable, "-c", _DRIVER, str(argv_file),
                            "warm-occt" if kind == "step" else "-"],
                           capture_output=True, text=True, timeout=TIMEOUT_S, cwd=tmp_path,
                           env=env, preexec_fn=_limit_memory)
    except subprocess.TimeoutExpired as exc:
        done = str(exc.stdout or "").count('{"i"')
        pytest.fail(f"hung on case {done} {cases[done][:2]}")
    rows = [json.loads(ln) for ln in r.stdout.splitlines() if ln.startswith('{"i"')]
    assert r.returncode == 0 and len(rows) == len(cases), (
        f"the reader died (status {r.returncode}) on case {len(rows)} {cases[len(rows)][:2]}: "
        f"{r.stderr[-2000:]}")
    for row, (how, argv, target) in zip(rows, cases, strict=True):
        what = f"case {row['i']} ({how}): {argv}\n{row['stderr']}{row['escaped'] or ''}"
        assert row["escaped"] is None, what
        assert "Traceback" not in row["stderr"], what
        assert row["code"] in (0, 1, 2), what
        if row["code"] == 2:
            lines = row["stderr"].strip().splitlines()
            assert len(lines) == 1 and lines[0].startswith("hapticad: error: "), what
            if how in _HOSTILE:
                assert target.name in lines[0], what
        if how in _HOSTILE:
            assert row["code"] == 2, what
