import os

from hypothesis import settings

settings.register_profile("ci", deadline=None, derandomize=True, max_examples=60)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


import pytest  # noqa: E402


@pytest.fixture(scope="session")
def hoeken_sim_build(tmp_path_factory):
    """The bundled Hoeken built with the simulator formats (preview fidelity: same mass
    properties as inertia), shared by tests/test_sim_export.py and tests/test_wall.py."""
    import json
    from pathlib import Path

    from cad.build import build_design
    from cad.design import load_design

    out = tmp_path_factory.mktemp("hoeken_sim")
    d = load_design(Path(__file__).resolve().parents[1] / "designs" / "hoeken.toml")
    rep = build_design(d, out, {"mjcf", "urdf", "stl"}, fidelity="preview", use_cache=False)
    return d, out, json.loads((out / "report.json").read_text()), rep
