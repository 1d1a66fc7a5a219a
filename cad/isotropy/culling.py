"""Maximize the GII over a discrete candidate set: culling and brute force.

Problem (isotropy paper eq 6): p* = argmax_{p in P} GII(p), with
GII(p) = min_x sigma_min(J_hat(p, x)) / max_x sigma_max(J_hat(p, x)) over a
finite set of workspace samples x (eq 5).

Culling (Stocco, Salcudean & Sassani 1998, "Fast constrained global minimax
optimization of robot parameters", Robotica 16:595-605), as implemented here:

* After any subset of the workspace samples has been evaluated for a
  candidate, its partial ratio  min sigma_min / max sigma_max  over that subset
  is an UPPER bound on its GII: more samples can only lower the numerator
  and raise the denominator.
* A candidate evaluated at every sample has an exact GII; the best such value
  is a LOWER bound on the optimum.
* Any candidate whose upper bound is strictly below the best lower bound is
  culled: it cannot be (or tie with) the optimum.
* Which candidate to complete next: the one with the highest upper bound.
  Its worst samples (where its sigma_min was smallest and its sigma_max
  largest) are then evaluated for every surviving candidate first, since
  the worst points of one design tend to be the worst of its neighbours;
  that is what culls the field quickly.
* An upper bound of exactly 0 means GII = 0 exactly (a sample failed).

Exactness: the optimum, and every candidate tying with it, is never culled,
so both methods return the same index (ties go to the lowest index, like
``numpy.argmax``) and the same GII bit for bit (min and max are exact, and
each (candidate, sample) value is computed elementwise, independent of
batching). Both count Jacobian evaluations: one per (candidate, sample) pair.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from cad.errors import DesignError
from cad.isotropy.gii import gii_ratio


class MinimaxProblem(Protocol):
    """What both optimizers need from a problem (see :mod:`cad.isotropy.problems`)."""

    n_candidates: int
    n_points: int

    def sigma(self, cand: np.ndarray, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """sigma_min, sigma_max of J_hat for pairs (cand[k], point[k]); both 0 where
        the point is unreachable or singular for that candidate."""
        ...

    def point_order(self) -> np.ndarray:
        """A permutation of the samples; culling tries them in this order."""
        ...

    def seed_points(self) -> np.ndarray:
        """A few samples every candidate is evaluated at first."""
        ...


@dataclass(frozen=True)
class OptimizeResult:
    """Outcome of a GII maximization.

    best_index: index of p* in the candidate set; gii: GII(p*);
    jacobian_evaluations: (candidate, sample) pairs evaluated;
    wall_time_s: elapsed time; candidates_completed: candidates evaluated at
    every sample; gii_all: (M,) GII of every candidate (brute force only).
    """

    method: str
    best_index: int
    gii: float
    jacobian_evaluations: int
    wall_time_s: float
    n_candidates: int
    n_points: int
    candidates_completed: int
    gii_all: np.ndarray | None = None

    @property
    def brute_force_evaluations(self) -> int:
        """n_candidates * n_points: what brute force evaluates."""
        return self.n_candidates * self.n_points


def _check(problem) -> tuple[int, int]:
    M, N = int(problem.n_candidates), int(problem.n_points)
    if M < 1:
        raise DesignError("optimize", "the candidate set is empty")
    if N < 1:
        raise DesignError("workspace", "no workspace samples")
    return M, N


def checked_sigma(problem, ci: np.ndarray, pi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``problem.sigma(ci, pi)`` after checking 0 <= sigma_min <= sigma_max < inf.

    Singular values are finite and non-negative by definition; anything else
    (a NaN from a kernel, a negative value) would make the argmax of eq (6)
    meaningless and brute force and culling disagree, so it is a
    :class:`DesignError` naming the candidate and the sample.
    """
    s0, s1 = problem.sigma(ci, pi)
    s0 = np.asarray(s0, dtype=float)
    s1 = np.asarray(s1, dtype=float)
    if s0.shape != ci.shape or s1.shape != ci.shape:
        raise DesignError(
            "optimize", f"sigma returned shapes {s0.shape}, {s1.shape} for {ci.shape} pairs"
        )
    with np.errstate(invalid="ignore"):
        bad = ~(np.isfinite(s0) & np.isfinite(s1) & (s0 >= 0.0) & (s0 <= s1))
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise DesignError(
            "optimize",
            f"candidate {int(ci[k])} at workspace sample {int(pi[k])}: sigma_min = {s0[k]!r}, "
            f"sigma_max = {s1[k]!r}; singular values must satisfy 0 <= sigma_min <= sigma_max < inf",
        )
    return s0, s1


def brute_force(problem: MinimaxProblem, chunk_pairs: int = 250_000) -> OptimizeResult:
    """Evaluate every candidate at every sample; argmax of the GII (first on ties)."""
    t0 = time.perf_counter()
    M, N = _check(problem)
    smin = np.full(M, np.inf)
    smax = np.zeros(M)
    per = max(1, chunk_pairs // N)
    pts = np.arange(N)
    for c0 in range(0, M, per):
        c = np.arange(c0, min(M, c0 + per))
        ci = np.repeat(c, N)
        pi = np.tile(pts, c.size)
        s0, s1 = checked_sigma(problem, ci, pi)
        smin[c] = s0.reshape(c.size, N).min(axis=1)
        smax[c] = s1.reshape(c.size, N).max(axis=1)
    g = gii_ratio(smin, smax)
    best = int(np.argmax(g))
    return OptimizeResult(
        method="brute",
        best_index=best,
        gii=float(g[best]),
        jacobian_evaluations=M * N,
        wall_time_s=time.perf_counter() - t0,
        n_candidates=M,
        n_points=N,
        candidates_completed=M,
        gii_all=g,
    )


class _State:
    """Running bounds of every candidate during culling."""

    def __init__(self, problem, M: int, N: int):
        self.problem = problem
        self.N = N
        self.smin = np.full(M, np.inf)
        self.smax = np.zeros(M)
        self.imin = np.full(M, -1)
        self.imax = np.full(M, -1)
        self.n_eval = np.zeros(M, dtype=np.int64)
        self.evaluated = np.zeros((M, N), dtype=bool)
        self.evaluations = 0

    def evaluate(self, ci: np.ndarray, pi: np.ndarray) -> None:
        if ci.size == 0:
            return
        s0, s1 = checked_sigma(self.problem, ci, pi)
        self.evaluations += int(ci.size)
        self.evaluated[ci, pi] = True
        np.add.at(self.n_eval, ci, 1)
        # group minimum of sigma_min per candidate (with the sample index)
        order = np.lexsort((s0, ci))
        cs = ci[order]
        first = np.r_[True, cs[1:] != cs[:-1]]
        c_u, v, p = cs[first], s0[order][first], pi[order][first]
        better = v < self.smin[c_u]
        self.smin[c_u[better]] = v[better]
        self.imin[c_u[better]] = p[better]
        # group maximum of sigma_max
        order = np.lexsort((-s1, ci))
        cs = ci[order]
        first = np.r_[True, cs[1:] != cs[:-1]]
        c_u, v, p = cs[first], s1[order][first], pi[order][first]
        better = v > self.smax[c_u]
        self.smax[c_u[better]] = v[better]
        self.imax[c_u[better]] = p[better]

    def upper(self, idx=None) -> np.ndarray:
        if idx is None:
            return np.where(self.n_eval > 0, gii_ratio(self.smin, self.smax), np.inf)
        return np.where(self.n_eval[idx] > 0, gii_ratio(self.smin[idx], self.smax[idx]), np.inf)


def culling(problem: MinimaxProblem, chunk: int | None = None) -> OptimizeResult:
    """Culling optimizer (Stocco et al. 1998); same optimum as :func:`brute_force`.

    chunk: samples evaluated at a time while completing one candidate (it may be
    culled between chunks); default max(4, N // 16).
    """
    t0 = time.perf_counter()
    M, N = _check(problem)
    st = _State(problem, M, N)
    order = np.asarray(problem.point_order(), dtype=np.int64)
    if chunk is None:
        chunk = max(4, N // 16)
    alive = np.ones(M, dtype=bool)
    complete = np.zeros(M, dtype=bool)
    best, best_gii = -1, -np.inf
    queued = np.zeros(N, dtype=bool)
    pending = [int(p) for p in np.asarray(problem.seed_points()).reshape(-1)]
    completed = 0

    def cull() -> None:
        nonlocal alive
        alive &= ~(st.upper() < best_gii)

    while True:
        pending = [p for p in dict.fromkeys(pending) if not queued[p]]
        if pending:
            P = np.asarray(pending, dtype=np.int64)
            queued[P] = True
            pending = []
            open_ = np.flatnonzero(alive & ~complete)
            need = ~st.evaluated[np.ix_(open_, P)]
            r, k = np.nonzero(need)
            st.evaluate(open_[r], P[k])
            # an upper bound of 0 is an exact GII of 0
            zero = alive & ~complete & (st.n_eval > 0) & (st.upper() <= 0.0)
            for c in np.flatnonzero(zero):
                complete[c] = True
                if 0.0 > best_gii or (0.0 == best_gii and c < best):
                    best, best_gii = int(c), 0.0
            cull()
        open_ = np.flatnonzero(alive & ~complete)
        if open_.size == 0:
            break
        ub = st.upper(open_)
        c = int(open_[int(np.argmax(ub))])
        rest = order[~st.evaluated[c, order]]
        for k0 in range(0, rest.size, chunk):
            P = rest[k0 : k0 + chunk]
            st.evaluate(np.full(P.size, c), P)
            u = float(st.upper(np.array([c]))[0])
            if u < best_gii or u <= 0.0:
                break
        u = float(st.upper(np.array([c]))[0])
        if st.n_eval[c] == N or u <= 0.0:
            complete[c] = True
            completed += int(st.n_eval[c] == N)
            if u > best_gii or (u == best_gii and c < best):
                best, best_gii = c, u
        pending.extend([int(st.imin[c]), int(st.imax[c])])
        cull()

    return OptimizeResult(
        method="culling",
        best_index=int(best),
        gii=float(best_gii),
        jacobian_evaluations=st.evaluations,
        wall_time_s=time.perf_counter() - t0,
        n_candidates=M,
        n_points=N,
        candidates_completed=completed,
    )


def optimize(problem: MinimaxProblem, method: str) -> OptimizeResult:
    """Dispatch on ``method`` ("culling" or "brute")."""
    if method == "culling":
        return culling(problem)
    if method == "brute":
        return brute_force(problem)
    raise DesignError("method", f"must be 'culling' or 'brute', got {method!r}")
