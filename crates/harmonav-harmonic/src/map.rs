//! The boundary-element harmonic map `H = (u, v)` of a [`Domain`] onto the punctured unit disk.
//!
//! **Representation** (per component, `u` shown; `v` shares every matrix):
//!
//! ```text
//! u(x) = Σ_j k_j·W_j(z) + c,     z = (x − x̄)/D,
//! ```
//!
//! `W_j` the closed-form single layer of element `j` (`crate::kernel`), `k_j` its constant
//! density, `c` a constant, `x̄` the bounding box's centre and `D` its diagonal.
//!
//! **Equations** (`N` elements, `M` holes, `N + M + 1` unknowns `k, p, c` per component):
//!
//! ```text
//! u(c_j) = cos(2π s_j)                      j on the outer ring (s_j its midpoint's arc length / perimeter)
//! u(c_j) − p_i = 0                          j on hole i          (u is constant, = p_i, on the hole)
//! Σ_{l ∈ hole i} |E_l| k_l = 0              one row per hole     (zero net flux across hole i)
//! Σ_{l ∈ outer} |E_l| k_l = 0               one row              (zero total charge)
//! ```
//!
//! with `sin` for `v`. One LU of this matrix serves both right-hand sides.
//!
//! *Why a charge row is the flux row.* `Δ ln|x − s|² = 4π δ_s`, so by the divergence theorem
//! the flux of `u` out of any loop that encloses hole `i` and no other element is exactly
//! `4π Σ_{l ∈ hole i} |E_l| k_l`: zero charge is zero flux, exactly, for every such loop
//! (the research notes' length-weighted normal-derivative sum is a quadrature of the same
//! integral; docs/maths.md §11).
//!
//! *Guard against the degenerate scale.* A bare single layer `Σ k_j W_j` cannot represent the
//! constants when the boundary's logarithmic capacity is 1 (for this kernel), and is
//! ill-conditioned near it. The constant `c` with the zero-total-charge row makes the system
//! uniquely solvable at every scale: scaling `z → λz` adds `2 ln λ·Σ_j |E_j| k_j = 0`. The
//! coordinates are also normalised (`z = (x − x̄)/D`, diameter 1, so the capacity is at most ½),
//! which keeps the matrix entries `O(1)` whatever the units.

use std::time::{Duration, Instant};

use faer::Mat;
use faer::linalg::solvers::Solve;
use harmonav_multipole::{C64, Fmm, Options as FmmOptions, Piece, Source};
use nalgebra::{Matrix2, Vector2};

use crate::domain::{Domain, RingId};
use crate::kernel::{self, Panel};
use crate::mesh::{self, Element, MeshError, MeshOptions};
use crate::solve;

/// Largest relative residual `‖A x − b‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞)` accepted from the LU solve;
/// measured values are about 1e-16.
pub const MAX_SOLVE_RESIDUAL: f64 = 1e-10;

/// Fewest elements for which [`HarmonicMap::new`] builds the far field ([`HarmonicMap::eval`]
/// then costs `O(p + near)` instead of `O(N)`). Below it the far field is less than 3× faster
/// per point while its tree costs about twice the solve (release, `N` = 280: 2.4 against 6.3 µs,
/// tree 8 ms, solve 4 ms; docs/benchmarks.md, "Harmonic map cost").
pub const FAR_FIELD_MIN_ELEMENTS: usize = 400;

/// The multipole tolerance of the far field: `|ΔH| ≤ tol·A`, `A = Σ_j 2|k_j||E_j|` (normalised
/// units, both components; [`HarmonicMap::far_field_bound`]). `1e-15` gives the expansion order
/// `p = 60`.
pub const FAR_FIELD_TOLERANCE: f64 = 1e-15;

/// The far field's deepest leaf level `L` (`4^L` leaves). Measured at N ≈ 2 000 (pillared
/// room, dev profile): `L = 6` builds in 0.33 s and evaluates in 1.8 µs, `L = 5` in 0.13 s and
/// 2–3 µs, `L = 4` in 0.06 s and 8–12 µs; the error is the same (rounding, ~1e-14).
const FAR_FIELD_MAX_LEVEL: u32 = 5;

/// The far field's deepest level above [`DEEP_FAR_FIELD_ELEMENTS`] elements: at level 5 an
/// 84 000-element floor leaves about 1 000 near pieces per evaluation (a command took 283 µs);
/// the tree's depth then follows its leaf size (8 pieces) down to this. Below, the level stays
/// at [`FAR_FIELD_MAX_LEVEL`], so the maps that loaded before evaluate as before.
const FAR_FIELD_MAX_LEVEL_LARGE: u32 = 7;

/// The elements above which the far field may go to [`FAR_FIELD_MAX_LEVEL_LARGE`] (the old
/// cap of the dense solve).
const DEEP_FAR_FIELD_ELEMENTS: usize = 5_000;

/// The most elements [`Solver::Auto`] gives to the dense LU; above it, the iterative solve.
/// The crossover measured in docs/maths/13-harmonic-scaling.md (the iterative solve is faster
/// from about 2 000 elements; at 4 851 elements, the TurtleBot3 world of the public maps, the
/// dense LU took 3.8 s and 566 MB). Until 2026-12-06 it was 5 000, the old cap of the dense
/// solve, kept so that every map that loaded before was solved bit for bit as before; every
/// map of the suites but the public ones has fewer than 2 000.
pub const DENSE_MAX_ELEMENTS: usize = 2_000;

/// The most elements [`Solver::Dense`] takes: `8(N + M + 1)²` bytes, 1 GB at 11 000.
pub const DENSE_LIMIT: usize = 11_000;

/// How [`HarmonicMap::new_with`] solves the boundary-element system.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Solver {
    /// The dense LU up to [`DENSE_MAX_ELEMENTS`] elements, the iterative solve above.
    #[default]
    Auto,
    /// The dense LU (faer, partial pivoting), up to [`DENSE_LIMIT`] elements.
    Dense,
    /// Restarted GMRES with the multipole product and a two-level preconditioner
    /// (docs/maths/13-harmonic-scaling.md), whatever `N`: `O(N)` memory.
    Iterative,
}

/// Pieces' ends within this (normalised units, `|z| ≤ 1`) of an element's end are that end:
/// the multipole tree computes the last piece's end as `A + (B − A)·1`, an ulp or so from `B`.
const SNAP: f64 = 16.0 * f64::EPSILON;

/// Where [`HarmonicMap::new`]'s time went (wall clock, this thread).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SetupCost {
    /// Meshing ([`mesh::mesh`]).
    pub mesh: Duration,
    /// The `(N + M + 1)²` closed-form matrix entries and the right-hand sides.
    pub assembly: Duration,
    /// The LU factorisation, the solve of both right-hand sides and the residual check.
    pub factor: Duration,
    /// The far field's multipole tree (zero without one).
    pub far_field: Duration,
    /// GMRES iterations of the iterative solve, both components (0 for the dense LU, where
    /// `assembly` is the matrix and `factor` the LU; in the iterative solve `assembly` is the
    /// multipole tree, the near matrix and the preconditioner, and `factor` the iterations).
    pub iterations: usize,
}

impl SetupCost {
    /// The sum of the parts.
    #[must_use]
    pub fn total(&self) -> Duration {
        self.mesh + self.assembly + self.factor + self.far_field
    }
}

/// Why a harmonic map cannot be built.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SolveError {
    /// The mesh options are bad or give too many elements.
    Mesh(MeshError),
    /// The factorisation gave non-finite densities or a residual above [`MAX_SOLVE_RESIDUAL`]
    /// (a numerically singular system).
    Singular {
        /// The relative residual (infinite when the solution was not finite).
        residual: f64,
    },
    /// The far field's multipole tree refused its options ([`HarmonicMap::with_far_field`]: a
    /// tolerance outside `[1e-15, 1e-2]`).
    FarField(harmonav_multipole::FmmError),
    /// The iterative solve ([`Solver::Iterative`]) did not reach [`MAX_SOLVE_RESIDUAL`].
    NotConverged {
        /// The relative residual `‖b − A x‖₂/‖b‖₂` it reached (the worse component).
        residual: f64,
        /// Its GMRES iterations, both components.
        iterations: usize,
    },
}

impl std::fmt::Display for SolveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Mesh(e) => write!(f, "{e}"),
            Self::Singular { residual } => write!(
                f,
                "the boundary-element system is numerically singular (relative residual {residual:e})"
            ),
            Self::FarField(reason) => write!(f, "the far field cannot be built: {reason}"),
            Self::NotConverged {
                residual,
                iterations,
            } => write!(
                f,
                "the iterative boundary-element solve stopped at relative residual {residual:e} \
                 after {iterations} iterations"
            ),
        }
    }
}

impl std::error::Error for SolveError {}

impl From<MeshError> for SolveError {
    fn from(e: MeshError) -> Self {
        Self::Mesh(e)
    }
}

/// Why `H` cannot be evaluated at a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum EvalError {
    /// The point has a NaN or infinite coordinate.
    NonFinite,
    /// The point is an element's end point, where `∇W_j` is logarithmically infinite.
    AtElementEnd,
}

impl std::fmt::Display for EvalError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NonFinite => write!(f, "the point has a NaN or infinite coordinate"),
            Self::AtElementEnd => write!(
                f,
                "the point is a boundary element's end point, where the Jacobian is infinite"
            ),
        }
    }
}

impl std::error::Error for EvalError {}

/// `H(x)` and its exact Jacobian `J_H(x) = [∇u; ∇v]` (rows), in the domain's units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapEval {
    /// `H(x) = (u, v)`, in the unit disk for `x` in the free space away from the boundary layer.
    pub value: Vector2<f64>,
    /// `J_H(x)`: row 0 is `∇u`, row 1 is `∇v`.
    pub jacobian: Matrix2<f64>,
}

impl MapEval {
    /// `det J_H = u_x v_y − u_y v_x` (positive where `H` preserves orientation).
    #[must_use]
    pub fn det(&self) -> f64 {
        self.jacobian.determinant()
    }
}

/// Collocation residuals and hole fluxes of a solved map (see [`HarmonicMap::residuals`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Residuals {
    /// `max_j |H(c_j) − (cos 2πs_j, sin 2πs_j)|` over outer midpoints.
    pub outer: f64,
    /// `max_j |H(c_j) − p_i|` over hole midpoints.
    pub holes: f64,
    /// `max_i |flux_i|` (both components), [`HarmonicMap::hole_flux`].
    pub flux: f64,
}

/// The solved boundary-element harmonic map of a domain (module docs: the equations).
#[derive(Clone, Debug)]
pub struct HarmonicMap {
    domain: Domain,
    elements: Vec<Element>,
    panels: Vec<Panel>,
    /// Element range of each ring (outer first).
    ranges: Vec<std::ops::Range<usize>>,
    /// `2π s_j` for the outer elements.
    angles: Vec<f64>,
    centre: Vector2<f64>,
    scale: f64,
    constant: Vector2<f64>,
    punctures: Vec<Vector2<f64>>,
    solve_residual: f64,
    /// The multipole tree of the single layers with weights `(2k^u_j, 2k^v_j)` (normalised
    /// units), when [`HarmonicMap::eval`] uses it.
    far: Option<Box<FarField>>,
    cost: SetupCost,
}

/// The far field: the tree and its bound `tol·A`, `A = Σ_j 2|k_j||E_j|` (the larger
/// component's).
#[derive(Clone, Debug)]
struct FarField {
    fmm: Fmm<2>,
    bound: f64,
}

/// The near pieces' sums: `u, v` and their normalised gradients.
#[derive(Default)]
struct Near {
    u: f64,
    v: f64,
    ux: f64,
    uy: f64,
    vx: f64,
    vy: f64,
    singular: bool,
}

/// What [`HarmonicMap::enclosure`] gives: `H` and `J_H` at the disc's centre, and the radius
/// of a disc about `H(x)` that holds the image of the whole disc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Enclosure {
    /// `H(x)` and `J_H(x)` at the centre.
    pub eval: MapEval,
    /// `r` with `H(B(x, ρ)) ⊂ B(H(x), r)` (infinite when the disc meets an element).
    pub radius: f64,
    /// `[e_u, e_v]` with `|∇u(y) − ∇u(x)| ≤ e_u` and `|∇v(y) − ∇v(x)| ≤ e_v` on the disc: the
    /// rows of `J_H` over it (infinite when the disc meets an element).
    pub gradient_radius: [f64; 2],
}

/// Data that several evaluations share: the value, Jacobian and (for the certificate) the
/// Hessian-norm bounds of both components over a disc of radius `rho` (normalised units).
pub(crate) struct Bounded {
    pub eval: MapEval,
    /// `sup ‖∇²u‖₂` and `sup ‖∇²v‖₂` over the disc (world units), infinite if it meets Γ.
    pub hessian: [f64; 2],
    /// `∇²u(x)` and `∇²v(x)` exactly (world units; zero without a disc).
    pub hessian_at: [Matrix2<f64>; 2],
    /// `sup |F'''|` of `u` and of `v` over the disc (`u = Re F`): bounds of the third
    /// derivatives, `Σ_j |k_j|·4|E_j|/(d_j − ρ)³`; infinite if the disc meets Γ.
    pub third: [f64; 2],
}

impl HarmonicMap {
    /// Meshes `domain` ([`mesh::mesh`]), assembles the `(N + M + 1)²` system of the module docs,
    /// factors it once (faer's partial-pivoting LU) and solves for `u` and `v` together.
    /// Cost: `O(N²)` closed-form entries, `(2/3)(N + M + 1)³` flops.
    ///
    /// # Errors
    /// [`SolveError::Mesh`] for bad options or too many elements, [`SolveError::Singular`] when
    /// the solve fails its residual check.
    pub fn new(domain: &Domain, options: &MeshOptions) -> Result<Self, SolveError> {
        Self::new_with(domain, options, Solver::Auto)
    }

    /// [`HarmonicMap::new`] with a choice of [`Solver`]: the same equations, solved by the
    /// dense LU or iteratively (GMRES, the multipole product; docs/maths/13-harmonic-scaling.md).
    /// The two agree to the iterative solve's tolerance (tested on the test plans and random
    /// polygons with holes).
    ///
    /// # Errors
    /// As [`HarmonicMap::new`]; [`SolveError::Mesh`] with [`MeshError::TooManyElements`] for
    /// [`Solver::Dense`] above [`DENSE_LIMIT`]; [`SolveError::NotConverged`] when GMRES stops
    /// above [`MAX_SOLVE_RESIDUAL`].
    pub fn new_with(
        domain: &Domain,
        options: &MeshOptions,
        solver: Solver,
    ) -> Result<Self, SolveError> {
        let clock = Instant::now();
        let elements = mesh::mesh(domain, options)?;
        let mut cost = SetupCost {
            mesh: clock.elapsed(),
            ..SetupCost::default()
        };
        let clock = Instant::now();
        let (lower, upper) = domain.bounding_box();
        let centre = (lower + upper) * 0.5;
        let scale = domain.diameter();
        let n = elements.len();
        let holes = domain.holes().len();
        let mut ranges = Vec::with_capacity(holes + 1);
        let mut start = 0;
        for r in 0..=holes {
            let id = if r == 0 {
                RingId::Outer
            } else {
                RingId::Hole(r - 1)
            };
            let end = start
                + elements[start..]
                    .iter()
                    .take_while(|e| e.ring == id)
                    .count();
            ranges.push(start..end);
            start = end;
        }
        let mut panels: Vec<Panel> = elements
            .iter()
            .map(|e| {
                let a = (e.a - centre) / scale;
                let b = (e.b - centre) / scale;
                let d = b - a;
                let len = d.norm();
                let m = (a + b) * 0.5;
                Panel {
                    centre: [m.x, m.y],
                    tangent: [d.x / len, d.y / len],
                    half: len / 2.0,
                    ku: 0.0,
                    kv: 0.0,
                }
            })
            .collect();
        // Boundary data: the outer midpoints by normalised arc length, s_j ∈ (0, 1).
        let perimeter: f64 = elements[ranges[0].clone()]
            .iter()
            .map(Element::length)
            .sum();
        let mut arc = 0.0;
        let angles: Vec<f64> = elements[ranges[0].clone()]
            .iter()
            .map(|e| {
                let l = e.length();
                let s = (arc + l / 2.0) / perimeter;
                arc += l;
                std::f64::consts::TAU * s
            })
            .collect();
        let ring_of: Vec<usize> = ranges
            .iter()
            .enumerate()
            .flat_map(|(r, range)| std::iter::repeat_n(r, range.len()))
            .collect();
        let mean = panels.iter().map(|p| 2.0 * p.half).sum::<f64>() / n as f64;
        let size = n + holes + 1;
        let dense = match solver {
            Solver::Auto => n <= DENSE_MAX_ELEMENTS,
            Solver::Dense => {
                if n > DENSE_LIMIT {
                    return Err(SolveError::Mesh(MeshError::TooManyElements {
                        elements: n,
                        max: DENSE_LIMIT,
                    }));
                }
                true
            }
            Solver::Iterative => false,
        };
        let (solution, residual) = if dense {
            Self::solve_dense(
                &panels,
                &ring_of,
                holes,
                &angles,
                ranges[0].end,
                mean,
                &mut cost,
            )?
        } else {
            let rhs = |f: fn(f64) -> f64| -> Vec<f64> {
                (0..size)
                    .map(|row| {
                        if row < ranges[0].end {
                            f(angles[row])
                        } else {
                            0.0
                        }
                    })
                    .collect()
            };
            let (bu, bv) = (rhs(f64::cos), rhs(f64::sin));
            cost.assembly = clock.elapsed();
            let clock = Instant::now();
            let (x, stats) =
                solve::solve(&panels, &ranges, mean, [&bu, &bv]).map_err(SolveError::FarField)?;
            cost.assembly += stats.assembly;
            cost.factor = clock.elapsed().saturating_sub(stats.assembly);
            cost.iterations = stats.iterations;
            if stats.residual.is_nan() || stats.residual > MAX_SOLVE_RESIDUAL {
                return Err(SolveError::NotConverged {
                    residual: stats.residual,
                    iterations: stats.iterations,
                });
            }
            (x, stats.residual)
        };
        let [xu, xv] = &solution;
        for (j, p) in panels.iter_mut().enumerate() {
            p.ku = xu[j];
            p.kv = xv[j];
        }
        let punctures = (0..holes)
            .map(|i| Vector2::new(xu[n + i], xv[n + i]))
            .collect();
        let constant = Vector2::new(xu[size - 1], xv[size - 1]);
        let map = Self {
            domain: domain.clone(),
            elements,
            panels,
            ranges,
            angles,
            centre,
            scale,
            constant,
            punctures,
            solve_residual: residual,
            far: None,
            cost,
        };
        if n >= FAR_FIELD_MIN_ELEMENTS {
            map.with_far_field(Some(FAR_FIELD_TOLERANCE))
        } else {
            Ok(map)
        }
    }

    /// The dense LU of the `(N + M + 1)²` system for both right-hand sides (the module docs'
    /// equations), with its residual check; the solutions as columns `[u, v]`.
    fn solve_dense(
        panels: &[Panel],
        ring_of: &[usize],
        holes: usize,
        angles: &[f64],
        outer_end: usize,
        mean: f64,
        cost: &mut SetupCost,
    ) -> Result<([Vec<f64>; 2], f64), SolveError> {
        let clock = Instant::now();
        let n = panels.len();
        let size = n + holes + 1;
        // Entry (row, col): the module docs' equations; charge rows scaled by the mean element
        // length so that every row is O(1).
        let a = Mat::<f64>::from_fn(size, size, |row, col| {
            if row < n {
                if col < n {
                    let (p, q) = (&panels[row], &panels[col]);
                    let dx = p.centre[0] - q.centre[0];
                    let dy = p.centre[1] - q.centre[1];
                    let xo = dx * q.tangent[0] + dy * q.tangent[1];
                    let yo = -dx * q.tangent[1] + dy * q.tangent[0];
                    let yo = if row == col { 0.0 } else { yo };
                    kernel::element(xo, yo, q.half).w
                } else if col == size - 1 {
                    1.0
                } else if ring_of[row] == col - n + 1 {
                    -1.0
                } else {
                    0.0
                }
            } else if col < n {
                let ring = if row == size - 1 { 0 } else { row - n + 1 };
                if ring_of[col] == ring {
                    2.0 * panels[col].half / mean
                } else {
                    0.0
                }
            } else {
                0.0
            }
        });
        let b = Mat::<f64>::from_fn(size, 2, |row, col| {
            if row < outer_end {
                if col == 0 {
                    angles[row].cos()
                } else {
                    angles[row].sin()
                }
            } else {
                0.0
            }
        });
        cost.assembly += clock.elapsed();
        let clock = Instant::now();
        let lu = a.partial_piv_lu();
        let x = lu.solve(&b);
        let residual = relative_residual(&a, &x, &b);
        cost.factor = clock.elapsed();
        // NaN (a non-finite solution) fails this test too.
        if residual.is_nan() || residual > MAX_SOLVE_RESIDUAL {
            return Err(SolveError::Singular { residual });
        }
        let column = |c: usize| (0..size).map(|row| x[(row, c)]).collect::<Vec<f64>>();
        Ok(([column(0), column(1)], residual))
    }

    /// The same map with a far field of tolerance `tol` (`Some(tol)`) or without one (`None`),
    /// whatever `N` ([`HarmonicMap::new`] takes [`FAR_FIELD_TOLERANCE`] from
    /// [`FAR_FIELD_MIN_ELEMENTS`] elements). The far field is a fast multipole tree
    /// (harmonav-multipole) of the single layers,
    ///
    /// ```text
    /// u = Re Σ_j 2k^u_j G_j(z) + c_u,   G_j(z) = ∫_{E_j} log(z − s)|ds|,   W_j = 2 Re G_j,
    /// ```
    ///
    /// (likewise `v`), built in `O(N p + 4^L p²)`; its truncation error is at most `tol·A`
    /// ([`HarmonicMap::far_field_bound`]).
    ///
    /// # Errors
    /// [`SolveError::FarField`] for a tolerance outside `[1e-15, 1e-2]`.
    pub fn with_far_field(mut self, tolerance: Option<f64>) -> Result<Self, SolveError> {
        self.far = None;
        self.cost.far_field = Duration::ZERO;
        let Some(tolerance) = tolerance else {
            return Ok(self);
        };
        let clock = Instant::now();
        let mut sources = Vec::with_capacity(self.panels.len());
        let mut weights = Vec::with_capacity(self.panels.len());
        let (mut au, mut av) = (0.0, 0.0);
        for p in &self.panels {
            let c = C64::new(p.centre[0], p.centre[1]);
            let t = C64::new(p.tangent[0], p.tangent[1]);
            sources.push(Source::Segment(c - t * p.half, c + t * p.half));
            weights.push([2.0 * p.ku, 2.0 * p.kv]);
            au += 4.0 * p.half * p.ku.abs();
            av += 4.0 * p.half * p.kv.abs();
        }
        let options = FmmOptions {
            tolerance,
            max_level: if self.panels.len() > DEEP_FAR_FIELD_ELEMENTS {
                FAR_FIELD_MAX_LEVEL_LARGE
            } else {
                FAR_FIELD_MAX_LEVEL
            },
            ..FmmOptions::default()
        };
        let fmm = Fmm::new(&sources, &weights, &options).map_err(SolveError::FarField)?;
        self.far = Some(Box::new(FarField {
            fmm,
            bound: tolerance * au.max(av),
        }));
        self.cost.far_field = clock.elapsed();
        Ok(self)
    }

    /// The far field's expansion order `p` and leaf level `L` (`4^L` leaves), `None` without one.
    #[must_use]
    pub fn far_field_levels(&self) -> Option<(usize, u32)> {
        self.far.as_ref().map(|f| (f.fmm.order(), f.fmm.levels()))
    }

    /// Whether [`HarmonicMap::eval`] takes the far field.
    #[must_use]
    pub fn has_far_field(&self) -> bool {
        self.far.is_some()
    }

    /// The far field's stated error bound on `H` (unit-disk units), `tol·A` with
    /// `A = max(Σ_j 2|k^u_j||E_j|, Σ_j 2|k^v_j||E_j|)` (normalised lengths; harmonav-multipole's
    /// `|ΔRe F| ≤ tol·A`); `None` without a far field. It bounds the truncation only: the
    /// rounding of the sums (about 1e-14, docs/maths.md §11) comes on top, in both paths.
    #[must_use]
    pub fn far_field_bound(&self) -> Option<f64> {
        self.far.as_ref().map(|f| f.bound)
    }

    /// Where [`HarmonicMap::new`]'s time went (mesh, assembly, LU, far field).
    #[must_use]
    pub fn setup_cost(&self) -> SetupCost {
        self.cost
    }

    /// `H(x)` and its exact Jacobian. With the far field ([`HarmonicMap::has_far_field`]) in
    /// `O(p + near)`: the multipole tree's local expansion for the elements beyond the 3 × 3
    /// leaves about `x` (`u = Re F_u + c_u`, `∇u = (Re F'_u, −Im F'_u)/D`), and the closed form of
    /// `crate::kernel` on each near piece (an element, or its part inside one leaf). Without it
    /// [`HarmonicMap::eval_direct`]. The two differ by the far field's truncation
    /// ([`HarmonicMap::far_field_bound`]) plus the rounding of both sums: measured ≤ 1.5e-13 of
    /// the map's scale on the test plans, tested ≤ 1e-12 (docs/maths.md §11).
    ///
    /// Defined everywhere off the element end points; it is the harmonic map on the free space
    /// (inside a hole it is the single layer's harmonic continuation, which means nothing).
    /// Within about half an element of the boundary it may fold or leave the disk
    /// (docs/maths.md §11): certify with [`crate::certify`].
    ///
    /// # Errors
    /// [`EvalError::NonFinite`] for a NaN or infinite point, [`EvalError::AtElementEnd`] at an
    /// element's end point.
    pub fn eval(&self, x: Vector2<f64>) -> Result<MapEval, EvalError> {
        match &self.far {
            Some(far) => self.eval_far(&far.fmm, x),
            None => self.eval_direct(x),
        }
    }

    /// `H(x)` and its exact Jacobian by the direct sum, `O(N)`: per element two logarithms and
    /// one `atan2` (`crate::kernel`), `J_H = [Σ k^u_j ∇W_j; Σ k^v_j ∇W_j] / D`. Errors as
    /// [`HarmonicMap::eval`].
    ///
    /// # Errors
    /// [`EvalError::NonFinite`], [`EvalError::AtElementEnd`].
    pub fn eval_direct(&self, x: Vector2<f64>) -> Result<MapEval, EvalError> {
        self.eval_bounded(x, None).map(|b| b.eval)
    }

    /// The far-field path of [`HarmonicMap::eval`].
    fn eval_far(&self, fmm: &Fmm<2>, x: Vector2<f64>) -> Result<MapEval, EvalError> {
        if !(x.x.is_finite() && x.y.is_finite()) {
            return Err(EvalError::NonFinite);
        }
        let z = (x - self.centre) / self.scale;
        let mut near = Near::default();
        let [fu, fv] = fmm.eval(C64::new(z.x, z.y), |piece| {
            self.add_piece(&mut near, z, piece)
        });
        if near.singular {
            return Err(EvalError::AtElementEnd);
        }
        let s = self.scale;
        // ∇Re F = (Re F', −Im F').
        Ok(MapEval {
            value: Vector2::new(fu.value + near.u, fv.value + near.v) + self.constant,
            jacobian: Matrix2::new(
                (fu.d1.re + near.ux) / s,
                (near.uy - fu.d1.im) / s,
                (fv.d1.re + near.vx) / s,
                (near.vy - fv.d1.im) / s,
            ),
        })
    }

    /// Adds one near piece (normalised point `z`): `crate::kernel::interval` on the piece's
    /// span `[t₀, t₁]` along its element, in the element's own frame (the direct sum's local
    /// coordinates, so that the element's end points are decided exactly as there).
    fn add_piece(&self, near: &mut Near, z: Vector2<f64>, piece: &Piece) {
        let Some(p) = self.panels.get(piece.source) else {
            return;
        };
        let Source::Segment(s0, s1) = piece.shape else {
            return;
        };
        let (tx, ty) = (p.tangent[0], p.tangent[1]);
        let dx = z.x - p.centre[0];
        let dy = z.y - p.centre[1];
        let xo = dx * tx + dy * ty;
        let yo = -dx * ty + dy * tx;
        let along = |s: C64| {
            let t = (s.re - p.centre[0]) * tx + (s.im - p.centre[1]) * ty;
            if (t + p.half).abs() <= SNAP {
                -p.half
            } else if (t - p.half).abs() <= SNAP {
                p.half
            } else {
                t
            }
        };
        let (t0, t1) = (along(s0), along(s1));
        // A piece shorter than the snap (a cut an ulp from an end) carries nothing.
        if t1 <= t0 {
            return;
        }
        let (l, at_start, at_end) = kernel::interval(xo, yo, t0, t1);
        if (at_start && t0 == -p.half) || (at_end && t1 == p.half) {
            near.singular = true;
        }
        let gx = l.gx * tx - l.gy * ty;
        let gy = l.gx * ty + l.gy * tx;
        near.u += p.ku * l.w;
        near.v += p.kv * l.w;
        near.ux += p.ku * gx;
        near.uy += p.ku * gy;
        near.vx += p.kv * gx;
        near.vy += p.kv * gy;
    }

    /// [`HarmonicMap::eval`], plus (with `rho = Some(r)`, world units) bounds of `‖∇²u‖₂` and
    /// `‖∇²v‖₂` on the disc of radius `r` about `x`:
    ///
    /// ```text
    /// ‖∇²u(y)‖₂ ≤ Σ_j |k_j| ∫_{E_j} ‖∇² ln|y − s|²‖₂ ds ≤ Σ_j |k_j| · 2|E_j| / (d_j − r)²,
    /// ```
    ///
    /// `d_j = dist(x, E_j)`, since `∇² ln|w|² = 2(|w|²I − 2wwᵀ)/|w|⁴` has eigenvalues `±2/|w|²`
    /// (infinite when some `d_j ≤ r`).
    pub(crate) fn eval_bounded(
        &self,
        x: Vector2<f64>,
        rho: Option<f64>,
    ) -> Result<Bounded, EvalError> {
        if !(x.x.is_finite() && x.y.is_finite()) {
            return Err(EvalError::NonFinite);
        }
        let z = (x - self.centre) / self.scale;
        let r = rho.map(|r| r / self.scale);
        let (mut u, mut v) = (0.0, 0.0);
        let (mut ux, mut uy, mut vx, mut vy) = (0.0, 0.0, 0.0, 0.0);
        let (mut hu, mut hv) = (0.0, 0.0);
        // Σ k_j F_j''(z) of u and v as complex numbers (re, im), and the third-derivative bounds.
        let (mut su, mut sv) = ((0.0, 0.0), (0.0, 0.0));
        let (mut tu, mut tv) = (0.0, 0.0);
        for p in &self.panels {
            let dx = z.x - p.centre[0];
            let dy = z.y - p.centre[1];
            let (tx, ty) = (p.tangent[0], p.tangent[1]);
            let xo = dx * tx + dy * ty;
            let yo = -dx * ty + dy * tx;
            let l = kernel::element(xo, yo, p.half);
            if l.singular {
                return Err(EvalError::AtElementEnd);
            }
            // World-axis gradient: ∂W/∂xo along t, ∂W/∂yo along n = (−t_y, t_x).
            let gx = l.gx * tx - l.gy * ty;
            let gy = l.gx * ty + l.gy * tx;
            u += p.ku * l.w;
            v += p.kv * l.w;
            ux += p.ku * gx;
            uy += p.ku * gy;
            vx += p.kv * gx;
            vy += p.kv * gy;
            if let Some(r) = r {
                let along = (xo.abs() - p.half).max(0.0);
                let d = (along * along + yo * yo).sqrt();
                let gap = d - r;
                let w = if gap > 0.0 {
                    4.0 * p.half / (gap * gap)
                } else {
                    f64::INFINITY
                };
                hu += p.ku.abs() * w;
                hv += p.kv.abs() * w;
                // The element's W = 2 Re G, G(z) = ∫ log(z − t) dt over [−a, a] (local
                // z = xo + i·yo), so F = 2G has F'' = −4a/(z² − a²) and
                // |F'''| = |4∫dt/(z − t)³| ≤ 8a/(d − ρ)³ on the disc. In world axes
                // F''_w = F''·(t_x − i·t_y)² (d/dz_w = e^{−iα} d/dz).
                let t3 = if gap > 0.0 {
                    8.0 * p.half / (gap * gap * gap)
                } else {
                    f64::INFINITY
                };
                tu += p.ku.abs() * t3;
                tv += p.kv.abs() * t3;
                let (dr, di) = (xo * xo - yo * yo - p.half * p.half, 2.0 * xo * yo);
                let d2 = dr * dr + di * di;
                let (fr, fi) = (-4.0 * p.half * dr / d2, 4.0 * p.half * di / d2);
                let (rr, ri) = (tx * tx - ty * ty, -2.0 * tx * ty);
                let (wr, wi) = (fr * rr - fi * ri, fr * ri + fi * rr);
                su = (su.0 + p.ku * wr, su.1 + p.ku * wi);
                sv = (sv.0 + p.kv * wr, sv.1 + p.kv * wi);
            }
        }
        let s = self.scale;
        // u = Re F: u_xx = Re F'', u_xy = −Im F'', u_yy = −u_xx (harmonic).
        let hess = |(re, im): (f64, f64)| Matrix2::new(re, -im, -im, -re) / (s * s);
        Ok(Bounded {
            eval: MapEval {
                value: Vector2::new(u, v) + self.constant,
                jacobian: Matrix2::new(ux / s, uy / s, vx / s, vy / s),
            },
            hessian: [hu / (s * s), hv / (s * s)],
            hessian_at: [hess(su), hess(sv)],
            third: [tu / (s * s * s), tv / (s * s * s)],
        })
    }

    /// A disc that holds the image of a disc: `H(B(x, ρ)) ⊂ B(H(x), r)` with
    ///
    /// ```text
    /// r = ρ‖J_H(x)‖_F + ½ρ²·√(H_u² + H_v²),   H_u ≥ sup_{B(x,ρ)} ‖∇²u‖₂, H_v likewise,
    /// ```
    ///
    /// Taylor's theorem for each component, with the single-layer Hessian bounds of
    /// `eval_bounded` (`Σ_j |k_j|·2|E_j|/(d_j − ρ)²`). Certified to rounding; it ignores
    /// cancellation between elements, so it is loose where the elements are near. `r` is
    /// infinite when the disc meets an element. Used to bound `Θ` over a cell
    /// (`harmonav-floorplan`'s certified `c_δ`, docs/maths.md §13.5).
    ///
    /// The rows of `J_H` over the disc, each the better of the first- and second-order bounds
    /// of §13.5 (`A = ∇²u(x)` exact, `‖A‖₂ = |F''|`, `T_u` the third-derivative bound):
    ///
    /// ```text
    /// |∇u(x + e) − ∇u(x)| ≤ e_u = min(ρ·H_u, ρ‖A‖₂ + ½ρ²·T_u),   v likewise      (eq. jacball)
    /// ```
    ///
    /// (the direction of `∇Θ` over a cell, `harmonav-floorplan`'s slide level, §13.9).
    ///
    /// # Errors
    /// [`EvalError::NonFinite`] for a NaN or infinite point, [`EvalError::AtElementEnd`] at an
    /// element's end point; a negative or NaN `rho` is [`EvalError::NonFinite`].
    pub fn enclosure(&self, x: Vector2<f64>, rho: f64) -> Result<Enclosure, EvalError> {
        if !(rho >= 0.0 && rho.is_finite()) {
            return Err(EvalError::NonFinite);
        }
        let b = self.eval_bounded(x, Some(rho))?;
        let [hu, hv] = b.hessian;
        let radius = rho * b.eval.jacobian.norm() + 0.5 * rho * rho * hu.hypot(hv);
        // ‖A‖₂ of a symmetric traceless [[p, q], [q, −p]] is √(p² + q²) (eigenvalues ±).
        let row = |first: f64, a: &Matrix2<f64>, third: f64| {
            (rho * first).min(rho * a[(0, 0)].hypot(a[(0, 1)]) + 0.5 * rho * rho * third)
        };
        let gradient_radius = [
            row(hu, &b.hessian_at[0], b.third[0]),
            row(hv, &b.hessian_at[1], b.third[1]),
        ];
        Ok(Enclosure {
            eval: b.eval,
            radius,
            gradient_radius,
        })
    }

    /// The punctures `p_i = H(hole i)`, one per hole in order: unknowns of the solve.
    #[must_use]
    pub fn punctures(&self) -> &[Vector2<f64>] {
        &self.punctures
    }

    /// The domain the map was built on.
    #[must_use]
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// The boundary elements (world coordinates), outer ring first, then each hole.
    #[must_use]
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// The longest element `h_max` (world units): the scale of the boundary layer, so the
    /// natural certificate distance is `δ ≥ h_max`.
    #[must_use]
    pub fn max_element_length(&self) -> f64 {
        self.elements
            .iter()
            .map(Element::length)
            .fold(0.0, f64::max)
    }

    /// The prescribed boundary angle `2π s_j` of outer element `j` (its midpoint maps to
    /// `(cos, sin)` of it): monotone from 0 at outer vertex 0, so the boundary correspondence
    /// is a homeomorphism onto the circle.
    #[must_use]
    pub fn boundary_angles(&self) -> &[f64] {
        &self.angles
    }

    /// Flux of `(u, v)` out of any loop that encloses hole `i` and no other element:
    /// `4π Σ_{l ∈ hole i} |E_l| k_l` (the divergence theorem with `Δ ln|x − s|² = 4π δ_s`;
    /// it is the same in world and normalised units). The solve makes it zero; `None` for a
    /// hole that does not exist.
    #[must_use]
    pub fn hole_flux(&self, hole: usize) -> Option<Vector2<f64>> {
        let range = self.ranges.get(hole + 1)?.clone();
        let (mut fu, mut fv) = (0.0, 0.0);
        for p in &self.panels[range] {
            fu += 2.0 * p.half * p.ku;
            fv += 2.0 * p.half * p.kv;
        }
        let c = 2.0 * std::f64::consts::TAU;
        Some(Vector2::new(c * fu, c * fv))
    }

    /// The solve's relative residual: the dense LU's `‖A x − b‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞)`, or
    /// the iterative solve's `‖A x − b‖₂ / ‖b‖₂` (the worse component, `A x` by the multipole
    /// product; [`SetupCost::iterations`] tells which ran).
    #[must_use]
    pub fn solve_residual(&self) -> f64 {
        self.solve_residual
    }

    /// Collocation residuals and fluxes, re-evaluated through [`HarmonicMap::eval`] at every
    /// midpoint (`O(N²)`): what the equations demand, measured on the evaluated map.
    #[must_use]
    pub fn residuals(&self) -> Residuals {
        let mut out = Residuals {
            outer: 0.0,
            holes: 0.0,
            flux: 0.0,
        };
        for (r, range) in self.ranges.iter().enumerate() {
            for j in range.clone() {
                let Ok(e) = self.eval(self.elements[j].midpoint()) else {
                    out.outer = f64::INFINITY;
                    continue;
                };
                if r == 0 {
                    let t = self.angles[j];
                    let err = (e.value - Vector2::new(t.cos(), t.sin())).norm();
                    out.outer = out.outer.max(err);
                } else {
                    out.holes = out.holes.max((e.value - self.punctures[r - 1]).norm());
                }
            }
        }
        for i in 0..self.punctures.len() {
            if let Some(f) = self.hole_flux(i) {
                out.flux = out.flux.max(f.amax());
            }
        }
        out
    }
}

/// `‖A x − b‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞)`, infinite if anything is not finite.
fn relative_residual(a: &Mat<f64>, x: &Mat<f64>, b: &Mat<f64>) -> f64 {
    let r = a * x - b;
    let inf_norm = |m: &Mat<f64>| {
        let mut worst = 0.0_f64;
        for i in 0..m.nrows() {
            let mut s = 0.0;
            for j in 0..m.ncols() {
                s += m[(i, j)].abs();
            }
            if !s.is_finite() {
                return f64::INFINITY;
            }
            worst = worst.max(s);
        }
        worst
    };
    let num = inf_norm(&r);
    let den = inf_norm(a) * inf_norm(x) + inf_norm(b);
    if num.is_finite() && den.is_finite() && den > 0.0 {
        num / den
    } else {
        f64::INFINITY
    }
}
