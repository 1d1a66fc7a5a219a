"""The system C and C++ compilers for the tests that compile the generated firmware.

Without one, a test is skipped with the reason; with ``HAPTICAD_REQUIRE_CC=1`` (``.ci/run``
sets it and installs gcc and g++) it fails instead: no compiling test skips silently.
"""

from __future__ import annotations

import os
import shutil

import pytest


def compiler(lang: str = "c") -> str:
    """Path of ``cc``/``gcc`` (``lang="c"``) or ``g++``/``c++`` (``lang="c++"``)."""
    names = ("cc", "gcc") if lang == "c" else ("g++", "c++")
    found = next((p for p in map(shutil.which, names) if p), None)
    if found:
        return found
    why = f"no {lang.upper()} compiler ({'/'.join(names)}) on PATH (.ci/run installs gcc and g++)"
    if os.environ.get("HAPTICAD_REQUIRE_CC") == "1":
        pytest.fail(f"HAPTICAD_REQUIRE_CC=1 but {why}")
    pytest.skip(why)
