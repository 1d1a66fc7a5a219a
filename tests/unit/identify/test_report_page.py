"""identify.md's verdict table (cad.report.identify.page): each row names the figure by its
key, as identify.json, the terminal table and docs/identify.md do, then its description."""

from __future__ import annotations

from cad.report.identify import page


def test_rows_name_the_key_then_the_description():
    res = {"design": "d", "figures": [
        {"key": "offset_x", "what": "constant generalized force along x", "value": 0.5,
         "unit": "mN m", "verdict": "ok"},
        {"key": "encoder_direction_2", "value": "as configured", "verdict": "ok"}]}
    rows = [ln for ln in page(res).splitlines() if ln.startswith("| `")]
    assert rows[0].startswith("| `offset_x` | constant generalized force along x | 0.5 |")
    assert rows[1].startswith("| `encoder_direction_2` |  | as configured |")
