"""Deterministic figure files: same figure -> same bytes (SPEC "Trust": same design ->
byte-identical outputs). The file writer of :mod:`cad.report.figures`, here so that the math
layers' studies (:mod:`cad.isotropy`) write charts without importing the report layer.

Matplotlib stamps SVGs with a date and random element ids and PNGs with its version;
:func:`save_figure` writes without either (a fixed ``svg.hashsalt``, no ``Date``, no
``Software``), so charts can be compared and cached by hash.
"""

from __future__ import annotations

#: Metadata that would differ between runs or matplotlib versions, per format.
#: Every chart names hapticad as its creator (a fixed text: :func:`written_by_hapticad`
#: tells our charts from a user's file of the same name before one is replaced).
NO_STAMPS = {
    "svg": {"Date": None, "Creator": "hapticad"},
    "png": {"Software": "hapticad"},
    "pdf": {"CreationDate": None, "Creator": "hapticad"},
}


def save_figure(fig, target, fmt: str | None = None, **kwargs) -> None:
    """``fig.savefig(target, format=fmt, **kwargs)`` without time stamps or random ids.

    ``target``: a path or a binary file object; ``fmt``: "png", "svg", "pdf" (default:
    from the path's suffix, else png).
    """
    import matplotlib

    if fmt is None:
        suffix = str(getattr(target, "name", target)).rsplit(".", 1)[-1].lower()
        fmt = suffix if suffix in NO_STAMPS else "png"
    meta = {**NO_STAMPS.get(fmt, {}), **kwargs.pop("metadata", {})}
    with matplotlib.rc_context({"svg.hashsalt": "hapticad"}):
        fig.savefig(target, format=fmt, metadata=meta, **kwargs)
