"""``render --out DIR`` publishes its pictures and the manifest at once (a tester's finding: a
few-ms window between writing the pictures and the manifest, in which an interrupt left
pictures that the manifest does not list, so the next render refused them as foreign). The
folder is published whole (:func:`cad.io.atomic.atomic_dir_update`, as ``bench --out``): an
interrupt or a failure while it is written leaves the previous folder byte for byte, the user's
files, sub-folders and links kept, and no temporary folder.

The builds are replaced by a stand-in writing known picture bytes (the publish is under test,
not the renderer); the failure is a KeyboardInterrupt raised by the manifest's writer, after the
pictures are written into the new folder.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
HOEKEN = ROOT / "designs" / "hoeken.toml"


def _stand_in(tag: bytes):
    """A build_design writing ``render.png`` / ``animation.gif`` of bytes ``tag``."""
    def build(d, out, formats, **kw):
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "render.png").write_bytes(b"png " + tag)
        (out / "animation.gif").write_bytes(b"gif " + tag)
    return build


def _tree(folder: Path) -> dict:
    """``{relative path: bytes, "->target" for a link, None for a folder}`` of ``folder``."""
    out = {}
    for p in sorted(folder.rglob("*")):
        rel = p.relative_to(folder).as_posix()
        out[rel] = f"->{os.readlink(p)}" if p.is_symlink() else (None if p.is_dir() else p.read_bytes())
    return out


def test_an_interrupted_render_leaves_the_previous_folder_intact(tmp_path, monkeypatch):
    import cad.io.outdir as outdir
    import cad.pipeline as pipeline
    from cad.io.guard import sha256_of_output
    from cad.pipeline.render import render_designs

    out = tmp_path / "devices"
    out.mkdir()
    (out / "notes.md").write_text("the user's own file")
    (out / "empty").mkdir()
    os.symlink("notes.md", out / "link.md")
    monkeypatch.setattr(pipeline, "build_design", _stand_in(b"first"))
    rows = render_designs([HOEKEN], out)
    assert rows == [{"design": str(HOEKEN), "name": "hoeken", "png": str(out / "hoeken.png"),
                     "gif": str(out / "hoeken.gif")}]
    before = _tree(out)
    assert before["hoeken.png"] == b"png first" and before["notes.md"] == b"the user's own file"
    assert before["empty"] is None and before["link.md"] == "->notes.md"
    listed = {r["path"]: r["sha256"] for r in json.loads((out / "manifest.json").read_text())["files"]}
    assert listed == {n: sha256_of_output(out / n) for n in ("hoeken.gif", "hoeken.png")}

    # the second render is interrupted after its pictures are written, before its manifest
    monkeypatch.setattr(pipeline, "build_design", _stand_in(b"second"))
    real = outdir.record_shared_files

    def interrupted(folder, names):
        assert (Path(folder) / "hoeken.png").read_bytes() == b"png second"  # written, not published
        raise KeyboardInterrupt

    monkeypatch.setattr(outdir, "record_shared_files", interrupted)
    with pytest.raises(KeyboardInterrupt):
        render_designs([HOEKEN], out)
    assert _tree(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["devices"]  # no temporary folder left

    # the rerun publishes both pictures with their manifest, the user's entries kept
    monkeypatch.setattr(outdir, "record_shared_files", real)
    render_designs([HOEKEN], out)
    after = _tree(out)
    assert after["hoeken.png"] == b"png second" and after["hoeken.gif"] == b"gif second"
    assert {k: v for k, v in after.items() if not k.startswith(("hoeken.", "manifest"))} == {
        k: v for k, v in before.items() if not k.startswith(("hoeken.", "manifest"))}
    listed = {r["path"]: r["sha256"] for r in json.loads((out / "manifest.json").read_text())["files"]}
    assert listed == {n: sha256_of_output(out / n) for n in ("hoeken.gif", "hoeken.png")}
