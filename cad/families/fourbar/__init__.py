"""The fourbar family's layout code (:mod:`cad.families`)."""
