"""The pantograph family's layout code (:mod:`cad.families`)."""
