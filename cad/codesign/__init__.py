"""Co-design of a light four-bar: cheap mass model, optuna search, exact re-evaluation.

:mod:`cad.codesign.cheap` (numpy + catalog, no CAD) estimates every moving part's
mass, COM and inertia; :mod:`cad.codesign.search` runs the optuna study over
kinematics and hardware; :mod:`cad.codesign.exact` re-evaluates optima on the solids.
"""
