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
//!   undecided. The bound ignores cancellation between elements, so it is loose where `det J`
//!   is tiny (a hole's pocket, docs/maths.md §11): there the answer is honestly "undecided".

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
    /// `δ` with depth 6 and 200 000 evaluations.
    #[must_use]
    pub fn new(delta: f64) -> Self {
        Self {
            delta,
            max_depth: 6,
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
        let [hu, hv] = b.hessian;
        let gu = e.jacobian.row(0).norm();
        let gv = e.jacobian.row(1).norm();
        let det_low = det - rho * (hu * gv + hv * gu) - rho * rho * hu * hv;
        let norm_high = norm + rho * e.jacobian.norm() + 0.5 * rho * rho * hu.hypot(hv);
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
