//! # harmonav-perception
//!
//! Obstacles from range scans (issue 26, part 1; docs/maths.md §12): a `sensor_msgs/LaserScan`
//! becomes star-shaped obstacles that **provably contain the true obstacle** under three stated
//! priors, persist, and only ever grow. Pure Rust, no ROS; the facade's `Navigator::observe_scan`
//! feeds it (docs/maths.md §12.6).
//!
//! - [`LaserScan`], [`Pose`], [`Reading`]: the ROS fields, validated ([`ScanError`]); NaN, `±∞`
//!   and out-of-range readings classified as ROS does (REP 117);
//! - [`segment()`]: the ordered scan split at range jumps (eq. jump), ends [`End::Occluded`]
//!   beside a closer return;
//! - [`Perception::explained`]: hits within the noise bound of the known boundary or a map
//!   obstacle, or of a perceived shape near the hits it was fitted to, are dropped (eqs.
//!   explained, attribution);
//! - [`fit_segment`]: the conservative star of a segment (eqs. sagitta, region, fit, certify);
//! - [`FreeSpace`]: what the scan shows free (eq. freefan) and the wall prior (eq. wallgap),
//!   left out of each fit's region;
//! - [`merge`]: two overlapping perceived shapes become one star that contains both: the
//!   union itself about a common kernel point (eq. kernel), otherwise its radial hull about
//!   the point that gives the least area (eq. hull);
//! - [`Perception::observe`]: all of it, all or nothing;
//! - [`sim::Lidar`]: a seeded simulated lidar for tests.
//!
//! ## The fit and why it contains the obstacle
//!
//! A segment has hits `p_1..p_m` (measured ranges `r_i` along unit beams `u_i` from the sensor
//! `s`). The true first hits are `q_i = s + r*_i u_i`. The fit is a Fourier star `F` (order
//! [`Options::order`]; or with [`StarForm::Hull`] the radial hull of the cover's discs) about
//! a centre behind the visible arc, certified (eq. certify) to contain
//!
//! ```text
//! Y = (K ∩ H_a ∩ H_b) \ (int(E_a ∪ T_1 ∪ … ∪ T_{m−1} ∪ E_b) ∪ free side beams)      (eq. region)
//! K = ∩_k B(p_k, D + ε)
//! T_i = triangle(s, p_i − κ_i u_i, p_{i+1} − κ_i u_{i+1}),  κ_i = e_i / min(u_i·n_i, u_{i+1}·n_i)
//! e_i = ε + ρ_min − √(ρ_min² − c_i²/4),   c_i = |p_{i+1} − p_i| + 2ε                 (eq. sagitta)
//! H_a = the side of the line of beam j_a holding the hits, j_a the first beam outward of
//!       the first hit whose free part (r_j − ε, or range_max − ε) covers its chord of K    (eq. side)
//! E_a = triangle(s, s + τ u_a, s + τ u_{j_a}),  τ = r_a − ε − sag(2w) − w,
//!       w = 2 r_a sin(∠(u_a, u_{j_a})/2), only when w < 2ρ_min                      (eq. end)
//! ```
//!
//! (and `H_b`, `E_b` at the last hit). A wedge or end triangle is left out when its bound does
//! not apply (`c_i > 2ρ_min`, grazing incidence `u·n < 0.05`, the sensor within `e_i` of the
//! chord's line).
//!
//! **Assumptions** (the guarantee is exactly as strong as these):
//!
//! - **(A1) noise and pose.** The pose is exact and `|r_i − r*_i| ≤ ε` ([`Options::range_noise`])
//!   for every hit of the segment.
//! - **(A2) one obstacle, regular between beams.** The segment's hits lie on one obstacle `O`
//!   (not containing `s`), and between neighbouring hits the boundary visible from `s` is one
//!   arc of curvature radius `≥ ρ_min` ([`Options::rho_min`]) turning by less than `π`.
//! - **(A3) depth.** Every point of `O` lies within `D` ([`Options::max_obstacle_depth`]) of
//!   every hit point `q_i` of the segment: `O ⊂ ∩_i B(q_i, D)`. This holds when
//!   `diam O ≤ D`; it is how far an obstacle may extend behind (and beside) its seen surface.
//!   Obstacles larger than `D` (walls, long furniture) must come from the map.
//! - **(A4) ends.** `O` is a union of discs of radius `ρ_min` (every boundary point has an
//!   inner tangent disc of that radius). Beside a segment's end, between its last beam and a
//!   free side beam `w < 2ρ_min` apart, such a disc can reach no nearer to the sensor than
//!   `r* − sag(2w)`: it cannot pass between the two beams and must cross the end beam behind
//!   its first hit. `E_a` keeps a further `w` of slack for the angular approximation; this
//!   step is argued, not yet proved line by line (docs/maths.md §12).
//!
//! **Claim.** Under (A1)–(A4), `O ⊂ Y ⊂ F`.
//!
//! *Proof.* (A3) and (A1): `O ⊂ ∩ B(q_k, D) ⊂ ∩ B(p_k, D + ε) ⊂ K` (any subset of the hits
//! gives a superset, so `K` uses at most 8). The arc of (A2) between `q_i` and `q_{i+1}` lies in
//! the lens of the two circles of radius `ρ_min` through them (an arc of curvature `≤ 1/ρ_min`
//! turning by less than `π`), so within the sagitta `sag(|q_i q_{i+1}|)` of their chord, and
//! that chord is within `ε` of the measured chord; `|q_i q_{i+1}| ≤ c_i` and `sag` increases,
//! so the visible boundary in the wedge lies within `e_i` of the chord `p_i p_{i+1}`, i.e. in
//! the half-plane `n_i·(x − p_i) ≥ −e_i`. The triangle `T_i` lies in the other half-plane
//! `n_i·(x − p_i) ≤ −e_i` (its three vertices do: `s` by the check `n_i·(p_i − s) ≥ e_i`, the
//! far vertices by the choice of `κ_i`). If a point `x ∈ O` were in `int T_i`, the first point
//! `a` of `O` on the segment `[s, x]` would be visible, in the wedge, and in `int T_i` (a
//! segment from a vertex to an interior point of a triangle is interior but for the vertex, and
//! `a ≠ s`): a contradiction. The side cut: `O` is connected, holds the first hit, lies in the
//! convex `K`, and cannot cross the free beam `j_a`, whose chord cuts `K` in two; so `O ⊂ H_a`.
//! `E_a` by (A4). Along the shared beam `i + 1`, `int(T_i ∪ T_{i+1})` holds points
//! nearer than `r_{i+1} − κ < r*_{i+1}`, free by definition of the first hit. So
//! `O ⊂ K \ int(∪T_i) = Y`; eq. certify gives `Y ⊂ F`. ∎
//!
//! The noise and the sagitta enter only through `e_i`, the room left in front of the chords;
//! without them the cuts remove true boundary that bulges in front of the measured chords, and
//! the containment test fails (the negative control in `tests/containment.rs`).
//!
//! ## Explained hits, growth and disjointness
//!
//! A hit within `ε_x = max(ε, ε_g)` ([`Options::growth_threshold`]) of a map obstacle or of the
//! known boundary is attributed to it (eq. explained), which assumes that an unknown obstacle
//! does not come within `ε + ε_x` of an exact one. A perceived shape explains less: it holds its
//! obstacle and also, on its unseen side closed `D` behind, empty room where a neighbour out of
//! view may stand. So a segment is dropped only when one perceived shape `P` is within `ε_x` of
//! every hit and some hit lies within `d_ev` ([`Options::evidence_radius`]) of the hits `P` was
//! fitted to (eq. attribution), under
//!
//! - **(A5) separation.** Two obstacles stay more than `d_ev + 2ε` apart.
//!
//! Then the segment is on `P`'s obstacle, which `P` holds; any other segment with a hit that no
//! shape explains is fitted whole. This keeps repeated scans of a perceived obstacle from growing
//! it and makes growth events finitely many (`ε_g > 0`: event hits are `min(ε_x − τ, d_ev/2)`
//! apart, docs/maths.md §12.8). A fit that
//! overlaps a perceived shape is merged with it ([`merge`]): the merged star contains both (eq.
//! certify over both boundaries), so perceived shapes only grow and stay disjoint.

#![warn(missing_docs)]

mod boxes;
mod enclosure;
pub mod fit;
pub mod free;
pub mod growth;
pub mod perceived;
pub mod perception;
pub mod scan;
pub mod segment;
pub mod sim;
pub mod walls;
pub mod work;

pub use fit::{Fit, FitFailure, FitParams, SIDE_BEAMS, fit_in_scan, fit_segment, side_beams};
pub use free::{FreeEvidence, FreeSet, FreeSpace, FreeUnion, WallPrior, free_radius, sagitta};
pub use perceived::{
    Certification, MergeFailure, Perceived, StarForm, certified, certified_hull, certified_star,
    merge, merge_clear_of,
};
pub use perception::{Known, Observation, Options, Perception, PerceptionError};
pub use scan::{LaserScan, MAX_ANGLE, MAX_BEAMS, Pose, Reading, ScanError};
pub use segment::{End, Segment, hit_point, segment};
pub use walls::{Walls, WallsError};
pub use work::{Work, work};
