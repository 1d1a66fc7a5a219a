"""Data hapticad reads, not computes: the part catalog (:mod:`cad.data.catalog`), materials
(:mod:`cad.data.materials`), ISO 286 fits and shop allowances (:mod:`cad.data.fits`) and the
one family registry (:mod:`cad.data.families`). No CAD import."""
