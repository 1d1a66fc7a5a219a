"""The ``[firmware]`` table of a design: what ``hapticad build --formats firmware`` needs
beyond the mechanism (issue 26). Every key is optional::

    [firmware]
    plane = "horizontal"            # or "vertical": gravity acts in the mechanism plane
    gravity_direction = [0, -1]     # unit direction of g in the device frame (vertical only)
    encoder_counts_per_rev = 2000   # quadrature counts per motor turn (default: the BOM's encoder)
    encoder_direction = 1           # +1 / -1, or one per motor: sign of counts vs joint angle
    encoder_zero_deg = 174.0        # joint angle at count 0, or one per motor (default: home)
    wall_stiffness_N_per_m = 1000   # the example sketch's virtual wall (default: stable range)
    wall_damping_N_s_per_m = 0.5

``encoder_counts_per_rev`` is one of the three ways to state the device's encoder (with
``parts.encoder`` and ``parts.encoder_counts_per_rev``); None when not given. The count the
firmware is compiled for is the resolved device's (:func:`cad.device.resolve_device`): the
encoder the BOM orders; two fields that disagree are refused there. Family defaults come from
the papers: the Hoeken prototype's "general purpose 2000 counts/rev optical encoder" (Hoeken
paper §III.A) for four-bars, the pantograph devices' "1000 window (4000 cpt) optical encoder"
(isotropy paper §3.2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from cad.design.fields import check_unknown, optional_int, optional_number
from cad.errors import DesignError

KEYS = ("plane", "gravity_direction", "encoder_counts_per_rev", "encoder_direction",
        "encoder_zero_deg", "wall_stiffness_N_per_m", "wall_damping_N_s_per_m")
PLANES = ("horizontal", "vertical")
#: Hoeken paper §III.A: "A general purpose 2000 counts/rev optical encoder is used."
FOURBAR_COUNTS_PER_REV = 2000
#: Isotropy paper §3.2: "a 1000 window (4000 cpt) optical encoder".
PANTOGRAPH_COUNTS_PER_REV = 4000
COUNTS_MAX = 10**9


@dataclass(frozen=True)
class FirmwareOptions:
    """Validated ``[firmware]`` table. ``encoder_counts_per_rev`` None = not stated (the
    resolved device's encoder); ``encoder_zero_deg`` None = the home pose's angles;
    ``gravity_direction`` is a unit (x, y) vector in the device frame."""

    plane: str = "horizontal"
    gravity_direction: tuple[float, float] = (0.0, -1.0)
    encoder_counts_per_rev: int | None = None
    encoder_direction: tuple[int, ...] = (1,)
    encoder_zero_deg: tuple[float, ...] | None = None
    wall_stiffness_N_per_m: float | None = None
    wall_damping_N_s_per_m: float | None = None

    @property
    def vertical(self) -> bool:
        return self.plane == "vertical"


def _per_motor(tab: dict, key: str, n: int, check) -> tuple | None:
    if key not in tab:
        return None
    v = tab[key]
    vals = v if isinstance(v, list) else [v] * n
    if len(vals) != n:
        raise DesignError(f"firmware.{key}", f"must be one value or a list of {n} (one per motor), "
                          f"got {len(vals)} values")
    return tuple(check(x) for x in vals)


def parse_firmware(tab: dict[str, Any], n_motors: int) -> FirmwareOptions:
    """Validate the ``[firmware]`` table for a device with ``n_motors`` motors."""
    check_unknown(tab, KEYS, "firmware")
    plane = tab.get("plane", "horizontal")
    if plane not in PLANES:
        raise DesignError("firmware.plane", f"must be one of {', '.join(PLANES)}, got {plane!r}")
    g = tab.get("gravity_direction", [0.0, -1.0])
    if (not isinstance(g, list) or len(g) != 2
            or not all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in g)
            or not all(math.isfinite(c) for c in g) or math.hypot(*g) == 0):
        raise DesignError("firmware.gravity_direction", f"must be a non-zero [x, y], got {g!r}")
    n = math.hypot(*g)
    counts = optional_int(tab, "encoder_counts_per_rev", "firmware", None, minimum=1)
    if counts is not None and counts > COUNTS_MAX:
        raise DesignError("firmware.encoder_counts_per_rev", f"must be <= {COUNTS_MAX}, got {counts}")

    def sign(x):
        if isinstance(x, bool) or x not in (1, -1):
            raise DesignError("firmware.encoder_direction", f"must be 1 or -1, got {x!r}")
        return int(x)

    def angle(x):
        if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
            raise DesignError("firmware.encoder_zero_deg", f"must be a finite angle (deg), got {x!r}")
        return float(x)

    dirs = _per_motor(tab, "encoder_direction", n_motors, sign) or (1,) * n_motors
    zero = _per_motor(tab, "encoder_zero_deg", n_motors, angle)
    k = optional_number(tab, "wall_stiffness_N_per_m", "firmware", None)
    b = optional_number(tab, "wall_damping_N_s_per_m", "firmware", None)
    if k is not None and not 0 < k <= 1e7:
        raise DesignError("firmware.wall_stiffness_N_per_m", f"must lie in (0, 1e7] N/m, got {k!r}")
    if b is not None and not 0 <= b <= 1e4:
        raise DesignError("firmware.wall_damping_N_s_per_m", f"must lie in [0, 1e4] N s/m, got {b!r}")
    return FirmwareOptions(plane, (g[0] / n, g[1] / n), counts, dirs, zero, k, b)
