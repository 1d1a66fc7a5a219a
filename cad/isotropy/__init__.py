"""Global isotropy index (GII) and the culling optimizer (isotropy paper §3, eqs 1-6).

Pure numpy: no CAD import. :mod:`cad.isotropy.gii` evaluates the GII of one
design over a sampled workspace; :mod:`cad.isotropy.culling` maximizes it over a
discrete candidate set (Stocco, Salcudean & Sassani 1998) and by brute force;
:mod:`cad.isotropy.problems` states the pantograph, twin-pantograph and
haptic-pen problems in the form both optimizers take.
"""
