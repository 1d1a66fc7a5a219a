"""The sweep's pose skipping is safe: the bounding-box bounds never exceed the mesh distance,
and the bounded pass measures every pose a brute-force pass finds near (zero misses) and
finds the same per-pair minimum.

References: python-fcl's mesh distance at every pose (brute force); the closed-form gap of
parts separated along z (planar motion keeps z).
"""

from __future__ import annotations

import fcl  # noqa: F401  (python-fcl is a hard dependency, pyproject.toml: a missing one fails)
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cad.assembly import interference as itf


def _planar(theta, x, y):
    T = np.repeat(np.eye(4)[None], len(theta), axis=0)
    c, s = np.cos(theta), np.sin(theta)
    T[:, 0, 0], T[:, 0, 1], T[:, 1, 0], T[:, 1, 1] = c, -s, s, c
    T[:, 0, 3], T[:, 1, 3] = x, y
    return T


@pytest.fixture(scope="module")
def parts():
    from build123d import Align, Box, Cylinder, Pos

    bar = (Box(40, 8, 4, align=(Align.MIN, Align.CENTER, Align.MIN))).solids()[0].wrapped
    pin = (
        (Pos(0, 0, 5) * Cylinder(3, 6, align=(Align.CENTER, Align.CENTER, Align.MIN)))
        .solids()[0]
        .wrapped
    )
    eye = np.eye(4)
    prep = itf.prepare(
        [("bar", "a", bar, eye), ("pin", "b", pin, eye), ("bar2", "b", bar, eye)], 0.05
    )
    return prep


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_box_bounds_are_lower_bounds_of_the_mesh_distance(parts, seed):
    rng = np.random.default_rng(seed)
    n = 6
    Ta = _planar(rng.uniform(-np.pi, np.pi, n), rng.uniform(-30, 30, n), rng.uniform(-30, 30, n))
    Tb = _planar(rng.uniform(-np.pi, np.pi, n), rng.uniform(-30, 30, n), rng.uniform(-30, 30, n))
    pa, pb = parts.bodies["a"], parts.bodies["b"]
    lb = itf.box_lower_bounds(pa, pb, Ta, Tb)
    for i in range(n):
        d = min(itf._part_mesh_distance(p, q, Ta[i], Tb[i]) for p in pa for q in pb)
        assert lb[i] <= d + 1e-9


def test_box_bound_of_parts_stacked_in_z_is_the_z_gap(parts):
    """The pin (z 5..11) rides above the turning bar (z 0..4): 1 mm apart at every pose."""
    n = 16
    theta = np.linspace(0, np.pi, n)
    Ta = _planar(theta, np.zeros(n), np.zeros(n))
    Tb = _planar(-theta, 20.0 * np.cos(theta), 20.0 * np.sin(theta))
    pin = [p for p in parts.bodies["b"] if p.name == "pin"]
    lb = itf.box_lower_bounds(parts.bodies["a"], pin, Ta, Tb)
    d = [itf._part_mesh_distance(parts.bodies["a"][0], pin[0], Ta[i], Tb[i]) for i in range(n)]
    np.testing.assert_allclose(lb, 1.0, atol=1e-12)
    np.testing.assert_allclose(d, 1.0, atol=1e-9)


@pytest.mark.parametrize("n_poses", [41, 200])
def test_bounded_pass_measures_every_near_pose_of_the_brute_force(n_poses):
    """The bench's cylinder scene (closed-form gaps -0.2 .. 0.5 mm): at every pose the brute
    force distance; the bounded pass must measure each pose below the near threshold, agree
    where it measures, bound from below where it skips, and find the same minimum."""
    from cad.bench.interference import CONTACT_CLEARANCE_MM, interference_scene

    items, tfs, _ = interference_scene(n_poses)
    prep = itf.prepare(items, itf.SWEEP_MESH_TOL_MM)
    threshold = CONTACT_CLEARANCE_MM + 2 * prep.mesh_tol_mm + itf.CONFIRM_MARGIN_MM
    scene = itf._FclScene(prep, np.inf)
    bodies = sorted(prep.bodies)
    for a in bodies:
        for b in bodies:
            if a >= b or a[1:] != b[1:]:
                continue  # the scene's pairs: f<k> against m<k>
            Ta, Tb = tfs[a], tfs[b]
            brute = np.array([scene.distance(a, b, Ta[i], Tb[i]) for i in range(len(Ta))])
            d, measured = itf.bounded_pair_distances(
                scene, a, b, Ta, Tb, lambda m: max(threshold, m)
            )
            assert measured[brute < threshold].all()
            np.testing.assert_allclose(d[measured], brute[measured], rtol=0, atol=1e-12)
            assert (d[~measured] <= brute[~measured] + 1e-9).all()
            assert float(d[measured].min()) == pytest.approx(float(brute.min()), abs=1e-12)
