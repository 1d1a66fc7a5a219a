"""Studies over designs: fit, co-design, sweeps, tolerance (they drive the pipeline; nothing below imports them)."""
