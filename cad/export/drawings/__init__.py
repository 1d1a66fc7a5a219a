"""Shop drawings of the made parts (issue 25 section 1): ``--formats …,drawings``.

One A4 sheet per made part, ``drawings/<part>.svg``, and every sheet in one multi-page
``drawings.pdf`` (matplotlib's PdfPages), drawn from the part's solid (views from
build123d's hidden-line projection, :mod:`cad.export.drawings.sheet`; features from its cylindrical
faces, :mod:`cad.export.drawings.features`; fit and thread texts, :mod:`cad.export.drawings.notes`; the stock the BOM orders, :func:`cad.pipeline.family.kind_stock`).
The files are byte-identical run to run (no dates, fixed SVG ids).
"""

from __future__ import annotations

import io
from pathlib import Path

from cad.export.drawings.sheet import SheetPart, draw_sheet
from cad.io.atomic import write_bytes_atomic

PDF_NAME = "drawings.pdf"
SVG_DIR = "drawings"

__all__ = ["PDF_NAME", "SVG_DIR", "SheetPart", "write_drawings"]


def write_drawings(parts: list[SheetPart], out_dir: Path, design: str) -> list[Path]:
    """``drawings/<part>.svg`` for each of ``parts`` and ``drawings.pdf`` (one page each, in
    that order) under ``out_dir``; returns the paths written (atomically)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.backends.backend_pdf import PdfPages

    out_dir = Path(out_dir)
    pdf_buf = io.BytesIO()
    written = []
    with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "hapticad",
                                "pdf.compression": 6}):
        with PdfPages(pdf_buf, metadata={"CreationDate": None, "Creator": "hapticad"}) as pdf:
            for k, part in enumerate(parts, 1):
                fig = draw_sheet(part, design, (k, len(parts)))
                svg = io.BytesIO()
                fig.savefig(svg, format="svg", metadata={"Date": None})
                pdf.savefig(fig)
                plt.close(fig)
                written.append(write_bytes_atomic(out_dir / SVG_DIR / f"{part.name}.svg",
                                                  svg.getvalue()))
    written.append(write_bytes_atomic(out_dir / PDF_NAME, pdf_buf.getvalue()))
    return written
