"""Numerical tolerances, gathered in one place, each with the reason for its value.

Lengths in mm unless the name says otherwise; angles in radians.
"""

import math

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

#: A price (``--prices`` CSV or a design's ``[prices]``) is at most this (any currency): a
#: unit price of a thousand million is a typo, and line and total (quantity x price, summed)
#: stay finite far beyond it (1e308 overflowed the total to inf).
PRICE_MAX = 1e9
#: A ``--prices`` CSV cell is at most this many characters (a designation is ~10-60): the csv
#: module's own limit (131 072) ended in a traceback.
PRICE_FIELD_MAX_CHARS = 1000

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
    # a --prices CSV: ~40 bytes a line, a BOM has tens of lines; 4 MiB is ~100 000 lines
    "prices": 4 << 20,
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
    # an identification log (identify LOG.csv): ~40 bytes a row per motor; 10 s at 3 kHz is
    # ~1.5 MB for one motor; 256 MiB is ~100x a minute-long four-motor log
    "log": 256 << 20,
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
#: (brentq, xtol ROOT_XTOL_RAD) so the chord equals the asked stroke; 1e-6 leaves the root
#: finder's ~1e-10 relative far below and is 0.06 um on a 60 mm stroke, under any
#: fabrication tolerance.
SYNTH_STROKE_REL = 1e-6
#: Generated firmware, twin pantograph: the crank pin found by the crank pantograph's FK may
#: lie off the crank circle (radius l6 about the main journal) by encoder quantization and
#: assembly error; beyond 1 mm (5 % of the eq-7 crank of 20 mm) the readings disagree and
#: hc_forward refuses them (HC_ERR_CRANK).
FIRMWARE_CRANK_TOL_M = 1e-3
#: Generated firmware, haptic pen: the two arm ends found by the arms' FK may lie off the pen
#: length l6 by encoder quantization and assembly error; beyond 1 mm (1.4 % of the paper's
#: 70 mm pen, Table 2) the readings disagree and hc_forward refuses them (HC_ERR_CRANK).
FIRMWARE_PEN_LENGTH_TOL_M = 1e-3
#: Generated firmware, haptic pen: yaw = atan2(u_y, u_x) is undefined for a vertical pen; below
#: cos(pitch) = 0.01 (pitch beyond 89.4 deg, far outside any workspace of rotation_deg < 90)
#: hc_forward calls the pose singular.
FIRMWARE_PEN_COS_PITCH_MIN = 1e-2
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

# ---------------------------------------------------------------- voice-coil optimisers
# (cad/actuators/voicecoil.py, isotropy paper section 6 and Fig. 8)

#: Default stopping bracket of the gap search (:func:`cad.actuators.voicecoil.optimal_gap`),
#: relative to l_m + w_m + t_m + d_r: relative so tiny and huge actuators are solved alike;
#: 1e-8 is far below any machining tolerance (1e-6 mm on a 100 mm actuator) and still ~8
#: orders above float64 round-off of the log-space Brent search.
GAP_XATOL_REL = 1e-8
#: Least coil width d - d_r the actuator NLP allows (mm): eq (8)'s force is 0 at d = d_r,
#: where the coil width enters under a square root (an infinite slope), so the NLP keeps the
#: coil at least this wide; 1 um is far below any coil that can be wound.
NLP_COIL_WIDTH_MIN_MM = 1e-3
#: Constraint violation (mm) still counted feasible after SLSQP: its iterates meet the
#: inequality constraints to round-off, not exactly; 1e-9 mm is ~7 orders below any size
#: of a magnet or coil (~1-100 mm).
NLP_FEASIBLE_SLACK_MM = 1e-9
#: A constraint within this (mm) of its bound is reported active (box bounds are exact after
#: clipping; the height and footprint constraints are met to SLSQP's precision); 1e-6 mm is
#: still far below any size that matters to a magnet or a coil.
NLP_ACTIVE_MM = 1e-6
#: SLSQP stopping tolerance on the normalized objective (force / 10 N, O(1)): 1e-12 is
#: ~4 orders above float64 round-off, so the optimum is converged, not stalled.
NLP_SLSQP_FTOL = 1e-12

# ---------------------------------------------------------------- inverse design (cad/studies/fit.py)

#: Weight of the change from the start added to the max target violation in the optuna
#: objective of ``hapticad fit``: the change is at most ~1 per free parameter, so 1e-6 only
#: breaks ties between value sets whose violations agree to ~1e-6 (violations are relative;
#: the default target tolerance is 5 %), never trades a real violation for a smaller change.
FIT_CHANGE_WEIGHT = 1e-6
#: A stock plate thickness counts as inside a ``--free parts.bar_thickness_mm=LO:HI`` range
#: when within this (mm) of it: LO and HI come from 0.5x/1.5x products that carry float
#: round-off (~1e-15 mm); 1e-9 mm keeps a stock size given exactly as a bound inside.
STOCK_RANGE_SLACK_MM = 1e-9

# ---------------------------------------------------------------- design targets (cad/design/targets.py)

#: Relative tolerance of a target given as a bare number (``coupler_mass_g = 40.0``) or as
#: ``{ value = ... }`` without ``tol_rel`` / ``tol_abs``: 5 %, the designer's stated default
#: (docs/design-files.md); tighter than the 30 % the Hoeken paper's CAD values carry in the
#: bundled design, looser than what our solids reproduce run to run (exact, 1e-9).
TARGET_TOL_REL_DEFAULT = 0.05

# ---------------------------------------------------------------- layer planner (cad/families/fourbar/layers.py)

#: Slack (mm) of the layer planner's comparisons of stack heights and planar clearances
#: against their required values: those are sums of catalog sizes and design numbers in
#: mm (~1-100), whose float64 round-off is ~1e-14 mm; 1e-9 mm keeps a stack that meets a
#: requirement exactly from being refused by round-off, and is far below any dimension
#: that can be made.
LAYER_SLACK_MM = 1e-9

# ---------------------------------------------------------------- 5-bar, twin pantograph, haptic pen
# (cad/kinematics/fivebar.py, twin_pantograph.py, haptic_pen.py; the generated firmware uses the
# same values, cad/firmware/csrc.py). Also importable from cad.kinematics.pantograph_tolerances.

#: |sin| of the angle between a proximal and its distal link (serial, "type-1"
#: singularity: the arm is fully stretched or folded, the workspace boundary)
#: below this is singular. At 1e-9 the Jacobian row is ~1e9 times its regular
#: size, so sigma_max and the GII are numerically meaningless anyway; float64
#: round-off of the acos argument for 100 mm links is ~1e-16 relative, so a
#: genuinely regular point is never flagged.
ARM_SINGULAR_SIN = 1e-9
#: |sin| of the angle between the two distal links (parallel, "type-2"
#: singularity: the distal links are collinear and the end effector cannot
#: resist a force along their normal) below this is singular. Same reasoning.
DISTAL_SINGULAR_SIN = 1e-9
#: Reach margin: |E - B| > (l2 + l3) * (1 + this) or < |l2 - l3| * (1 - this)
#: is unreachable. Inside the margin the acos argument is clipped to [-1, 1]
#: and the point is reported singular (not unreachable).
REACH_REL_EPS = 1e-12
#: Global max-stroke (cad/kinematics/max_stroke.py): the branch and bound stops splitting
#: when the next level would take the cells bounded past this. Near a closure limit or a
#: toggle the coupler point's speed bound grows without limit, so cells there are never
#: dropped; the cap keeps `synth` to seconds (the Hoeken's proof takes ~3e4 cells) and the
#: bound reported is that of the cells left (valid, possibly loose).
SYNTH_BOUND_MAX_CELLS = 300_000
#: Delta (cad/kinematics/delta.py): an arm is serially singular when |b_i| / (L_a L_b), the
#: cosine between its lower arm and its elbow's velocity, is below this; at 1e-9 the row of
#: J is ~1e9 times its regular size (the same reasoning as ARM_SINGULAR_SIN).
DELTA_SERIAL_SINGULAR = 1e-9
#: Delta: the pose is parallel-singular when |det A_x| / L_b^3, the triple product of the
#: three lower arms' unit vectors, is below this (the same reasoning as DISTAL_SINGULAR_SIN).
DELTA_PARALLEL_SINGULAR = 1e-9
#: Delta FK with Stamper's joint offset (no closed form): Newton steps from the sphere point of
#: radius L_b + g. The start is within ~g^2 / L_b of the answer and Newton converges
#: quadratically, so 8 steps reach round-off from any start a device meets (the tests check
#: IK(FK) to 1e-10 rad over random poses of the Falcon's geometry).
DELTA_FK_NEWTON_STEPS = 8
#: Largest |f_i| / L_b^2 of a converged delta FK point: float64 round-off of mm^2 sums is
#: ~1e-16 relative; 1e-10 leaves six orders of margin and still flags a point Newton left.
DELTA_FK_RESIDUAL_REL = 1e-10
#: The same test in the float build of the generated delta firmware
#: (cad/families/delta/firmware.py): float32 resolves ~1.2e-7 relative, and f_i sums three
#: squares of lengths ~L_b, so its round-off is a few 1e-7 L_b^2; 1e-5 leaves ~30x margin.
DELTA_FK_RESIDUAL_REL_FLOAT = 1e-5
#: |E - B| below this (mm) leaves atan2(E - B) undefined: the end effector sits
#: on an actuated joint. Unreachable for any arm with l2 != l3, singular else.
ON_JOINT_MM = 1e-9
#: Radial distance (mm) of a pen end from its waist axis below which the waist
#: angle is undefined (haptic pen, cylindrical coordinates).
ON_WAIST_AXIS_MM = 1e-9

# ---------------------------------------------------------------- root finding and extrema

#: Bracket (rad of crank angle) at which the scalar root finders and minimisers of the
#: four-bar stop: the closure-margin minimum (cad/kinematics/fourbar.py, golden section) and
#: the crank end of a given stroke (cad/kinematics/synthesis.py, brentq). 1e-12 rad moves the
#: coupler point ~1e-10 mm on a 100 mm linkage: converged to round-off, not to a sample step.
ROOT_XTOL_RAD = 1e-12
#: Nelder-Mead stop of ``hapticad synth`` with the stroke held (cad/kinematics/synthesis.py;
#: variables: crank angles in rad and link lengths relative to l2; objective dy_max/stroke):
#: 1e-8 rad or 1e-8 of l2 is ~1e-6 mm on a 100 mm linkage, below any fabrication tolerance,
#: and 1e-12 on dy_max/stroke is far below a deviation that can be made or measured.
SYNTH_HELD_XATOL = 1e-8
SYNTH_HELD_FATOL = 1e-12
#: Nelder-Mead stop of the penalized ``synth`` search (same variables; objective the torque
#: variation or -stroke/l2, O(0.1-1)): 1e-6 rad or 1e-6 of l2 (~1e-4 mm), 1e-9 on the objective;
#: the best point is polished and re-evaluated with the refined metrics afterwards (module
#: docstring there), so the search itself needs no finer stop.
SYNTH_SEARCH_XATOL = 1e-6
SYNTH_SEARCH_FATOL = 1e-9
#: Manufacturing-tolerance analysis (cad/kinematics/tolerance.py): the zoom refinement of an
#: extremum stops at this bracket (rad). A metric is flat to first order at its extremum, so
#: its error goes as the square of the bracket: 1e-7 rad leaves it far below the 1e-7 relative
#: of the first-order propagation (FD_STEP_MM).
ZOOM_XTOL_RAD = 1e-7
#: The second-best grid peak is zoomed too when within this fraction of the best: two
#: near-equal peaks of |y| may swap order between grid and exact values.
ZOOM_SECOND_PEAK_REL = 0.01
#: Central-difference step of the first-order tolerance propagation (mm): the metrics are
#: smooth in the geometry and refined to ~1e-12 mm, so 1e-4 mm keeps truncation (~h^2) and
#: round-off (~1e-12 / h) both below 1e-7 relative.
FD_STEP_MM = 1e-4

# ---------------------------------------------------------------- mass properties

#: |R^T R - E| above this (max abs entry) is not a rotation matrix (cad/massprops/props.py):
#: a rotation composed from a few float64 trig products is orthonormal to ~1e-15; 1e-9 still
#: refuses any matrix with a scale or shear that would change an inertia tensor measurably.
ROTATION_ORTHO_TOL = 1e-9

# ---------------------------------------------------------------- simulation (cad/sim)

#: Stopping residual (m) of the Newton iterations that close an exported MJCF's loops
#: (cad/sim/mj.py close_loops, at most 50 iterations): the loop constraints are sums of ~0.1 m
#: lengths, so 1e-14 m is a few hundred ulp: the loops are closed to float64 round-off (Newton
#: converges quadratically, so the last iterations cost almost nothing).
CLOSE_TOL_M = 1e-14
#: Relative bracket at which the bisection of the largest stable wall stiffness K_max stops
#: (cad/sim/wall.py): 1 % matches the reduced model's own accuracy (SUBSTEP_MAX_S there: within
#: 1 % of the mujoco model), and each halving of the bracket costs a set of wall simulations.
K_RTOL = 0.01
#: Relative step of the fine K grid over which K_max is estimated as a stability threshold
#: (cad/sim/wall.py k_max_estimate): near K_max the wall's stability is intermittent (stable
#: and unstable stiffnesses interleave over ~15 %: a 0.2 % change of apparent mass moved the
#: first unstable probe of a bisection by 14 %), so K_max is the threshold that best separates
#: ~400 probes 0.25 % apart; its bootstrap error (measured ~1 % on the Hoeken) is reported.
K_GRID_STEP = 0.0025
#: Bootstrap resamples of those probes for the stated sampling error of K_max (95 % interval).
K_BOOTSTRAP = 200

# ---------------------------------------------------------------- meshes drawn, not measured

#: Chordal (mm) and angular (rad) deflection of the 2-D preview meshes (cad/report/preview.py):
#: coarse, only drawn at a few pixels per mm, never measured.
PREVIEW_MESH_TOL_MM = 0.5
PREVIEW_ANGULAR_TOL_RAD = 0.6
#: Chordal (mm) and angular (rad) deflection of the viewer meshes (glb, GIF, still;
#: cad/pipeline/views.py): 0.2 mm is below a pixel of the viewer at full size, and the meshes
#: are only looked at (mass properties and interference use exact solids).
VIEW_TOLERANCE_MM = 0.2
VIEW_ANGULAR_TOLERANCE_RAD = 0.5

# ---------------------------------------------------------------- exported part meshes

#: Default chordal (mm) and angular (rad) deflection of the exported part STL files and
#: parts.3mf (cad/export export_part, a design's parts.stl_tolerance_mm overrides the first):
#: 0.01 mm is ten times below a print layer (0.1-0.3 mm) and below machining tolerances; the
#: chordal criterion alone leaves facets of 2 sqrt(2 tol / r) rad, so 15 deg governs only on
#: radii under ~1.2 mm (small fillets and holes).
STL_TOLERANCE_MM = 0.01
STL_ANGULAR_TOLERANCE_RAD = math.radians(15.0)
#: Chordal deflection (mm) of the part STL at the four-bar's ``preview`` fidelity, at least
#: (cad/families/fourbar/build.py): a preview is looked at, not made; ten times the default.
PREVIEW_STL_TOL_MM = 0.1
#: Pixel centres this close outside an edge (px) still count as inside in the rasterizer
#: (cad/report/raster.py): a pixel centre on an edge shared by two triangles is not lost to
#: round-off of the edge functions (no cracks), and 1e-7 px covers no visible area.
EDGE_EPS_PX = 1e-7
#: Triangles thinner than this (px; seen edge-on) are skipped by the rasterizer: they cover
#: no visible area, and their depth gradient would be ill-conditioned.
MIN_HEIGHT_PX = 1e-3

# ---------------------------------------------------------------- drawings (cad/drawings)

#: A diameter on a sheet is the fit's or tap drill's when they agree this closely (mm): both
#: come from the same catalog numbers through a boolean, so they agree to round-off.
MATCH_MM = 1e-6
#: Two faces belong to one feature when axis, centre and diameter agree this closely (mm):
#: faces of one boolean share the same circle up to round-off.
SAME_FEATURE_MM = 1e-6
#: A face is aligned with a part axis when its direction is within this of it (cosine
#: slack): hapticad's holes are drilled along a part axis exactly, up to round-off.
AXIS_SLACK = 1e-9
#: A floor face lies inside a pocket's outline when its box is within this of the walls'
#: box (mm): both are exact boxes of faces of one boolean, equal up to round-off.
SAME_POCKET_MM = 1e-6

# ---------------------------------------------------------------- part clearances (cad/parts)
# The part cache hashes this file with cad/parts (cad/parts/part_cache.py): a change here
# rebuilds the parts.

#: Radial margin of pantograph plate openings around a motor pilot or pin (mm): a clearance
#: (our choice), so that neither touches the plate whatever the cutting tolerance of the
#: opening (tenths of a mm for a laser or waterjet cut).
OPENING_MARGIN_MM = 1.0
#: PowerMouse: radial margin of a shoulder's seat beyond the part's radius (mm): a faced corner
#: or a socket bottom is made this much wider than the shoulder that bears on it (a
#: clearance, our choice).
SEAT_MARGIN_MM = 0.5
#: PowerMouse: radial margin of the corner holes (the post's in the flotor, the handle's in the
#: housing) beyond the excursion over the motion range (mm): covers the sampling of rotations in
#: :func:`cad.actuators.powermouse.diagonal_excursion_mm`.
HOLE_MARGIN_MM = 0.5
#: Printed parts (cad/parts/printed.py): sections are taken this far inside a slab boundary (mm),
#: never on a horizontal face, where a planar section of a B-rep is degenerate; 1e-6 mm is far
#: below a print layer (0.1-0.3 mm) and far above the round-off of the slab heights.
PRINT_SECTION_EPS_MM = 1e-6
#: Printed parts: a section contour with any edge that is not a line or a circle (a B-spline cut
#: through a fillet or a cone) is replaced by a polygon of chords this long (mm) before the wall
#: offset: OCCT's 2D offset of such a curve ran for 20 minutes and grew to 5 GB on a 12 mm knob,
#: a polygon's offset is linear in its vertices. The chord error s^2 / (8 r) is 1.3e-4 mm on a
#: 1 mm radius, far below a print line (0.4 mm).
PRINT_CHORD_MM = 0.1
#: ... and at most this many vertices per contour (the chord grows instead): bounds the work of
#: one offset whatever the part's size (a 1 m contour still gets 1 mm chords).
PRINT_CONTOUR_MAX_POINTS = 2000
#: ... unless every sampled point of it lies within this fraction of the mean radius from the
#: centroid: it is then the circle (a turned part cut through a fillet; the B-spline OCCT makes
#: of it is exact to ~1e-8 relative), offset exactly.
PRINT_CIRCLE_FIT_REL = 1e-6
#: Printed parts: at most this many layers per part (its height / the layer height). The wall
#: model cuts up to one section per layer (within a fillet or cone every layer is its own), so
#: the work grows with it: 2000 layers is a 400 mm part at 0.2 mm, beyond any desktop device's
#: printed part (the largest bundled one is ~25 mm, 125 layers).
PRINT_LAYERS_MAX = 2000

# ---------------------------------------------------------------- interference check (cad/assembly/interference.py)

#: Extra margin on top of 2 x mesh tolerance before a near contact is confirmed exactly (mm).
CONFIRM_MARGIN_MM = 0.05
#: Distances below this are contact (mm): OCCT's own confusion tolerance is 1e-7.
CONTACT_MM = 1e-6
#: Default absolute mesh tolerance of the fast pass (mm); see cad.bench.interference.
SWEEP_MESH_TOL_MM = 0.05
#: A pose is skipped when its lower bound is at least the level that matters minus this
#: (mm): it absorbs float rounding between the box bounds and fcl's distance (a gap of
#: exactly 1 mm between parallel faces comes back as 0.9999999999999999), so ties do not
#: force a measurement. It moves a reported minimum by at most this much, far below
#: CONFIRM_MARGIN_MM, so no near contact can be skipped.
LB_SLACK_MM = 1e-9
#: Parts farther than this in z from the other body are left out of a pair's fast pass
#: (planar motion keeps z, so they stay at least that far); a pair whose mesh minimum
#: exceeds the z gap of a left-out part is redone without culling (mm).
CULL_MARGIN_MM = 5.0
#: A common volume above this between two parts of one body is a collision (mm^3): far
#: above OCCT's boolean noise on touching faces (~1e-9), below the issue-10 acceptance
#: threshold (1e-3) so nothing the independent STEP check would find is let through.
OVERLAP_MIN_MM3 = 1e-4
#: Bounding boxes that overlap by no more than this along some axis only touch (mm): parts
#: stacked face to face (a spacer on a bar, a leg under the plate) need no boolean.
BOX_TOUCH_MM = 1e-6

# ---------------------------------------------------------------- benchmark sweeps (cad/bench)

#: Absolute mesh tolerances (mm) swept by the mass-properties bench (cad/bench/massprops.py):
#: from coarser than any part feature (1 mm) to below the exact-vs-mesh crossover (3 um).
BENCH_MASSPROPS_MESH_TOLERANCES_MM = (1.0, 0.3, 0.1, 0.03, 0.01, 0.003)
#: OCCT adaptive-mode targets swept by the same bench (OCCT does not adapt for eps > 1e-3):
#: four decades down to 1e-8, where its inertia error stops improving.
BENCH_OCCT_EPS = (1e-2, 1e-4, 1e-6, 1e-8)
#: Mesh tolerances (mm) swept by the interference bench (cad/bench/interference.py): from
#: 0.2 mm (coarser than its 0.05 mm overlap, which meshes at 0.1 mm already miss, SPEC "Measured
#: pitfalls") down to 0.01 mm, its smallest prescribed gap.
BENCH_INTERFERENCE_MESH_TOLERANCES_MM = (0.2, 0.1, 0.05, 0.02, 0.01)

# ---------------------------------------------------------------- display

#: A datasheet row shows its min .. max range unless the two agree to this (relative): values
#: printed to 3-4 significant digits, so a range narrower than 1e-6 is round-off of one value.
RANGE_SAME_REL = 1e-6

# --------------------------------------------------------------------------- haptic pen
#: Gap between the lowest point any link clevis reaches over the pen's motion and the top of
#: the waist bracket's foot strip (mm): the clevises are machined parts, 5 mm covers their
#: stack and a bent tube (cad/families/pen/layout.py).
PEN_FOOT_MARGIN_MM = 5.0
#: Gap of the pen gimbal's ring to its yoke (arms and base) and of the pen hub to the ring
#: (mm): 1.5 mm clears the bearings' axial play and the turned parts' tolerances, and keeps the
#: rotating parts apart over the whole range (checked by the interference check).
PEN_GIMBAL_GAP_MM = 1.5
#: Central-difference step of the pen's body poses for the effective mass (task units: mm and
#: rad, times the task scaling): truncation O(h^2) ~1e-10 relative and round-off ~1e-16 / h
#: ~1e-11 relative on poses of a few hundred mm; MuJoCo's mass matrix agrees to 1e-6
#: (tests/families/pen/test_pen_build.py).
PEN_FD_STEP = 1e-5

# --------------------------------------------------------------------- laser sheets
# (cad/export/nesting.py: laser-cut plate parts nested on stock sheets, parts.process = "laser")

#: Gap between the bounding boxes of two nested parts (mm): more than twice the widest kerf
#: of the sheet table (0.25 mm) plus the beam's heat-affected zone, and room for the thin web
#: between two cuts not to warp or burn through; shops quote 2-5 mm part spacing (stated
#: choice, not a handbook value).
NEST_GAP_MM = 3.0
#: Margin from the sheet's edge to any part (mm): the cut sheet edge is not square or clean,
#: the sheet is clamped/weighted there, and the laser's lead-ins need room (the plate stock
#: margin STOCK_PLATE_MARGIN_MM is per part; this is per sheet; stated choice).
NEST_EDGE_MARGIN_MM = 10.0
#: Rectangle sizes are handed to rectpack in integer units of this (mm): rectpack's float
#: sizes are rounded; parts are rounded up and sheets down, so a placement never grows.
NEST_GRID_MM = 0.01
#: A part box within this of the sheet less its margins fits (mm): the round-off of a box read
#: from OCCT and of sizes summed in floating point, far below any cut tolerance; the same
#: 1e-6 mm the order's whole-mm stock rounding forgives (cad/export/order.py).
NEST_FIT_EPS_MM = 1e-6
#: Engraved label: text height tried from the largest down (mm); the label goes where its box
#: (character width x height, see LABEL_CHAR_WIDTH) lies inside the part's material with
#: LABEL_CLEARANCE_MM around it, and no lower than the last height (a part too thin for
#: that gets its label beside it on the NOTES layer).
LABEL_HEIGHTS_MM = (5.0, 4.0, 3.0, 2.5, 2.0, 1.5, 1.0)
#: Width of one character of the DXF's standard font per unit text height: ezdxf's default
#: style is ~0.6-0.9 h per character; 1.0 bounds it (a label box never too small).
LABEL_CHAR_WIDTH = 1.0
#: Material left around an engraved label's box (mm).
LABEL_CLEARANCE_MM = 0.5
#: Step of the grid of candidate label centres over a part's bounding box (mm).
LABEL_GRID_MM = 1.0
#: Issue 24 §5: a device-level structure figure (first mode, handle compliance, stress) and
#: a second, independent model of it (tests/unit/structure/test_structure_proofs.py: force method by hand)
#: agree within 10 %: the two model the bars' pockets, shear and torsion differently.
STRUCTURE_PROOF_REL = 0.10

#: The same figure from the frame and from a hand model of exactly the frame's mechanics
#: (Euler-Bernoulli links, two-force members): round-off only, 1e-6 relative leaves ~8
#: orders above float64 eps for the conditioning of a ~100-DOF frame.
STRUCTURE_SAME_MODEL_REL = 1e-6

#: Issue 32 §2: a device fact read back from a written file (C header, MJCF, json: numbers
#: written with repr, so round-trip exact) against the resolved device. Only the order of
#: the arithmetic of a derived value differs (peak current T/Kt in mN m or in N m: ~1 ulp);
#: 1e-12 relative leaves ~4 orders above float64 eps and catches any real disagreement.
OUTPUT_AGREE_REL = 1e-12

#: A [motor] table's continuous torque may differ by this (relative) from what its continuous
#: current carries through Kt (Kt (I_N - I0) .. Kt I_N): data sheets print 3 significant
#: digits, and maxon's own RE 35 figures (38.9 mN m/A x (2.63 - 0.126) A = 97.4 against
#: T_N = 97.2 mN m) agree to 0.2 %; 2 % leaves that rounding and no contradiction.
MOTOR_CONTINUOUS_REL = 0.02

# ---------------------------------------------------------------- printed parts (cad/printing)

#: Dimensional tolerance of an FDM print: +-0.5 mm or +-1 % of the size, whichever is greater
#: ("FDM parts need to be produced within an accuracy of +-0.5 mm or 1% depending on which is
#: greater", "FDM Quality Guideline" of a print service's wiki (Imagine That 3D),
#: https://imaginethat3d.atlassian.net/wiki/spaces/IMAGINETHA/pages/196679/FDM+QUALITY+GUIDELINE).
#: A printed hole is stated with it (:func:`cad.printing.printed_fit`), never with an ISO 286 class.
FDM_TOL_MM = 0.5
FDM_TOL_REL = 0.01

# ---------------------------------------------------------------- identification (issue 37)
#: A log whose commanded current sits at the firmware's clamp (the continuous limit) in more
#: than this fraction of its rows is refused as saturated: the clamp cuts the excitation and
#: the hold, so the current no longer follows the model's torque. The generated routine's
#: excitation peaks at 60 % of the limit and reaches the clamp only in the first hold samples.
IDENT_SATURATION_FRACTION_MAX = 0.02
#: Too little excitation: the crank must travel at least this many encoder counts (peak to
#: peak) during the excitation, and the fit's regressors must be this well conditioned
#: (largest / smallest singular value of the normalized regressor matrix).
IDENT_MIN_TRAVEL_COUNTS = 40
IDENT_CONDITION_MAX = 1e6
#: Samples slower than this fraction of the log's peak crank rate are left out of the fit:
#: Coulomb friction's sign(velocity) is undefined there (stick, the velocity estimate's
#: quantization noise); 5 % keeps > 85 % of a chirp's samples.
IDENT_SLOW_FRACTION = 0.05
#: Verdict tolerances of identify (measured against the datasheet's prediction): apparent mass
#: 10 % (the solids' masses are exact; a printed or hand-made part differs by a few %, a
#: heavier knob or wrong material by more), friction 50 % (the datasheet's friction is an
#: estimate from the motor's no-load current or the paper's identified Fs), gravity load 15 %,
#: a constant torque offset up to 5 % of the motor's continuous torque.
IDENT_MASS_TOL_REL = 0.10
IDENT_FRICTION_TOL_REL = 0.50
IDENT_GRAVITY_TOL_REL = 0.15
IDENT_OFFSET_TOL_FRACTION = 0.05

#: A 5-bar capstan's joint range (cad.families.pantograph.capstan) is the proximal link's angle
#: over the workspace grid widened by this on each side (deg): the handle a little outside the
#: square, and the motion between grid samples, still keep the rope on the drum and the drums
#: clear of each other.
CAPSTAN_RANGE_MARGIN_DEG = 2.0

#: How far below a placed solid's fast bounding box (OCCT ``BRepBndLib::Add``, which holds the
#: solid) :func:`cad.pipeline.family.lowest_z_mm` still computes its exact one (mm): a margin
#: for the fast box only (the answer is every exact box's); 5 mm is far above the shape
#: tolerances (1e-7 .. 1e-3 mm) the fast box is enlarged by.
LOOSE_BOX_MARGIN_MM = 5.0
