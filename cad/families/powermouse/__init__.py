"""The powermouse family's layout code (:mod:`cad.families`)."""
