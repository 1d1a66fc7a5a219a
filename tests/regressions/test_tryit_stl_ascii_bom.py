"""An ASCII STL saved with a UTF-8 byte-order mark (Windows editors) is ASCII (found by
trying, t1tester): it was taken for a binary STL and refused as "truncated: the header says
1919252000 triangles" -- the bytes "soli" read as a count. The 10 mm cube: 1000 mm^3 and
its centre (5, 5, 5) mm, closed forms."""

import numpy as np
import pytest

from cad.massprops.io import read_stl
from cad.massprops.mesh import mesh_arrays_mass_props

_V = np.array([[x, y, z] for x in (0, 10) for y in (0, 10) for z in (0, 10)], float)
_F = [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]


def _ascii(bom: bool) -> str:
    lines = ["solid cube"]
    for f in _F:
        lines += [" facet normal 0 0 0", "  outer loop",
                  *(f"   vertex {' '.join(f'{c:g}' for c in _V[i])}" for i in f),
                  "  endloop", " endfacet"]
    return ("\ufeff" if bom else "") + "\n".join([*lines, "endsolid cube", ""])


@pytest.mark.parametrize("bom", [False, True])
def test_ascii_stl_with_or_without_a_byte_order_mark(tmp_path, bom):
    p = tmp_path / "cube.stl"
    p.write_text(_ascii(bom), encoding="utf-8")
    warnings: list[str] = []
    v, f = read_stl(p, warnings)
    res = mesh_arrays_mass_props(v, f, 1000.0)
    assert warnings == [] and len(f) == 12
    assert res.volume_mm3 == pytest.approx(1000.0, rel=1e-12)
    np.testing.assert_allclose(np.asarray(res.props.com_m) * 1e3, [5, 5, 5], atol=1e-12)
