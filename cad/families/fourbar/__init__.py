"""The fourbar family's layout code (:mod:`cad.families`): :func:`assemble` lays out the
four-bar (:mod:`cad.families.fourbar.layout`), :mod:`.build` builds it through the shared
pipeline (:mod:`cad.pipeline.family`)."""

from cad.families.fourbar.layout import assemble

__all__ = ["assemble"]
