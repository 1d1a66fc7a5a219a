"""``cad.api.assemble(design)`` -> :class:`cad.assembly.model.AssemblyModel` and its
``compound()``: a labelled, coloured build123d ``Compound``, one child per part instance at its
world transform, that build123d's ``export_step`` writes with those names (issue 23 §2).

References: closed-form volumes of the turned rings and spacers (annulus, minus the two 45 deg
bore chamfers by Pappus' theorem), the world placement of their centroids computed from the
transforms by hand, the material table's colours, and the STEP file read back by OCP's own
STEP reader (solids, volumes) and build123d's importer (names).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import cad
from cad.data import families as registry
from cad.families import family_package
from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[2]
#: One bundled design per family of the registry.
BUNDLED = {"hoeken": "hoeken.toml", "roberts": "roberts.toml", "chebyshev": "chebyshev.toml",
           "chebyshev-v": "chebyshev_v.toml", "custom": "custom_example.toml",
           "pantograph": "pantograph.toml", "twin-pantograph": "haptic_mouse.toml",
           "haptic-pen": "haptic_pen.toml", "powermouse": "powermouse.toml",
           "delta": "delta.toml"}
WITH_PARTS = [n for n in registry.FAMILIES if family_package(n).assemble is not None]


def _rot_z(a: float) -> np.ndarray:
    T = np.eye(4)
    T[:2, :2] = [[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]
    return T


R_IN, R_OUT, H_RING, H_SPACER, R_SPACER = 4.0, 8.0, 3.0, 5.0, 9.0


def _ring_volume() -> float:
    return math.pi * (R_OUT**2 - R_IN**2) * H_RING


def _spacer_volume() -> float:
    """Annulus minus two chamfer rings: triangle c^2/2 revolved at r_in + c/3 (Pappus)."""
    from cad.parts.joints import SPACER_BORE_CHAMFER_MM as c

    return math.pi * (R_SPACER**2 - R_IN**2) * H_SPACER - 2 * 2 * math.pi * (R_IN + c / 3) * c**2 / 2


@pytest.fixture(scope="module")
def model():
    """Two bodies, three instances (one kind twice), from the real part scripts."""
    from cad.assembly.model import AssemblyModel
    from cad.parts import PartInstance, PartKind, translation
    from cad.parts.joints import ring_shape, spacer_shape

    ring = PartKind("ring_4-8-3", ring_shape(R_IN, R_OUT, H_RING), "stainless-304", True)
    spacer = PartKind("spacer_4-9-5", spacer_shape(R_IN, R_SPACER, H_SPACER), "delrin", True)
    design = type("D", (), {"name": "two_bodies"})()
    return AssemblyModel(
        design=design,
        instances=(PartInstance("ring_A1", ring, "ground", translation(0, 0, 0)),
                   PartInstance("ring_A4", ring, "ground", translation(40, 0, 0)),
                   PartInstance("spacer_A2", spacer, "crank", translation(20, 0, 5))),
        tf_world_body={"ground": np.eye(4), "crank": _rot_z(0.3) @ translation(0, 0, 10)},
        motion={"crank": np.stack([_rot_z(a) @ translation(0, 0, 10) for a in (0.3, 1.2)])},
        pose_labels=("phi1 = 17.2 deg", "phi1 = 68.8 deg"),
    )


def _centroid(shape) -> np.ndarray:
    c = shape.center()  # build123d: centre of mass
    return np.array([c.X, c.Y, c.Z])


def test_compound_children_labels_colours_volumes_and_placement(model):
    from cad.data.materials import get_material

    cp = model.compound()
    kids = list(cp.children)
    assert len(kids) == len(model.instances) == 3
    assert [k.label for k in kids] == ["ring_A1", "ring_A4", "spacer_A2"]
    assert cp.label == "two_bodies"
    want = [_ring_volume(), _ring_volume(), _spacer_volume()]
    for k, inst, v in zip(kids, model.instances, want, strict=True):
        assert k.volume == pytest.approx(v, rel=1e-9)  # closed form
        assert k.volume == pytest.approx(_occ_volume(inst.kind.shape), rel=1e-12)  # its kind
        rgb = get_material(inst.kind.material).color_rgb
        assert tuple(k.color)[:3] == pytest.approx(rgb, abs=1e-6)
    # placement: the part-frame centroid (0, 0, h/2) carried by tf_world_body @ tf_body_part
    ring_a4 = np.array([40.0, 0.0, H_RING / 2])
    assert _centroid(kids[1]) == pytest.approx(ring_a4, abs=1e-9)
    a = 0.3
    x, y = 20 * math.cos(a), 20 * math.sin(a)
    assert _centroid(kids[2]) == pytest.approx([x, y, 10 + 5 + H_SPACER / 2], abs=1e-9)


def test_compound_at_a_pose_of_the_motion(model):
    kids = list(model.compound(pose=1).children)
    a = 1.2
    assert _centroid(kids[2]) == pytest.approx([20 * math.cos(a), 20 * math.sin(a), 17.5], abs=1e-9)
    assert _centroid(kids[0]) == pytest.approx([0, 0, 1.5], abs=1e-9)  # ground: not moved
    with pytest.raises(DesignError, match="pose"):
        model.compound(pose=2)


def _occ_volume(shape) -> float:
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    g = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, g)
    return g.Mass()


def test_export_step_reads_back_with_the_same_solids_volumes_and_names(model, tmp_path):
    """build123d's export_step of the compound, read by OCP's STEP reader (solids, volumes)
    and by build123d's importer (names): two instances of one kind keep their own names."""
    from build123d import export_step, import_step
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    cp = model.compound()
    path = tmp_path / "two_bodies.step"
    assert export_step(cp, str(path))
    reader = STEPControl_Reader()
    assert reader.ReadFile(str(path)) == IFSelect_RetDone
    reader.TransferRoots()
    exp, vols = TopExp_Explorer(reader.OneShape(), TopAbs_SOLID), []
    while exp.More():
        vols.append(_occ_volume(exp.Current()))
        exp.Next()
    assert sorted(vols) == pytest.approx(sorted(k.volume for k in cp.children), rel=1e-9)
    assert sum(vols) == pytest.approx(2 * _ring_volume() + _spacer_volume(), rel=1e-9)
    back = import_step(str(path))
    assert sorted(c.label for c in back.children) == ["ring_A1", "ring_A4", "spacer_A2"]


def test_unknown_fidelity_and_family_without_parts_are_design_errors(monkeypatch):
    d = cad.load_design(ROOT / "designs" / "hoeken.toml")
    with pytest.raises(DesignError) as exc:
        cad.assemble(d, fidelity="sketch")
    assert exc.value.field == "fidelity"
    row = registry.FAMILIES["hoeken"]
    monkeypatch.setitem(registry.FAMILIES, "hoeken", dataclasses.replace(row, package=None))
    with pytest.raises(DesignError) as exc:
        cad.assemble(d)
    assert exc.value.field == "mechanism.family" and "no parts" in str(exc.value)


def test_a_package_without_assemble_is_a_design_error(monkeypatch):
    import dataclasses
    import importlib

    row = registry.FAMILIES["hoeken"]
    pkg = importlib.import_module(row.package_module)
    monkeypatch.setattr(pkg, "FAMILY", dataclasses.replace(pkg.FAMILY, assemble=None))
    with pytest.raises(DesignError) as exc:
        cad.assemble(cad.load_design(ROOT / "designs" / "hoeken.toml"))
    assert exc.value.field == "mechanism.family" and "no parts" in str(exc.value)


def test_every_family_in_the_registry_has_a_bundled_design():
    assert set(BUNDLED) == set(registry.FAMILIES)
    for name, file in BUNDLED.items():
        assert cad.load_design(ROOT / "designs" / file).family == name


@pytest.mark.parametrize("family", WITH_PARTS)
def test_assemble_every_family_with_parts(family):
    """Each family's ``assemble`` (written in parallel by the family owners): an AssemblyModel
    of the design, every instance's body placed, and a compound with one labelled child per
    instance whose volumes are the instances' kinds' solid volumes."""
    from cad.assembly.model import AssemblyModel

    d = cad.load_design(ROOT / "designs" / BUNDLED[family])
    m = cad.assemble(d, fidelity="preview")
    assert isinstance(m, AssemblyModel) and m.design is d and m.instances
    assert set(m.bodies) <= set(m.tf_world_body)
    cp = m.compound()
    kids = list(cp.children)
    assert [k.label for k in kids] == [i.name for i in m.instances]
    assert len({i.name for i in m.instances}) == len(m.instances)  # names are unique
    for k, inst in zip(kids, m.instances, strict=True):
        assert k.volume == pytest.approx(_occ_volume(inst.kind.shape), rel=1e-9)
