"""Pure-numpy kinematics (no CAD imports): four-bar straight-line linkages.

Modules: :mod:`fourbar` (Hoeken paper eqs 1-12), :mod:`linkgeom` (joint
positions in link frames, link poses), :mod:`families` (paper Fig. 2 table),
:mod:`metrics` (Tables I and II), :mod:`synthesis` (link-length optimizer).
"""
