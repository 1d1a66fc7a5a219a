"""One exception root for hapticad.

Every error the tool raises on purpose derives from :class:`HapticadError`.
Errors caused by bad input also derive from :class:`ValueError`. The CLI turns
any :class:`HapticadError` into one line on stderr and exit code 2
(:class:`TargetMissed` is the exception: exit code 1).

Messages quote the value received and, where one exists, the fix.
"""

from __future__ import annotations


class HapticadError(Exception):
    """Root of every error hapticad raises on purpose."""


class DesignError(HapticadError, ValueError):
    """A design file or a parameter is invalid.

    ``field`` names the offending key (dotted TOML path, e.g.
    ``mechanism.l1_mm``); the message says why.
    """

    def __init__(self, field: str, reason: str):
        self.field = field
        self.reason = reason
        super().__init__(f"{field}: {reason}")


class KinematicsError(HapticadError, ValueError):
    """A linkage cannot do what was asked (closure, toggle, branch jump)."""


class ClosureError(KinematicsError):
    """The loop cannot close: |C| > sqrt(A^2 + B^2) for some phi1 (eqs 4-6)."""


class ToggleError(KinematicsError):
    """A toggle (sin(phi2 - phi3) -> 0) lies inside the requested range."""


class BranchJumpError(KinematicsError):
    """The assembly mode changes inside the requested range."""


class SingularJacobianError(HapticadError, ValueError):
    """A Jacobian is singular or too ill-conditioned to invert."""


class GeometryError(HapticadError, ValueError):
    """A part cannot be built from its parameters (or a boolean failed)."""


class MeshError(HapticadError, ValueError):
    """A mesh is unusable for the requested computation (e.g. not watertight)."""


class InterferenceError(HapticadError):
    """Parts of an assembly collide somewhere in the stroke."""


class TargetMissed(HapticadError):
    """A computed quantity is outside its target tolerance (CLI exit 1)."""


class FileRefused(DesignError):
    """A file hapticad was asked to read is refused before it is parsed (:mod:`cad.io.guard`):
    not a regular file, over its size limit, nested too deep, or not valid for its kind.

    ``field`` names where the file came from (a flag or design key), ``path`` the file,
    ``why`` the reason; the message is ``"<field>: <path> <why>"``.
    """

    def __init__(self, field: str, path, why: str):
        self.path = str(path)
        self.why = why
        super().__init__(field, f"{path} {why}")


class FileDamaged(FileRefused):
    """A regular file within its limits whose content is not valid for its kind (not UTF-8,
    not valid JSON or TOML): a reader that treats a damaged file as absent catches this one
    and lets every other :class:`FileRefused` (a FIFO, a device, too large) through."""
