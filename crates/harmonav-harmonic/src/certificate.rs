//! Checks that the discrete map is a local diffeomorphism into the disk on
//! `W_δ = {x ∈ W_s : dist(x, ∂W_s) ≥ δ}`.
//!
//! Two checks, named for what they prove:
//!
//! - [`sampled_check`]: `det J_H` and `|H|` on a grid of `W_δ`. It proves nothing between the
//!   samples; it finds folds and reports the smallest `det J_H` and where.
//! - [`certify`]: a covering of `W_δ` by square cells of half-diagonal `ρ`, each decided by a
//!   **Lipschitz bound** from its centre `x`. With `H_u ≥ sup ‖∇²u‖₂`, `H_v ≥ sup ‖∇²v‖₂` over
//!   the cell (from the element distances, [`crate::HarmonicMap`]'s single-layer Hessian bound
//!   `Σ_j |k_j|·2|E_j|/(d_j − ρ)²`), for every `y` in the cell
//!
//!   ```text
//!   det J(y) ≥ det J(x) − ρ(H_u|∇v(x)| + H_v|∇u(x)|) − ρ² H_u H_v,
//!   |H(y)|  ≤ |H(x)| + ρ‖J(x)‖_F + ½ρ² √(H_u² + H_v²),
//!   ```
//!
//!   (the first from `D_e det[∇u, ∇v] = det[∇²u e, ∇v] + det[∇u, ∇²v e]` integrated along
//!   `x → y`, the second from Taylor's theorem). A cell whose bounds give `det J > 0` and
//!   `|H| < 1` is certified; one whose centre folds (in `W_δ`) is a counterexample; any other
//!   cell is split in four, up to a depth and an evaluation budget, and what is left is
//!   reported as undecided area. Cells are dropped only when `sd(x) + ρ < δ` (`sd` the signed
//!   distance, 1-Lipschitz), so the certified cells cover all of `W_δ` when nothing is left
//!   undecided. That bound ignores cancellation between elements, so it is loose where
//!   `det J` is tiny (a hole's pocket, docs/maths.md §11). Each cell therefore also takes a
//!   **second-order** bound (`cell_bounds`): the exact Hessians `∇²u(x)`, `∇²v(x)` at the
//!   centre, which keep the cancellation, and term-by-term bounds `T ≥ sup|F'''|`
//!   (`Σ_j |k_j|·4|E_j|/(d_j − ρ)³`) only on the remainder, smaller by `ρ/d`; the better of the
//!   two decides. With it every map of the floor-plan suite is certified on all of `W_δ`
//!   (docs/maths.md §13.5); "undecided" remains the honest answer when the budget runs out.

use nalgebra::Vector2;

use crate::map::HarmonicMap;

/// Why a check cannot run.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum CertifyError {
    /// `δ` (or the sample spacing, `name`) is not positive and finite, or is larger than the
    /// domain's diameter.
    InvalidOption {
        /// The option.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// The initial grid would have more cells than the evaluation budget.
    TooManyCells {
        /// Cells of the initial grid.
        cells: usize,
        /// The budget.
        max: usize,
    },
}

impl std::fmt::Display for CertifyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InvalidOption { name, value } => write!(
                f,
                "certificate option `{name}` = {value:e} must be positive, finite and below the domain's diameter"
            ),
            Self::TooManyCells { cells, max } => write!(
                f,
                "the certificate's first grid has {cells} cells, over the budget of {max} evaluations (raise delta)"
            ),
        }
    }
}

impl std::error::Error for CertifyError {}

/// The extreme values seen at the evaluated points of `W_δ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extremes {
    /// Points of `W_δ` evaluated.
    pub samples: usize,
    /// Smallest `det J_H` seen (world units; `+∞` if no sample).
    pub min_det: f64,
    /// Where.
    pub min_det_at: Vector2<f64>,
    /// Its distance from the boundary.
    pub min_det_distance: f64,
    /// Largest `|H|` seen (`−∞` if no sample).
    pub max_norm: f64,
    /// Where.
    pub max_norm_at: Vector2<f64>,
    /// Samples with `det J_H ≤ 0`.
    pub folds: usize,
    /// Samples with `|H| ≥ 1`.
    pub outside_disk: usize,
}

impl Extremes {
    fn new() -> Self {
        Self {
            samples: 0,
            min_det: f64::INFINITY,
            min_det_at: Vector2::zeros(),
            min_det_distance: f64::NAN,
            max_norm: f64::NEG_INFINITY,
            max_norm_at: Vector2::zeros(),
            folds: 0,
            outside_disk: 0,
        }
    }

    fn record(&mut self, x: Vector2<f64>, distance: f64, det: f64, norm: f64) {
        self.samples += 1;
        if det < self.min_det {
            self.min_det = det;
            self.min_det_at = x;
            self.min_det_distance = distance;
        }
        if norm > self.max_norm {
            self.max_norm = norm;
            self.max_norm_at = x;
        }
        self.folds += usize::from(det <= 0.0);
        self.outside_disk += usize::from(norm >= 1.0);
    }
}

fn check_positive(name: &'static str, value: f64, diameter: f64) -> Result<(), CertifyError> {
    if value.is_finite() && value > 0.0 && value < diameter {
        Ok(())
    } else {
        Err(CertifyError::InvalidOption { name, value })
    }
}

/// A **sampled** check, not a proof: `det J_H` and `|H|` at the nodes of a square grid of
/// spacing `spacing` over the bounding box that lie in `W_δ` (free, at least `delta` from the
/// boundary). Points where evaluation fails (element end points) are skipped.
///
/// # Errors
/// [`CertifyError::InvalidOption`] for a non-positive, non-finite or too large `delta` or
/// `spacing`; [`CertifyError::TooManyCells`] for more than 10⁷ grid nodes.
pub fn sampled_check(
    map: &HarmonicMap,
    delta: f64,
    spacing: f64,
) -> Result<Extremes, CertifyError> {
    let domain = map.domain();
    check_positive("delta", delta, domain.diameter())?;
    check_positive("spacing", spacing, domain.diameter())?;
    let (lo, hi) = domain.bounding_box();
    let nx = ((hi.x - lo.x) / spacing).floor() as usize + 1;
    let ny = ((hi.y - lo.y) / spacing).floor() as usize + 1;
    const MAX_NODES: usize = 10_000_000;
    if nx.saturating_mul(ny) > MAX_NODES {
        return Err(CertifyError::TooManyCells {
            cells: nx.saturating_mul(ny),
            max: MAX_NODES,
        });
    }
    let mut out = Extremes::new();
    for i in 0..nx {
        for j in 0..ny {
            let x = lo + Vector2::new(i as f64, j as f64) * spacing;
            let sd = domain.signed_distance(x);
            if sd < delta {
                continue;
            }
            if let Ok(e) = map.eval(x) {
                out.record(x, sd, e.det(), e.value.norm());
            }
        }
    }
    Ok(out)
}

/// Options of [`certify`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CertifyOptions {
    /// `δ`: the certified region is `W_δ` (choose `δ ≥` [`HarmonicMap::max_element_length`]).
    pub delta: f64,
    /// Most halvings of a cell (the first cells have half-diagonal `ρ₀ = δ/3`).
    pub max_depth: u32,
    /// Most evaluations (each `O(N)`).
    pub max_evaluations: usize,
}

impl CertifyOptions {
    /// `δ` with depth 8 and 200 000 evaluations. (At depth 6 the warehouse of
    /// `scenarios/floorplans/` at `max_element = 0.2` left 3.2e-4 m² of cells undecided, with a
    /// sampled `min det J_H` of 6.9e-7; two levels more certify them with 507 more
    /// evaluations.)
    #[must_use]
    pub fn new(delta: f64) -> Self {
        Self {
            delta,
            max_depth: 8,
            max_evaluations: 200_000,
        }
    }
}

/// What [`certify`] concluded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Verdict {
    /// Every cell meeting `W_δ` is certified: `det J_H > 0` and `|H| < 1` on all of `W_δ`.
    Certified,
    /// A cell centre in `W_δ` has `det J_H ≤ 0`: the map folds there (a counterexample).
    Fold {
        /// The point.
        at: Vector2<f64>,
    },
    /// A cell centre in `W_δ` has `|H| ≥ 1`.
    OutsideDisk {
        /// The point.
        at: Vector2<f64>,
    },
    /// No counterexample, but some area (see [`Certificate::undecided_area`]) was neither
    /// certified nor refuted within the depth and budget.
    Undecided,
}

impl Verdict {
    /// A stable name for JSON.
    #[must_use]
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Certified => "certified",
            Self::Fold { .. } => "fold",
            Self::OutsideDisk { .. } => "outside_disk",
            Self::Undecided => "undecided",
        }
    }
}

/// The result of [`certify`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Certificate {
    /// `δ`.
    pub delta: f64,
    /// The conclusion.
    pub verdict: Verdict,
    /// Evaluations spent.
    pub evaluations: usize,
    /// Area of the certified cells (they cover `W_δ` and a little of its δ-collar).
    pub certified_area: f64,
    /// Area of the cells left undecided (an upper bound of the uncertified part of `W_δ`).
    pub undecided_area: f64,
    /// The extremes at the evaluated cell centres in `W_δ` (a sample, as in [`sampled_check`]).
    pub extremes: Extremes,
}

/// The lower bound of `det J_H` and the upper bound of `|H|` on the disc `B(x, ρ)`: the better
/// of the first-order bounds of the module docs and the second-order ones,
///
/// ```text
/// ∇u(x + e) = a + A e + R_u,  |R_u| ≤ ½ρ² T_u   (a = ∇u(x), A = ∇²u(x) exact, T_u ≥ sup|F_u'''|)
/// det J ≥ det J(x) − ρ|l| − ρ²‖A‖‖B‖ − ½ρ²((|a| + ρ‖A‖)T_v + (|b| + ρ‖B‖)T_u) − ¼ρ⁴T_u T_v,
/// l = Aᵀ(b_y, −b_x) + Bᵀ(−a_y, a_x)   (the exact linear part of det[a + Ae, b + Be]),
/// |H(x + e)| ≤ |H(x)| + ρ‖J‖_F + ½ρ²√(‖A‖² + ‖B‖²) + ⅙ρ³√(T_u² + T_v²),
/// ```
///
/// with `b`, `B`, `T_v` the same for `v`. The exact Hessians at the centre keep the
/// cancellation between elements that the first-order bound's `Σ_j |k_j|…` loses; only the
/// remainder, smaller by `ρ/d`, is bounded term by term. `‖A‖₂ = |F_u''|` for a harmonic `u`.
fn cell_bounds(b: &crate::map::Bounded, rho: f64) -> (f64, f64) {
    let e = &b.eval;
    let (det, norm) = (e.det(), e.value.norm());
    let [hu, hv] = b.hessian;
    let a = e.jacobian.row(0).transpose();
    let bb = e.jacobian.row(1).transpose();
    let (gu, gv) = (a.norm(), bb.norm());
    let first_det = det - rho * (hu * gv + hv * gu) - rho * rho * hu * hv;
    let first_norm = norm + rho * e.jacobian.norm() + 0.5 * rho * rho * hu.hypot(hv);
    let [ha, hb] = b.hessian_at;
    let [tu, tv] = b.third;
    // ‖A‖₂ of the symmetric traceless Hessian [[p, q], [q, −p]] is √(p² + q²).
    let (na, nb) = (ha[(0, 0)].hypot(ha[(0, 1)]), hb[(0, 0)].hypot(hb[(0, 1)]));
    let l = ha.transpose() * nalgebra::Vector2::new(bb.y, -bb.x)
        + hb.transpose() * nalgebra::Vector2::new(-a.y, a.x);
    let r2 = 0.5 * rho * rho;
    let second_det = det
        - rho * l.norm()
        - rho * rho * na * nb
        - r2 * ((gu + rho * na) * tv + (gv + rho * nb) * tu)
        - r2 * r2 * tu * tv;
    let second_norm =
        norm + rho * e.jacobian.norm() + r2 * na.hypot(nb) + rho * rho * rho / 6.0 * tu.hypot(tv);
    // Either bound holds; NaN (an infinite bound times 0) falls back to the first.
    (
        if second_det > first_det {
            second_det
        } else {
            first_det
        },
        if second_norm < first_norm {
            second_norm
        } else {
            first_norm
        },
    )
}

/// The Lipschitz-bound covering of the module docs.
///
/// # Errors
/// [`CertifyError::InvalidOption`] for a bad `delta`; [`CertifyError::TooManyCells`] when the
/// first grid alone exceeds the budget.
pub fn certify(map: &HarmonicMap, options: &CertifyOptions) -> Result<Certificate, CertifyError> {
    let domain = map.domain();
    let delta = options.delta;
    check_positive("delta", delta, domain.diameter())?;
    let (lo, hi) = domain.bounding_box();
    // Half-side w₀ with half-diagonal ρ₀ = w₀√2 = δ/3 < δ/2, so that no first cell both meets
    // W_δ and reaches the boundary (then sd(x) − ρ > 0 for every evaluated cell).
    let w0 = delta / (3.0 * std::f64::consts::SQRT_2);
    let nx = ((hi.x - lo.x) / (2.0 * w0)).ceil().max(1.0);
    let ny = ((hi.y - lo.y) / (2.0 * w0)).ceil().max(1.0);
    if nx * ny > options.max_evaluations as f64 {
        return Err(CertifyError::TooManyCells {
            cells: (nx * ny).min(usize::MAX as f64) as usize,
            max: options.max_evaluations,
        });
    }
    let mut queue = std::collections::VecDeque::new();
    for i in 0..nx as usize {
        for j in 0..ny as usize {
            let c = lo + Vector2::new(2.0 * i as f64 + 1.0, 2.0 * j as f64 + 1.0) * w0;
            queue.push_back((c, w0, 0_u32));
        }
    }
    let mut out = Certificate {
        delta,
        verdict: Verdict::Certified,
        evaluations: 0,
        certified_area: 0.0,
        undecided_area: 0.0,
        extremes: Extremes::new(),
    };
    let mut fold = None;
    let mut outside = None;
    while let Some((c, w, depth)) = queue.pop_front() {
        let rho = w * std::f64::consts::SQRT_2;
        let area = 4.0 * w * w;
        let sd = domain.signed_distance(c);
        if sd + rho < delta {
            continue;
        }
        let split = depth < options.max_depth && out.evaluations < options.max_evaluations;
        let children = |queue: &mut std::collections::VecDeque<_>| {
            let h = w / 2.0;
            for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                queue.push_back((c + Vector2::new(sx, sy) * h, h, depth + 1));
            }
        };
        if sd - rho <= 0.0 || out.evaluations >= options.max_evaluations {
            if split {
                children(&mut queue);
            } else {
                out.undecided_area += area;
            }
            continue;
        }
        out.evaluations += 1;
        let Ok(b) = map.eval_bounded(c, Some(rho)) else {
            // Not reachable (sd > ρ > 0 keeps c off the elements), but never certify blind.
            out.undecided_area += area;
            continue;
        };
        let e = b.eval;
        let det = e.det();
        let norm = e.value.norm();
        if sd >= delta {
            out.extremes.record(c, sd, det, norm);
            if det <= 0.0 && fold.is_none() {
                fold = Some(c);
            }
            if norm >= 1.0 && outside.is_none() {
                outside = Some(c);
            }
        }
        let (det_low, norm_high) = cell_bounds(&b, rho);
        if det_low > 0.0 && norm_high < 1.0 {
            out.certified_area += area;
        } else if split && !(sd >= delta && det <= 0.0) {
            children(&mut queue);
        } else {
            out.undecided_area += area;
        }
    }
    out.verdict = match (fold, outside) {
        (Some(at), _) => Verdict::Fold { at },
        (None, Some(at)) => Verdict::OutsideDisk { at },
        (None, None) if out.undecided_area > 0.0 => Verdict::Undecided,
        (None, None) => Verdict::Certified,
    };
    Ok(out)
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix2, Vector2};

    use crate::{Domain, HarmonicMap, MeshOptions};

    fn v(x: f64, y: f64) -> Vector2<f64> {
        Vector2::new(x, y)
    }

    /// A 4 × 4 room with a U-shaped hole open upward (its pocket and corners are where the
    /// elements crowd).
    fn u_map() -> HarmonicMap {
        let mut u = vec![
            v(-1.0, -1.0),
            v(1.0, -1.0),
            v(1.0, 1.0),
            v(0.6, 1.0),
            v(0.6, -0.6),
            v(-0.6, -0.6),
            v(-0.6, 1.0),
            v(-1.0, 1.0),
        ];
        u.reverse();
        let room = vec![v(-2.0, -2.0), v(2.0, -2.0), v(2.0, 2.0), v(-2.0, 2.0)];
        HarmonicMap::new(
            &Domain::new(room, vec![u]).unwrap(),
            &MeshOptions::graded(0.2),
        )
        .unwrap()
    }

    /// The exact Hessians at the centre match central differences of the exact Jacobian, and
    /// the gradient's second-order remainder stays within `½ρ²·T` at 200 points of each disc;
    /// then the second-order bounds of `det J` and `|H|` hold at those points.
    #[test]
    fn second_order_terms_match_differences_and_bound_the_remainder() {
        let map = u_map();
        let centres = [
            (0.0, 0.0),
            (0.0, 1.4),
            (-1.5, -1.5),
            (0.8, 1.2),
            (1.5, 0.2),
            (0.0, -0.4),
        ];
        for &(x, y) in &centres {
            let c = v(x, y);
            let sd = map.domain().signed_distance(c);
            for frac in [0.1, 0.4, 0.8] {
                let rho = frac * sd;
                let b = map.eval_bounded(c, Some(rho)).unwrap();
                let step = 1e-5;
                let jac = |p: Vector2<f64>| map.eval(p).unwrap().jacobian;
                let dx = (jac(c + v(step, 0.0)) - jac(c - v(step, 0.0))) / (2.0 * step);
                let dy = (jac(c + v(0.0, step)) - jac(c - v(0.0, step))) / (2.0 * step);
                for (row, h) in b.hessian_at.iter().enumerate() {
                    let fd = Matrix2::new(dx[(row, 0)], dy[(row, 0)], dx[(row, 1)], dy[(row, 1)]);
                    let err = (h - fd).norm() / h.norm().max(1e-3);
                    assert!(
                        err < 1e-5,
                        "{c:?}: ∇² of row {row}: {h} against {fd} ({err})"
                    );
                }
                let (det_low, norm_high) = super::cell_bounds(&b, rho);
                for i in 0..200 {
                    let t = i as f64 * 2.399_963_229_728_653;
                    let r = rho * ((i % 20) as f64 + 1.0) / 20.0;
                    let e = v(r * t.cos(), r * t.sin());
                    let at = map.eval(c + e).unwrap();
                    for row in 0..2 {
                        let lin = b.eval.jacobian.row(row).transpose() + b.hessian_at[row] * e;
                        let rem = (at.jacobian.row(row).transpose() - lin).norm();
                        assert!(
                            rem <= 0.5 * r * r * b.third[row] * (1.0 + 1e-9) + 1e-12,
                            "{c:?} ρ {rho}: remainder {rem} > ½r²T = {}",
                            0.5 * r * r * b.third[row]
                        );
                    }
                    assert!(
                        at.det() >= det_low && at.value.norm() <= norm_high,
                        "{c:?} ρ {rho}"
                    );
                }
            }
        }
    }

    /// Where the first-order bound is loose (the elements near, their densities cancelling),
    /// the second-order one is the larger lower bound of `det J` on some cell, so it is what
    /// decides cells there.
    #[test]
    fn the_second_order_bound_is_the_tighter_one_near_the_walls() {
        let map = u_map();
        let c = v(0.0, 1.4);
        let rho = 0.2 * map.domain().signed_distance(c);
        let b = map.eval_bounded(c, Some(rho)).unwrap();
        let [hu, hv] = b.hessian;
        let (gu, gv) = (b.eval.jacobian.row(0).norm(), b.eval.jacobian.row(1).norm());
        let first = b.eval.det() - rho * (hu * gv + hv * gu) - rho * rho * hu * hv;
        let (det_low, _) = super::cell_bounds(&b, rho);
        assert!(
            det_low > first,
            "second order {det_low} not above first order {first}"
        );
    }
}
