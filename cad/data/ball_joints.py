"""Ball joints for parallelogram rods: angle joints DIN 71802 (pure data, no CAD import).

A DIN 71802 angle joint (form C: without the safety catch) is a ball stud DIN 71803 in a
ball socket DIN 71805; the stud's axis is normal to the socket's threaded shank. Every
number carries the source read (:attr:`BallJointSpec.sources`); a number no source read
states is listed in :attr:`BallJointSpec.unverified` and every use of it says so, as
:data:`cad.data.catalog.MOTORS` marks its fields.

Fields (mm unless named): ``ball_d_mm`` the ball (d), ``stud_thread`` the stud's thread
(d3), ``shoulder_mm`` the ball centre to the stud's shoulder (l), ``stud_length_mm`` the
stud's threaded length (l1), ``shank_end_mm`` the ball centre to the socket's shank end (l2),
``thread_depth_mm`` the socket's female thread length (h min), ``af_mm`` the spanner flats
(s), ``socket_d_mm`` the socket housing's diameter, ``neck_d_mm`` the stud's neck,
``range_deg`` the stud's tilt from its centred position, ``pull_off_N`` the least
separating force, ``mass_g`` the joint (stud, socket, nut); ``socket_material`` the socket's.

The catalog keeps the generic 4.8 mm ball link the delta drew before it
(:data:`GENERIC_BALL_LINK`, every field unverified: no vendor sheet read) and is its
default: the DIN 71802 joints do not fit the bundled delta (module docstring of
:mod:`cad.families.delta.ball_joints`: their 18 deg range is short of the rods' 21.1 deg, and
the 8 mm joint's sockets on the effector of ``designs/delta.toml`` collide at a workspace
corner), so a design names one with ``[parts] ball_joint``.
"""

from __future__ import annotations

from dataclasses import dataclass

from cad.errors import DesignError

#: The dimension table read (a distributor's copy of the Elesa+Ganter DIN 71802 table):
#: columns d, d1, d2, d3, l, l1, l2, h min, s, "Min. separating force [N]", "Weight" of the
#: rows DIN 71802-<d>-M<t>-C. The column names are the page's; l, l2 and h min were matched
#: to the named columns of Chenghui's DIN 71802-BS 19 row (l3 "Center to stud shoulder" 20,
#: a "Center to shank end" 45, e "Female thread length" 21.5: the same numbers as this
#: table's l, l2, h min for d = 19). The weight column prints no unit: read as g (14 for the
#: 8 mm joint, as sysbearing.com's 12.85-15.2 for the same size).
DDBARRY = ("D.D. Barry, 'DIN 71802 Angled ball joints' (SKU 8080), "
           "http://www.ddbarry.com.au/shop/joints/8080-din-71802/, table 'Main dimensions'")
#: The angular range and the ball diameters' pull-off forces read.
CHENGHUI = ("Chenghui Bearing, 'Angle joints DIN 71802 form CS with threaded stud', "
            "https://www.chenghuibearing.com/product-type/Angle%20joints%20DIN%2071802%20form%20CS"
            "%20with%20threaded%20stud/metric/p1: 'The angle of rotation for the type with safety "
            "catch is 15°, without safety catch is 18°'")
#: The housing diameter: a copy of the Ganter GN 71802 table stored without its address
#: (columns d1, d2, d3, l2, d4, d5, d6, l1, l3, l4, t, A/F; rows DIN 71802-<d>-M<t>-C), whose
#: l4 and t are the D.D. Barry table's l2 and h min; d6 is not named on the page.
GANTER_COPY = "Ganter GN 71802 table (stored copy, no address), column d6 (not named there)"
#: The stud's neck: no source read states it; the drawing takes the thread's nominal size.
NECK_ASSUMED = "assumed: the stud thread's nominal diameter (no drawing read)"


@dataclass(frozen=True)
class BallJointSpec:
    """One catalog ball joint (module docstring for the fields). ``sources``: (field,
    source) pairs; ``unverified``: the fields no source read states."""

    key: str
    designation: str
    ball_d_mm: float
    stud_thread: str
    shoulder_mm: float
    stud_length_mm: float
    shank_end_mm: float
    thread_depth_mm: float
    af_mm: float
    socket_d_mm: float
    neck_d_mm: float
    range_deg: float
    pull_off_N: float
    mass_g: float
    material: str
    socket_material: str
    sources: tuple[tuple[str, str], ...]
    unverified: tuple[str, ...] = ()

    def source_of(self, field: str) -> str:
        """The source of ``field`` ('' when none is listed)."""
        return dict(self.sources).get(field, "")

    def bom_description(self) -> str:
        """The BOM text: designation, ball, range, and the unverified fields."""
        out = f"{self.designation}, ball d{self.ball_d_mm:g}, tilt {self.range_deg:g} deg"
        if self.unverified:
            out += f"; unverified (no source read): {', '.join(self.unverified)}"
        return out


def _din71802(d: float, thread: str, shoulder: float, l1: float, l2: float, h: float, s: float,
              socket_d: float, pull_off: float, mass: float) -> BallJointSpec:
    key = f"din71802-{d:g}-{thread.lower()}-c"
    table = f"{DDBARRY}, row DIN 71802-{d:g}-{thread}-C"
    return BallJointSpec(
        key=key, designation=f"angle joint DIN 71802-{d:g}-{thread}-C", ball_d_mm=d,
        stud_thread=thread, shoulder_mm=shoulder, stud_length_mm=l1, shank_end_mm=l2,
        thread_depth_mm=h, af_mm=s, socket_d_mm=socket_d,
        neck_d_mm=float(thread[1:]), range_deg=18.0, pull_off_N=pull_off, mass_g=mass,
        material="steel-1018", socket_material="steel-1018",
        sources=(("ball_d_mm", f"{table}: d"), ("stud_thread", f"{table}: d3"),
                 ("shoulder_mm", f"{table}: l"), ("stud_length_mm", f"{table}: l1"),
                 ("shank_end_mm", f"{table}: l2"), ("thread_depth_mm", f"{table}: h min"),
                 ("af_mm", f"{table}: s"), ("socket_d_mm", f"{GANTER_COPY}, row DIN 71802-{d:g}-{thread}-C"),
                 ("neck_d_mm", NECK_ASSUMED), ("range_deg", f"{CHENGHUI} (form C)"),
                 ("pull_off_N", f"{table}: Min. separating force [N]; {CHENGHUI}: min. extraction force"),
                 ("mass_g", f"{table}: Weight")),
        unverified=("socket_d_mm", "neck_d_mm"))


_NO_SHEET = ("unverified: generic dimensions of the 4.8 mm ball-link class, no vendor sheet read; "
             "replace with an ordered part's drawing")
#: The ball link the delta drew before the catalog (RC-model class, M2.5 stud): no vendor
#: sheet was read, so every field is unverified. Its range is its drawing's: the drawn
#: opening (78 deg half-angle) less the neck's half-angle seen from the ball centre,
#: asin(2.5 / 4.8) = 31.4 deg (:mod:`cad.families.delta.hardware`).
GENERIC_BALL_LINK = BallJointSpec(
    key="ball-link-4.8", designation="ball link, 4.8 mm ball, M2.5 stud (RC-model class)",
    ball_d_mm=4.8, stud_thread="M2.5", shoulder_mm=7.0, stud_length_mm=0.0, shank_end_mm=6.75,
    thread_depth_mm=0.0, af_mm=3.0, socket_d_mm=7.5, neck_d_mm=2.5, range_deg=46.6,
    pull_off_N=0.0, mass_g=1.2, material="steel-1018", socket_material="delrin",
    sources=(("*", _NO_SHEET),),
    unverified=("ball_d_mm", "stud_thread", "shoulder_mm", "shank_end_mm", "af_mm", "socket_d_mm",
                "neck_d_mm", "range_deg", "mass_g"))

#: The catalog: the generic ball link and DIN 71802 form C, ball 8, 10 and 13 mm (right-hand
#: thread).
BALL_JOINTS: dict[str, BallJointSpec] = {j.key: j for j in (
    GENERIC_BALL_LINK,
    _din71802(8.0, "M5", 9.0, 10.0, 22.0, 10.5, 7.0, 12.8, 30.0, 14.0),
    _din71802(10.0, "M6", 11.0, 12.5, 25.0, 11.5, 8.0, 14.8, 40.0, 25.0),
    _din71802(13.0, "M8", 13.0, 16.5, 30.0, 14.0, 11.0, 19.3, 60.0, 52.0),
)}
#: The joint a delta that names none gets: the generic link the bundled designs are built
#: with (module docstring: why not a DIN 71802 joint).
DEFAULT_BALL_JOINT = "ball-link-4.8"


def get_ball_joint(key: str, field: str = "parts.ball_joint") -> BallJointSpec:
    """The catalog entry ``key``; DesignError naming ``field`` and the keys otherwise."""
    if not isinstance(key, str) or key not in BALL_JOINTS:
        raise DesignError(field, f"unknown ball joint {key!r} (catalog keys: {', '.join(BALL_JOINTS)})")
    return BALL_JOINTS[key]
