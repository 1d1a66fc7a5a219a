"""The haptic pen's layout code (:mod:`cad.families`): the isotropy paper's 5-DOF
twin-pantograph pen (§4.2, Fig. 4, Table 2) with parts.

``assemble(design, fidelity="fabrication") -> AssemblyModel`` (:mod:`cad.families.pen.assembly`);
``build.py`` the build, ``datasheet.py`` its rows, ``sim.py`` its MJCF, ``design.py`` its
``[parts]`` schema, ``layout.py`` its numbers and body poses, ``parts.py`` its own part scripts.
"""

from cad.families.pen.assembly import assemble

__all__ = ["assemble"]
