"""Co-design of a light four-bar: cheap mass model, optuna search, exact re-evaluation.

:mod:`cad.studies.codesign.cheap` (numpy + catalog, no CAD) estimates every moving part's
mass, COM and inertia; :mod:`cad.studies.codesign.search` runs the optuna study over
kinematics and hardware; :mod:`cad.studies.codesign.exact` re-evaluates optima on the solids.
"""
