"""Issue 33 item 5: the generated firmware links where labs compile it, and design strings
reach C as data.

* ``hapticad_device.h`` has an ``extern "C"`` guard: the wall sketch (``.ino`` is C++ on
  Arduino / PlatformIO) and a C++ caller, compiled with ``g++``, link against
  ``hapticad_device.c`` compiled as C. The reference is the linker: without the guard
  (the header copied with it removed) the same link fails with undefined references.
* A hostile motor key and source (``*/``, ``/*``, a trigraph ``??/``, a newline, non-ASCII)
  land in one intact C comment: the header compiles with ``-Wall -Wextra -Werror
  -pedantic``, and ``HC_DEVICE_NAME`` printed by the compiled program is the design name's
  UTF-8 bytes (the C compiler as the independent reader of the string literal).

Compilers via :func:`tests.compilers.compiler` (skip with the reason, fail under
``HAPTICAD_REQUIRE_CC=1``).
"""

from __future__ import annotations

import dataclasses
import json
import re
import subprocess
from pathlib import Path

import pytest

from tests.compilers import compiler

CXX_CALLER = r"""
#include "hapticad_device.h"
#include <cstdio>
int main() {
    hc_encoder_t enc = HC_ENCODER_DEFAULT;
    long counts[HC_N_JOINTS] = {0};
    hc_real q[HC_N_JOINTS], X[HC_N_TASK];
    hc_counts_to_angles(&enc, counts, q);
    int st = hc_forward(q, X);
    std::printf("%d %s\n", st, HC_DEVICE_NAME);
    return 0;
}
"""

SKETCH_MAIN = r"""
static unsigned long micros(void) { return 0; }
#include "wall_example/wall_example.ino"
int main() { setup(); loop(); return 0; }
"""


def _firmware(request, fam: str) -> Path:
    if fam == "hoeken":
        return request.getfixturevalue("hoeken_sim_build")[1] / "firmware"
    return request.getfixturevalue("family_builds")[fam][1] / "firmware"


def _c_object(fw: Path, tmp: Path) -> Path:
    obj = tmp / "dev.o"
    subprocess.run([compiler("c"), "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-c",
                    "-o", str(obj), str(fw / "hapticad_device.c")], check=True, timeout=120)
    return obj


def _link_cxx(src: Path, fw: Path, obj: Path, exe: Path) -> subprocess.CompletedProcess:
    return subprocess.run([compiler("c++"), "-std=c++11", "-Wall", "-Wextra", "-Werror", "-pedantic",
                           f"-I{fw}", "-x", "c++", str(src), "-x", "none", str(obj), "-lm", "-o", str(exe)],
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("fam", ["hoeken", "pantograph", "twin-pantograph"])
def test_cxx_caller_links_the_c_functions(request, tmp_path, fam):
    fw = _firmware(request, fam)
    obj = _c_object(fw, tmp_path)
    (tmp_path / "main.cpp").write_text(CXX_CALLER)
    r = _link_cxx(tmp_path / "main.cpp", fw, obj, tmp_path / "main")
    assert r.returncode == 0, r.stderr
    st, name = subprocess.run([str(tmp_path / "main")], capture_output=True, text=True, check=True,
                              timeout=30).stdout.split()
    assert int(st) == 0 and name == json.loads((fw / "test_vectors.json").read_text())["design"]


def test_arduino_sketch_links_as_cxx_and_not_without_the_guard(request, tmp_path):
    fw = _firmware(request, "hoeken")
    obj = _c_object(fw, tmp_path)
    (tmp_path / "sk.cpp").write_text(SKETCH_MAIN)
    r = _link_cxx(tmp_path / "sk.cpp", fw, obj, tmp_path / "sk")
    assert r.returncode == 0, r.stderr
    subprocess.run([str(tmp_path / "sk")], check=True, timeout=10)
    # the same link with the guard taken out fails: the test can see a missing guard
    bare = tmp_path / "bare"
    (bare / "wall_example").mkdir(parents=True)
    h = (fw / "hapticad_device.h").read_text()
    h2 = re.sub(r'#ifdef __cplusplus\n(extern "C" \{[^\n]*|\})\n#endif\n', "", h)
    assert h2 != h and "extern" not in h2
    (bare / "hapticad_device.h").write_text(h2)
    (bare / "wall_example" / "wall_example.ino").write_text((fw / "wall_example" / "wall_example.ino").read_text())
    r = _link_cxx(tmp_path / "sk.cpp", bare, obj, tmp_path / "sk2")
    assert r.returncode != 0 and "undefined reference" in r.stderr


def test_powermouse_header_links_from_cxx(request, tmp_path):
    fw = _firmware(request, "powermouse")
    obj = _c_object(fw, tmp_path)
    (tmp_path / "pm.cpp").write_text('#include "hapticad_device.h"\n#include <cstdio>\n'
                                     "int main() { hc_real w[6]; hc_gravity_wrench(w); "
                                     'std::printf("%s %g\\n", HC_DEVICE_NAME, (double)w[2]); return 0; }\n')
    r = _link_cxx(tmp_path / "pm.cpp", fw, obj, tmp_path / "pm")
    assert r.returncode == 0, r.stderr
    subprocess.run([str(tmp_path / "pm")], check=True, timeout=10)


HOSTILE = ["x */ int injected = 1; /* y", "a\n#define HC_N_JOINTS 99\nb", "??/ trigraph ??=", "ünï €",
           "\\ back \\", '" quote "', "$x$ `id` <b>"]


@pytest.mark.parametrize("text", HOSTILE)
def test_hostile_motor_strings_stay_inside_one_c_comment(request, tmp_path, text):
    from cad.firmware import csrc
    from cad.firmware.device import device_spec
    from cad.io.escape import c_comment
    from cad.pipeline import design_hash

    d, out, rep, _ = request.getfixturevalue("hoeken_sim_build")
    spec = device_spec(d, rep, design_hash(d), "0")
    name = "dev ü$#%'=x &amp; [y]"  # a legal design name (cad.design.fields.check_name) with C-hostile characters
    spec = dataclasses.replace(spec, name=name, motor=dataclasses.replace(spec.motor, key=text, source=text))
    h = csrc.header(spec)
    line = next(x for x in h.splitlines() if x.startswith("/* motor "))
    assert line.endswith(" */") and line.count("*/") == 1 and c_comment(text) in line
    fw = tmp_path / "fw"
    fw.mkdir()
    (fw / "hapticad_device.h").write_text(h)
    (fw / "hapticad_device.c").write_text((out / "firmware" / "hapticad_device.c").read_text())
    (tmp_path / "m.c").write_text('#include "hapticad_device.h"\n#include <stdio.h>\n'
                                  'int main(void) { fputs(HC_DEVICE_NAME, stdout); return HC_N_JOINTS; }\n')
    r = subprocess.run([compiler("c"), "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", f"-I{fw}",
                        "-o", str(tmp_path / "m"), str(tmp_path / "m.c"), str(fw / "hapticad_device.c"), "-lm"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    run = subprocess.run([str(tmp_path / "m")], capture_output=True, timeout=10)
    assert run.stdout == name.encode("utf-8") and run.returncode == 1  # HC_N_JOINTS untouched
