//! The census of `Θ`'s critical points with their Hessians (theorem `isNF`: one minimum at
//! the destination and `M` saddles, each non-degenerate unless proposition `Morse` applies).

use harmonav_potential::CriticalKind;
use harmonav_potential::fd::{FD_STEP, fd_jacobian};
use nalgebra::{Matrix2, Vector2};

use crate::field::{Field, FieldError, FieldEval};

/// What a critical point of `Θ` is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CriticalType {
    /// The destination, the unique minimum.
    Minimum,
    /// A non-degenerate saddle (lemma `saddlep`).
    Saddle,
    /// A degenerate saddle (proposition `Morse`).
    DegenerateSaddle,
}

impl CriticalType {
    /// `"minimum"`, `"saddle"` or `"degenerate-saddle"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Minimum => "minimum",
            Self::Saddle => "saddle",
            Self::DegenerateSaddle => "degenerate-saddle",
        }
    }
}

/// One critical point of `Θ` in the workspace.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CensusPoint {
    /// Its position.
    pub x: Vector2<f64>,
    /// Its type.
    pub kind: CriticalType,
    /// Eigenvalues of `H(Θ)(x)`, ascending, from [`Field::hessian`]; `None` where the
    /// differences leave the free space (a saddle closer than [`FD_STEP`] to an obstacle).
    pub eigenvalues: Option<[f64; 2]>,
}

/// The critical points of `Θ` and their counts.
#[derive(Clone, Debug, PartialEq)]
pub struct Census {
    /// The destination first, then the saddles.
    pub points: Vec<CensusPoint>,
    /// Minima (1 for a navigation function).
    pub minima: usize,
    /// Non-degenerate saddles.
    pub saddles: usize,
    /// Degenerate saddles.
    pub degenerate: usize,
}

/// `H(Θ)(x)` of a navigation function `σ∘φ_k∘Phi` evaluated by `eval`, by central differences
/// of the analytic `∇Θ` with step [`FD_STEP`] (`H_ij ≈ (∂_j Θ_i(x + s e_j) − ∂_j Θ_i(x − s
/// e_j)) / 2s`), symmetrised: `Phi` has no closed-form second derivative. The Hessian of a star
/// world's [`Field::hessian`] and of a floor plan's.
///
/// # Errors
/// `eval`'s error at a difference point (one that leaves the free space).
pub fn fd_hessian(
    eval: impl Fn(Vector2<f64>) -> Result<FieldEval, FieldError>,
    x: Vector2<f64>,
) -> Result<Matrix2<f64>, FieldError> {
    let (ex, ey) = (Vector2::new(FD_STEP, 0.0), Vector2::new(0.0, FD_STEP));
    for p in [x + ex, x - ex, x + ey, x - ey] {
        eval(p)?;
    }
    let g = |y| eval(y).map_or(Vector2::zeros(), |e| e.gradient);
    let m = fd_jacobian(g, x, FD_STEP);
    Ok(0.5 * (m + m.transpose()))
}

/// The eigenvalues of a symmetric Hessian, ascending (a census point's `eigenvalues`).
#[must_use]
pub fn ascending_eigenvalues(h: Matrix2<f64>) -> [f64; 2] {
    let e = h.symmetric_eigenvalues();
    [e[0].min(e[1]), e[0].max(e[1])]
}

impl Field {
    /// `H(Θ)(x)` ([`fd_hessian`]). Errors if a difference point leaves the free space. Where
    /// `sigma'` underflows (`Θ` within 1e-16 of 1, far from the goal) the gradient and so this
    /// Hessian are 0.
    pub fn hessian(&self, x: Vector2<f64>) -> Result<Matrix2<f64>, FieldError> {
        fd_hessian(|y| self.eval(y), x)
    }

    /// The census of `Θ`: [`Field::critical_points`] typed, with the eigenvalues of
    /// [`Field::hessian`] at each.
    pub fn census(&self) -> Census {
        let mut census = Census {
            points: Vec::new(),
            minima: 0,
            saddles: 0,
            degenerate: 0,
        };
        for c in self.critical_points() {
            let kind = match c.point_world {
                None => {
                    census.minima += 1;
                    CriticalType::Minimum
                }
                Some(p) if p.kind == CriticalKind::Degenerate => {
                    census.degenerate += 1;
                    CriticalType::DegenerateSaddle
                }
                Some(_) => {
                    census.saddles += 1;
                    CriticalType::Saddle
                }
            };
            let eigenvalues = self.hessian(c.x).ok().map(ascending_eigenvalues);
            census.points.push(CensusPoint {
                x: c.x,
                kind,
                eigenvalues,
            });
        }
        census
    }
}
