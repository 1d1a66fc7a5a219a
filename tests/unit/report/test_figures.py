"""Charts are byte-identical run to run (no dates, no random SVG ids, no version stamp)."""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from cad.report.figures import save_figure  # noqa: E402


def _fig():
    fig, ax = plt.subplots()
    ax.plot([0, 1, 2], [0, 1, 4], label="x")
    ax.fill_between([0, 1, 2], [0, 1, 2])  # clip paths: random ids without a salt
    ax.legend()
    return fig


def test_same_figure_same_bytes_in_every_format():
    for fmt in ("svg", "png", "pdf"):
        out = []
        for _ in range(2):
            fig, buf = _fig(), io.BytesIO()
            save_figure(fig, buf, fmt)
            plt.close(fig)
            out.append(buf.getvalue())
        assert out[0] == out[1], fmt
    fig, buf = _fig(), io.BytesIO()
    save_figure(fig, buf, "svg")
    plt.close(fig)
    text = buf.getvalue().decode()
    assert "<dc:date>" not in text
    fig, buf = _fig(), io.BytesIO()
    save_figure(fig, buf, "png")
    plt.close(fig)
    assert b"matplotlib" not in buf.getvalue()  # no version stamp: a fixed creator mark only
    assert b"Software\x00hapticad" in buf.getvalue()
