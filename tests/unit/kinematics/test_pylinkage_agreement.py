"""Our four-bar position solution (Hoeken paper eqs 1-10) against pylinkage's, an independent
planar-linkage solver (circle-circle intersections), on the same linkages.

pylinkage is in the ``test`` extra (pinned in constraints.txt): imported plainly, a missing
install is a failure, not a skip.
"""

import numpy as np
import pylinkage as pl
import pytest

from cad.bench.kinematics import pylinkage_linkage
from cad.kinematics.families import FAMILIES, family_linkage
from cad.kinematics.fourbar import solve


@pytest.mark.parametrize("family", list(FAMILIES))
def test_coupler_point_equals_pylinkage(family):
    """Every joint and the coupler point P over the paper's crank range, 200 poses: pylinkage
    (its pure-Python ``step``) equals ours to 1e-9 mm (both exact closed forms; the bound is
    float round-off on ~100 mm coordinates)."""
    fb, lo, hi = family_linkage(family)
    n = 200
    dphi = (hi - lo) / n
    rows = np.array(list(pylinkage_linkage(pl, fb, lo, dphi).step(iterations=n)))  # (n, 5, 2)
    ours = solve(fb, lo + dphi * (np.arange(n) + 1))  # pylinkage steps before it records
    assert rows.shape == (n, 5, 2)
    np.testing.assert_allclose(rows[:, 2], ours.A2_mm, rtol=0, atol=1e-9)
    np.testing.assert_allclose(rows[:, 3], ours.A3_mm, rtol=0, atol=1e-9)
    np.testing.assert_allclose(rows[:, 4], ours.P_mm, rtol=0, atol=1e-9)
