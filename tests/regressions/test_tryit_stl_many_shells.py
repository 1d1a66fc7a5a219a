"""A mesh of many shells (a tray of printed parts, a lattice of separate pieces).

Found by trying (t1tester): the shell nesting compared every pair of shells' bounding
boxes in a Python loop, k^2/2 pairs: 2000 separate 1 mm cubes (24,000 triangles) took
48 s in ``hapticad massprops`` and 8000 cubes (96,000 triangles) did not finish in
300 s, and its (k, k) matrix would need k^2 bytes. The values below are closed forms.
"""

import numpy as np
import pytest

from cad.massprops.mesh import mesh_arrays_mass_props

# the 12 outward triangles of the unit cube on vertices (x, y, z) in {0, 1}^3, index 4x+2y+z
_F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
               [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
_V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)


def _grid(n: int, side_mm: float, pitch_mm: float, inner_mm: float | None = None):
    """n^3 cubes of ``side_mm`` on a ``pitch_mm`` grid, each (with ``inner_mm``) holding a
    centred cube shell wound OUTWARDS (a cavity the file winds like a solid)."""
    corners = pitch_mm * np.array(np.meshgrid(*[np.arange(n)] * 3, indexing="ij")).reshape(3, -1).T
    parts = [(side_mm, corners)]
    if inner_mm is not None:
        parts.append((inner_mm, corners + (side_mm - inner_mm) / 2))
    vs, fs = [], []
    for side, cs in parts:
        for c in cs:
            fs.append(_F + 8 * len(vs))
            vs.append(_V * side + c)
    return np.vstack(vs), np.vstack(fs)


def _cube_izz(side_mm: float, rho: float) -> float:
    """Moment of a solid cube about an axis through its centre, kg m^2: m a^2 / 6."""
    a = side_mm * 1e-3
    return rho * a**3 * a * a / 6


def test_four_thousand_separate_cubes():
    """16^3 = 4096 separate 1 mm cubes on a 3 mm grid: 4096 mm^3, COM at the grid centre
    (3 * 7.5 + 0.5 = 23 mm), Izz = sum of a^2 m/6 + m (dx^2 + dy^2) (parallel axis), nothing noted."""
    n, rho = 16, 1000.0
    v, f = _grid(n, 1.0, 3.0)
    res = mesh_arrays_mass_props(v, f, rho)
    assert res.volume_mm3 == pytest.approx(n**3, rel=1e-12) and res.notes == ()
    np.testing.assert_allclose(np.asarray(res.props.com_m) * 1e3, [23.0] * 3, atol=1e-9)
    centres = 3.0 * np.arange(n) + 0.5 - 23.0  # mm, along one axis
    m1 = rho * 1e-9
    izz = n**3 * _cube_izz(1.0, rho) + m1 * 2 * n**2 * np.sum((centres * 1e-3) ** 2)
    np.testing.assert_allclose(res.props.principal_moments_kg_m2, [izz] * 3, rtol=1e-9)


def test_a_thousand_cubes_each_with_a_cavity_wound_outwards():
    """10^3 hollow 2 mm cubes (1 mm cavities written as solids): each cavity is read as one,
    (8 - 1) mm^3 each, 7000 mm^3 in all, one note per cavity."""
    v, f = _grid(10, 2.0, 3.0, inner_mm=1.0)
    res = mesh_arrays_mass_props(v, f, 1000.0)
    assert res.volume_mm3 == pytest.approx(7000.0, rel=1e-12)
    assert len(res.notes) == 1000 and all("read as a cavity" in s for s in res.notes)


def test_overlapping_pairs_equal_every_pair_compared():
    """The box pairs the sweep finds equal the brute-force pairs of seeded random boxes,
    touching boxes (a shared face: no volume in common) included as not overlapping."""
    from cad.massprops.shells import overlapping_pairs

    rng = np.random.default_rng(7)
    lo = rng.integers(0, 10, (300, 3)).astype(float)
    hi = lo + rng.integers(0, 4, (300, 3))  # zero-width boxes too; integer: many touch
    brute = sorted((i, j) for i in range(300) for j in range(i + 1, 300)
                   if np.all(lo[i] < hi[j]) and np.all(hi[i] > lo[j]))
    got = overlapping_pairs(lo, hi)
    assert got.shape == (len(brute), 2) and [tuple(p) for p in got.tolist()] == brute
    assert len(brute) > 100  # the boxes do overlap: the comparison is not empty
