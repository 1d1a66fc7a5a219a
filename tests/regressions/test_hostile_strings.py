"""Issue 33 item 3: design strings are data in every output.

One build of the bundled Hoeken whose free strings are hostile in every format at once
(name, ``[motor]`` name and source, ``[prices]`` keys and currency), with every format; each
file is read back by an independent reader: Python-Markdown (tables) for report.md, the csv
module for bom.csv / order.csv, gcc for the firmware, ElementTree for SVG / URDF / MJCF, the
standard html.parser for report.html, ezdxf for DXF, json for report.json. Plus the load-time
refusals: a line break or other control character in any of those strings (C0 and C1) is
one line naming the key.
"""

from __future__ import annotations

import csv
import io
import json
import re
import subprocess
import xml.etree.ElementTree as ET
from html.parser import HTMLParser
from pathlib import Path

import pytest

from cad.design.fields import check_name, check_text
from cad.errors import DesignError
from tests.cli_helpers import hapticad
from tests.compilers import compiler

ROOT = Path(__file__).resolve().parents[2]
NAME = "ev$il #1 [x](y) =cmd ü 'q' %s &amp;"  # a legal folder name: no / \ < > : " | ? * or control
MOTOR = '=HYPERLINK(\\"http://e.invalid\\") */ $x$ <script>'
SOURCE = "x # heading ![i](http://example.invalid/t.png) | */ ??/ $\\\\alpha$ <b>bold</b> \\\\"
PRICE_KEY = "-2+3 ![i](http://e.invalid/p.png)"
CURRENCY = "=1+1"
FORMULA = ("=", "+", "-", "@", "\t", "\r")


@pytest.fixture(scope="module")
def hostile_build(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("hostile")
    text = (ROOT / "designs" / "hoeken.toml").read_text()
    text = re.sub(r'^name = "[^"]*"', lambda _: f"name = {json.dumps(NAME)}", text, count=1, flags=re.M)
    text += (f'\n[motor]\nname = "{MOTOR}"\nsource = "{SOURCE}"\ntorque_constant_mNm_per_A = 38.9\n'
             f'\n[prices]\ncurrency = "{CURRENCY}"\ncrank = 1.0\n"{PRICE_KEY}" = 2.0\n')
    (tmp / "d.toml").write_text(text)
    out = tmp / "out"
    code, _, err = hapticad("build", str(tmp / "d.toml"), "--fidelity", "preview", "--out", str(out),
                            "--formats", "step,stl,dxf,mjcf,urdf,glb,3mf,firmware,drawings")
    assert code == 0, err
    return out


def test_report_md_has_no_injected_structure(hostile_build):
    import markdown

    h = markdown.markdown((hostile_build / "report.md").read_text(), extensions=["tables"])
    srcs = re.findall(r'<img[^>]*src="([^"]*)"', h)
    assert srcs and all((hostile_build / s).is_file() for s in srcs)  # only our own figures
    assert not re.findall(r'<a [^>]*href="[a-z]+:', h)  # no link leaves the folder
    assert not re.search(r"<(script|b)>", h)
    heads = re.findall(r"<h(\d)>([^<]*)", h)
    assert [lvl for lvl, _ in heads].count("1") == 1 and not any("heading" in t for _, t in heads)
    assert MOTOR.replace('\\"', '"').split(" */")[0] in h  # the text is there, as text


@pytest.mark.parametrize("file", ["bom.csv", "order.csv"])
def test_csv_cells_are_not_formulas(hostile_build, file):
    rows = list(csv.reader(io.StringIO((hostile_build / file).read_text(), newline="")))
    cells = [c for r in rows for c in r]
    assert any(CURRENCY in c for c in cells) or file == "bom.csv"
    for c in cells:
        try:
            float(c)
            continue  # a number (no formula)
        except ValueError:
            assert not c.startswith(FORMULA), (file, c)


def test_firmware_compiles_and_the_motor_comment_is_intact(hostile_build, tmp_path):
    fw = hostile_build / "firmware"
    h = (fw / "hapticad_device.h").read_text()
    line = next(x for x in h.splitlines() if x.startswith("/* motor "))
    assert line.endswith(" */") and line.count("*/") == 1
    r = subprocess.run([compiler("c"), "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-o",
                        str(tmp_path / "t"), str(fw / "test_device.c"), str(fw / "hapticad_device.c"), "-lm"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr


def test_svg_urdf_mjcf_parse_and_html_has_no_injected_tags(hostile_build):
    files = [*(hostile_build / "drawings").glob("*.svg"), *hostile_build.glob("*.urdf"),
             *hostile_build.glob("*.xml")]
    assert len(files) >= 3
    for f in files:
        ET.parse(f)  # well-formed XML, whatever the strings
    tags: list[str] = []
    data: list[str] = []

    class P(HTMLParser):
        def handle_starttag(self, tag, attrs):
            tags.append(tag)

        def handle_data(self, d):
            data.append(d)

    P().feed((hostile_build / "report.html").read_text())
    text = "".join(data)
    assert "b" not in tags  # the page's own markup has no <b>; the source's <b>bold</b> is text
    assert "<b>bold</b>" in text and "<script>" in text


def test_dxf_reads_and_json_keeps_the_strings(hostile_build):
    import ezdxf

    dxfs = list((hostile_build / "parts").glob("*.dxf"))
    assert dxfs
    for f in dxfs:
        ezdxf.readfile(f)
    rep = json.loads((hostile_build / "report.json").read_text())
    assert rep["design"]["name"] == NAME if "design" in rep and "name" in rep["design"] else True
    assert CURRENCY == rep["order"]["currency"]


@pytest.mark.parametrize("bad", ["a\nb", "a\rb", "a\x00b", "a\x1bb", "a\x7fb", "a\u0085b", "a\u009fb",
                                 "a\u2028b"])
def test_control_characters_are_refused_in_free_texts(bad):
    with pytest.raises(DesignError, match=r"motor.source: must be one line of text"):
        check_text(bad, "motor.source")
    with pytest.raises(DesignError, match=r"name: must be a plain folder name \(control character"):
        check_name(bad)  # controls (Cc) and, since the tester's trial, separators (Zl) too


def test_every_c1_control_character_is_refused_in_a_name():
    """U+0080..U+009F are the C1 controls (Unicode category Cc, like C0 and DEL)."""
    for cp in range(0x80, 0xA0):
        with pytest.raises(DesignError, match="control character"):
            check_name(f"a{chr(cp)}b")
    assert check_name("a\u00a0b") == "a\u00a0b"  # NO-BREAK SPACE (Zs) is not a control


@pytest.mark.parametrize("family", ["hoeken_laser", "haptic_pen"])
def test_c1_name_refused_at_build(tmp_path, family):
    text = (ROOT / "designs" / f"{family}.toml").read_text()
    (tmp_path / "d.toml").write_text(re.sub(r'^name = "[^"]*"', lambda _: 'name = "a\\u0085b"', text,
                                            count=1, flags=re.M))
    code, _, err = hapticad("check", str(tmp_path / "d.toml"))
    assert code == 2 and err.count("\n") == 1 and "name: must be a plain folder name" in err
