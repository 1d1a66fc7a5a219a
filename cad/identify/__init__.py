"""Identification of a built device from a bench log (issue 37): pure numpy, no CAD import.

* :mod:`cad.identify.logfile` -- the public CSV log format (``t_s, counts_0[, counts_1 ...],
  current_A_0[, current_A_1 ...]`` after one ``#`` comment line naming the design hash):
  writer and parser, every bad log refused in one line (:class:`cad.errors.FileDamaged`);
* :mod:`cad.identify.excitation` -- the excitation the generated firmware runs (hand phase,
  position hold, a tapered chirp gated by the joint range, clamped at the continuous current),
  the Python reference of the C routine;
* :mod:`cad.identify.regression` -- the 1-DOF least-squares fit of a four-bar's crank
  dynamics (inertia, Coulomb and viscous friction, gravity scale and offset, delay, signs)
  with the covariance of every estimate;
* :mod:`cad.identify.excitation2` -- the 2-motor routine (the 5-bar pantograph): per-motor
  hold, chirps sweeping up on motor 0 and down on motor 1, the hold envelope, gravity
  feed-forward on a vertical device;
* :mod:`cad.identify.joint2` -- the 5-bar's 2-DOF fit: the tree of two arms closed by virtual
  work, linear in the inertial parameters; friction, offsets, gravity, delay and the signs
  per motor.

The device facts (predicted inertia table, motor constants, encoder) come in as plain arrays
and numbers; :mod:`cad.sim.identify_device` (four-bars) and :mod:`cad.sim.identify_fivebar`
(the 5-bar) read them from the resolved device.
"""
