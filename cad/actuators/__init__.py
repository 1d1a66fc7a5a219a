"""Actuator physics: flat voice-coil (Lorentz) actuators and the PowerMouse wrench map.

Pure numpy/scipy. magpylib is imported lazily inside functions of
:mod:`cad.actuators.field_magpylib`; no CAD library is ever imported here.

Modules
-------
voicecoil: eq (8) force per unit power, eq (9) gap field (derived in its
    docstring), the two-plate image series, gap and (d, t_m, w_m, l_m)
    optimisers, force along the stroke over the real coil volume.
field_magpylib: the same gap with magpylib's exact cuboid fields (back iron
    as image magnets; finite-permeability iron via the optional
    magpylib-material-response).
powermouse: cubic flotor with six flat coils, 6x6 current-to-wrench map,
    isotropy, peak acceleration, motion-range clearances.
"""
