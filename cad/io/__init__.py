"""Input/output helpers that import no CAD library."""
