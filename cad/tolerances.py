"""Numerical tolerances, gathered in one place, each with the reason for its value.

Lengths in mm unless the name says otherwise; angles in radians.
"""

#: Loop-closure residual accepted from the closed-form four-bar solution (mm).
#: The closed form is exact; 1e-9 mm leaves ~6 orders above float64 round-off
#: for links of ~100 mm.
CLOSURE_RESIDUAL_MM = 1e-9

#: Discriminant margin: A^2 + B^2 - C^2 below -this * (A^2 + B^2) means the loop
#: cannot close. Relative, so it scales with the linkage.
CLOSURE_REL_EPS = 1e-12

#: |sin(phi2 - phi3)| below this is a toggle (transmission angle < ~0.57 deg):
#: eq (11) velocity ratios blow up by > 100x the link ratio.
TOGGLE_SIN = 1e-2

#: |A + C| / sqrt(A^2 + B^2) below this makes eq (3)'s tan-half-angle form
#: divide by ~zero (the reference form only; the atan2 form is used everywhere).
TAN_HALF_EPS = 1e-9

#: A jump in phi2 between adjacent samples larger than this (rad) while the
#: crank moves by less than a sample step is a branch jump.
BRANCH_JUMP_RAD = 0.5

#: Smallest singular value ratio accepted before a pseudo-inverse is declared
#: singular (eq 22): 1e-9 relative is ~7 orders above float64 eps.
PINV_RCOND = 1e-9

#: Relative tolerance for inertia tensors: eigenvalues must exceed
#: -this * trace, and principal moments must satisfy the triangle inequality
#: to within this * trace.
INERTIA_REL_EPS = 1e-9

#: Central-difference step for Jacobian checks (rad). Truncation error ~h^2,
#: round-off ~eps/h: 1e-6 balances both near 1e-10 relative.
FD_STEP_RAD = 1e-6

#: Largest file hapticad reads, by kind (bytes), checked (``os.stat``/``fstat``) before a
#: byte is parsed (:mod:`cad.io.guard`, issue 22 §2): a file far larger than its kind can
#: legitimately be is hostile or damaged, and parsing it whole would exhaust memory.
READ_MAX_BYTES = {
    # designs/*.toml are 0.2-2.2 KB; 1 MiB is ~500x the largest and tomllib parses it in ~0.1 s
    "design": 1 << 20,
    # manifest.json: ~150 bytes per listed file; 16 MiB lists ~100 000 files
    "manifest": 16 << 20,
    # report.json of a build: tens of KB (per-sample curves included); 64 MiB is ~1000x
    "report": 64 << 20,
    # any other JSON hapticad wrote (a cached part's integrals, a design script's result)
    "json": 16 << 20,
    # a design's handle script (Python source): a few KB
    "script": 1 << 20,
    # an MJCF model of a build (wall --build-dir): tens of KB
    "mjcf": 16 << 20,
    # STEP / STL given to `massprops`: hapticad's own assembly.step is < 5 MB; 256 MiB is a
    # ~5-million-triangle binary STL (50 bytes each, ~4x that in float64 arrays once read)
    "step": 256 << 20,
    "stl": 256 << 20,
    # one cache entry (a part's BREP, derived arrays): hapticad writes a few MB at most
    "cache": 256 << 20,
    # a sweep's results.parquet (cad/sweep): ~200 bytes per row; 1 GiB is ~5 million rows
    "parquet": 1 << 30,
    # a file listed in an output folder's manifest, hashed to check it is ours: the largest
    # file hapticad writes is a sweep's results.csv (about twice its Parquet table, which is
    # read up to 1 GiB); a fabrication assembly.step is < 5 MB. 4 GiB leaves 2x on the CSV and
    # keeps a hostile manifest (a 200 GiB sparse file listed with its size) from being read.
    "output": 4 << 30,
    # a chart hapticad wrote (optimize --out: checked it is ours before it is replaced): ~100 KB
    "chart": 64 << 20,
    # a small marker file hapticad writes (the owner of a temporary folder: host and pid)
    "marker": 4 << 10,
}

#: Deepest bracket nesting accepted in a TOML or JSON file, or parenthesis nesting in a STEP
#: file, counted by a scan before the parser runs. hapticad's designs nest 1 level (table headers),
#: its JSON 5 (report.json), its STEP entities 3; tomllib and json recurse once per level (Python's
#: recursion limit ~1000: a RecursionError traceback at 50 000) and OCCT's STEP reader crashed
#: (segmentation fault) at 100 000 nested parentheses in a CARTESIAN_POINT.
NESTING_MAX_DEPTH = 64

#: Most digits of a STEP entity id (``#123``): OCCT's reader crashed (segmentation fault) on
#: a 12-digit id and read 10- and 11-digit ones (measured, OCP 7.9); a 256 MiB file holds
#: fewer than 10 million entities, so 9 digits (up to 999 999 999) refuse no real file.
STEP_ENTITY_ID_MAX_DIGITS = 9

#: Magnitude bounds for design lengths (mm): below 1 um or above 1 km the squares of
#: eqs (4)-(6) lose all precision or overflow; no haptic device lives out there.
LENGTH_MIN_MM = 1e-3
LENGTH_MAX_MM = 1e6

#: Upper bound of the force along the path (N) and of crank samples (memory: 1e6
#: samples x a few arrays of float64 is ~100 MB).
FORCE_MAX_N = 1e6
SAMPLES_MAX = 1_000_000

#: Largest manufacturing tolerance `hapticad tolerance` accepts (mm): beyond a few mm
#: an error is a different design, not a tolerance (and a value in um given as mm
#: is caught here).
TOLERANCE_MAX_MM = 5.0

#: Monte Carlo samples of `hapticad tolerance`: at least 100 for a meaningful yield,
#: at most 2e6 (~1 GB of metric arrays would follow, and 1e6 already resolves a
#: yield to 0.05 %).
MC_SAMPLES_MIN = 100
MC_SAMPLES_MAX = 2_000_000

#: Extent (largest bounding-box side, mm) outside which a mesh read as mm is no part of a
#: haptic device: below 0.5 mm (smaller than an M1 screw; a 30 mm part written in metres
#: is 0.03) the file is most likely in metres; above 5000 mm (a desk-top device is well
#: under 1 m; a 10 m part is more likely a 10 mm part written in um) in micrometres.
PART_EXTENT_MIN_MM = 0.5
PART_EXTENT_MAX_MM = 5000.0

#: Two closed shells of one mesh may share no volume (separate bodies) or all of the inner
#: one (nested); manifold3d's float64 intersection of exact meshes is right to ~1e-12
#: relative, so a discrepancy above 1e-6 of the smaller shell is a real crossing.
SHELL_OVERLAP_REL_EPS = 1e-6
#: Stroke held by ``hapticad synth --stroke-mm`` (relative): the crank end is root-found
#: (brentq, xtol 1e-12 rad) so the chord equals the asked stroke; 1e-6 leaves the root
#: finder's ~1e-10 relative far below and is 0.06 um on a 60 mm stroke, under any
#: fabrication tolerance.
SYNTH_STROKE_REL = 1e-6
#: Generated firmware, twin pantograph: the crank pin found by the crank pantograph's FK may
#: lie off the crank circle (radius l6 about the main journal) by encoder quantization and
#: assembly error; beyond 1 mm (5 % of the eq-7 crank of 20 mm) the readings disagree and
#: hc_forward refuses them (HC_ERR_CRANK).
FIRMWARE_CRANK_TOL_M = 1e-3
#: Generated firmware, double build against hapticad's numpy model (issue 26): 1e-9 m and
#: 1e-9 N m at every test pose (rounding of the same closed forms is ~1e-15).
FIRMWARE_DOUBLE_POSITION_M = 1e-9
FIRMWARE_DOUBLE_TORQUE_NM = 1e-9
#: Float build: positions within 2e-5 m (a third of the Hoeken's encoder step, 5.46e-5 m,
#: Hoeken paper §III.B.4: finer than the device can read) and torques within 2e-5 N m (0.02 %
#: of the RE 35's 0.1 N m continuous torque); float32 rounding (6e-8 relative) amplified by
#: the closed forms' conditioning stays well inside both (measured, docs/firmware.md).
FIRMWARE_FLOAT_POSITION_M = 2e-5
FIRMWARE_FLOAT_TORQUE_NM = 2e-5
#: Jacobian against central finite differences of the generated FK (double build, step
#: 1e-6 rad): truncation ~1e-13 m/rad, rounding ~1e-10 m/rad; 1e-7 m/rad leaves margin.
FIRMWARE_FD_JACOBIAN = 1e-7
#: PowerMouse map, float build: ampere-turns within 1e-3 At (~1e-6 of the ~1000 At peak of
#: the bundled design; float32 resolves ~6e-8 relative) and the wrench W NI within 2e-5 N, N m
#: (FIRMWARE_FLOAT_TORQUE_NM). Double: 1e-9 At and 1e-9 N, N m.
FIRMWARE_FLOAT_AMPERE_TURNS = 1e-3

#: Stock to order for made parts (cad.export.order): the cutting allowance added to each
#: part's bounding box. These are our stated ordering margins (shop practice, not a
#: handbook value), shown in report.md and docs/ordering.md.
#: Plate: per side around the profile, room for the waterjet/laser lead-in and for
#: clamping the sheet (the kerf itself is ~0.2-1 mm).
STOCK_PLATE_MARGIN_MM = 5.0
#: Round bar: added to the diameter (1 mm per side to turn the mill-finished skin off).
STOCK_ROD_DIAMETER_ALLOWANCE_MM = 2.0
#: Bar, rod and tube: added to the length (a saw cut of ~2 mm and facing both ends).
STOCK_LENGTH_ALLOWANCE_MM = 5.0
#: Block (milled parts that are neither plate nor turned): per side on every face.
STOCK_BLOCK_MARGIN_MM = 2.0
