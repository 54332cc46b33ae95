//! [`PointWorld`]: the point-world potential `phi_k` and the point-world navigation function
//! `varphi = sigma ∘ phi_k` with their derivatives.

use nalgebra::{Matrix2, Vector2};

use crate::error::{PotentialError, Singularity};
use crate::far::{FAR_MIN, FarField};
use crate::sigma::{ln_sigma_prime, sigma, sigma_prime};
use crate::terms::{hess_ln_norm2, ln_norm2, reciprocal, unit};

/// A point world `P = R² \ {P_1..P_M}` with destination `P_d` and the parameter `k > M`.
///
/// Invariants (checked by the constructors): all points finite, the obstacle points distinct
/// and different from `P_d`, and `k` finite with `k > M` (lemma `attactive`).
///
/// With [`FAR_MIN`] obstacle points or more, the hot path
/// [`Self::phi_and_grad`] sums the far points by multipoles (`crate::far`, docs/maths.md §15);
/// every other method sums them directly.
#[derive(Clone, Debug)]
pub struct PointWorld {
    destination: Vector2<f64>,
    obstacles: Vec<Vector2<f64>>,
    k: f64,
    /// The multipole tree over `obstacles` (derived from them: not part of equality).
    far: Option<FarField>,
    /// `Σ_i ln|P_d − P_i|²`, summed in order (derived: [`Self::destination_stiffness`]).
    ln_destination: f64,
}

/// `r* = k/(k − M)·|D|`, `D = P_d − c − (1/k)·sum` with `sum = Σ_i (P_i − c)`
/// ([`PointWorld::valley_radius`]).
fn valley(destination: Vector2<f64>, c: Vector2<f64>, sum: Vector2<f64>, m: f64, k: f64) -> f64 {
    let dipole = (destination - c) - sum / k;
    k / (k - m) * dipole.norm()
}

/// `Σ_i ln|P_d − P_i|²` over `obstacles` in order, from `-0.0` (the sum that [`PointWorld::push`]
/// continues term by term, so the same bits).
fn ln_destination(destination: Vector2<f64>, obstacles: &[Vector2<f64>]) -> f64 {
    obstacles
        .iter()
        .fold(-0.0, |s, p| s + ln_norm2(destination - p))
}

/// What the multipole path of `phi_and_grad` gives.
pub(crate) enum FarPath {
    /// `(phi_k, ∇phi_k)` by the split product of the near points and the tree.
    Value((f64, Vector2<f64>)),
    /// A factor or `|h − P_d|²` is not a normal `f64`: the guarded sum of logarithms.
    Guarded,
    /// `h` is not finite, or the exact offset's point is not near: the direct sum.
    Direct,
}

impl PartialEq for PointWorld {
    fn eq(&self, other: &Self) -> bool {
        self.destination == other.destination
            && self.obstacles == other.obstacles
            && self.k == other.k
    }
}

/// The obstacle terms of the fast path are multiplied in blocks of this many mantissas
/// (each in `[1, 2)`, so a block's product is below `2^512`: finite), one logarithm a block.
pub(crate) const PRODUCT_BLOCK: usize = 512;

/// `|v|² = m·2^e` with `m ∈ [1, 2)`, exactly, for a normal `|v|²` (the bits of the `f64`: no
/// rounding). For 0, a subnormal, `∞` or NaN the pair is meaningless; the callers check that
/// every factor was normal before they use it.
#[inline(always)]
pub(crate) fn split(r2: f64) -> (f64, i64) {
    const MANTISSA: u64 = (1 << 52) - 1;
    const ONE: u64 = 1023 << 52;
    let bits = r2.to_bits();
    (
        f64::from_bits((bits & MANTISSA) | ONE),
        ((bits >> 52) & 0x7ff) as i64 - 1023,
    )
}

/// The invariants of [`PointWorld::new`]: finite points, none at the destination, no two equal.
fn check(destination: Vector2<f64>, obstacles: &[Vector2<f64>]) -> Result<(), PotentialError> {
    if !(destination.x.is_finite() && destination.y.is_finite()) {
        return Err(PotentialError::NonFinite { index: None });
    }
    for (i, p) in obstacles.iter().enumerate() {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(PotentialError::NonFinite { index: Some(i) });
        }
        if *p == destination {
            return Err(PotentialError::ObstacleAtDestination { index: i });
        }
    }
    // Duplicates by sorting (O(M log M); was a scan of every earlier point): the reported
    // pair is the direct scan's, the smallest `second` with an equal earlier point and its
    // first occurrence (`==` on finite coordinates: −0 equals 0).
    let mut order: Vec<usize> = (0..obstacles.len()).collect();
    let key = |i: &usize| (obstacles[*i].x + 0.0, obstacles[*i].y + 0.0, *i);
    order.sort_unstable_by(|a, b| {
        let (a, b) = (key(a), key(b));
        a.0.total_cmp(&b.0)
            .then(a.1.total_cmp(&b.1))
            .then(a.2.cmp(&b.2))
    });
    let mut worst: Option<(usize, usize)> = None;
    for run in order.chunk_by(|&a, &b| obstacles[a] == obstacles[b]) {
        if let [first, second, ..] = *run
            && worst.is_none_or(|(_, s)| second < s)
        {
            worst = Some((first, second));
        }
    }
    match worst {
        Some((first, second)) => Err(PotentialError::DuplicateObstacle { first, second }),
        None => Ok(()),
    }
}

impl PointWorld {
    /// A point world with the paper's default `k = M + 1`.
    ///
    /// Errors: a NaN or infinite coordinate, an obstacle point at the destination or two equal
    /// obstacle points.
    pub fn new(
        destination: Vector2<f64>,
        obstacles: impl Into<Vec<Vector2<f64>>>,
    ) -> Result<Self, PotentialError> {
        let obstacles = obstacles.into();
        check(destination, &obstacles)?;
        let far = (obstacles.len() >= FAR_MIN)
            .then(|| FarField::new(&obstacles))
            .flatten();
        Ok(Self {
            destination,
            k: obstacles.len() as f64 + 1.0,
            ln_destination: ln_destination(destination, &obstacles),
            obstacles,
            far,
        })
    }

    /// This world with the obstacle point `p` appended (index `M`, returned) and the parameter
    /// `k`, in place: the world [`Self::new`]`(P_d, [P_1..P_M, p])`[`.with_k(k)`](Self::with_k)
    /// (equal as a [`PartialEq`] world; its multipole sums to their tolerance, as
    /// [`Self::new_after`]'s). The multipole tree, if any, takes the point by a push (`O(4^L)` leaves;
    /// the tree is copied first only if another world shares it) and is rebuilt when it holds
    /// twice the points it was built over; a world reaching [`FAR_MIN`] points gets its tree.
    /// The duplicate check is a scan of the `M` points (comparisons only).
    ///
    /// Errors (the world is then unchanged): `p` not finite, at `P_d` or equal to an obstacle
    /// point ([`PotentialError::DuplicateObstacle`], as [`Self::new`] names it), or `k` not
    /// attractive for `M + 1` points ([`PotentialError::KNotAttractive`]).
    pub fn push(&mut self, p: Vector2<f64>, k: f64) -> Result<usize, PotentialError> {
        let m = self.check_push(p, k)?;
        self.obstacles.push(p);
        self.ln_destination += ln_norm2(self.destination - p);
        self.k = k;
        self.far = match self.far.take() {
            // Pushed, or rebuilt once (doubled, or outside the root box), as `new_after` does.
            Some(mut far) => far.push(&self.obstacles).then_some(far),
            None if self.obstacles.len() >= FAR_MIN => FarField::new(&self.obstacles),
            None => None,
        };
        Ok(m)
    }

    /// The checks of [`Self::push`]`(p, k)` without the push: `Ok(M)`, the index `p` would
    /// get, or the error `push` would return.
    pub fn check_push(&self, p: Vector2<f64>, k: f64) -> Result<usize, PotentialError> {
        let m = self.obstacles.len();
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(PotentialError::NonFinite { index: Some(m) });
        }
        if p == self.destination {
            return Err(PotentialError::ObstacleAtDestination { index: m });
        }
        if let Some(first) = self.obstacles.iter().position(|q| *q == p) {
            return Err(PotentialError::DuplicateObstacle { first, second: m });
        }
        if !(k.is_finite() && k > (m + 1) as f64) {
            return Err(PotentialError::KNotAttractive {
                k,
                obstacles: m + 1,
            });
        }
        Ok(m)
    }

    /// [`Self::valley_radius`] about `c` of this world with the obstacle point `p` appended and
    /// the parameter `k`, without building it (the same sum in the same order, so the same
    /// bits as [`Self::push`] then [`Self::valley_radius`]). `O(M)` additions.
    #[must_use]
    pub fn valley_radius_with(&self, p: Vector2<f64>, k: f64, c: Vector2<f64>) -> f64 {
        let m = (self.obstacles.len() + 1) as f64;
        let sum = self
            .obstacles
            .iter()
            .chain(std::iter::once(&p))
            .map(|q| q - c)
            .sum::<Vector2<f64>>();
        valley(self.destination, c, sum, m, k)
    }

    /// [`Self::new`], reusing the multipole tree of `previous` when it has one, the same
    /// destination, and its obstacle points are the first ones of `obstacles`: the new points
    /// are pushed into a copy of its tree (`O(4^L)` leaves each) instead of a rebuild, until the tree
    /// holds twice the points it was built over (then it is rebuilt, deeper). This is the point
    /// world's share of a discovery (`Navigator::add_obstacle` at `M = 1 000`: a copy and a push
    /// of tens of µs, not a rebuild of about 15 ms). The result equals `Self::new(destination, obstacles)`, `k = M + 1`.
    ///
    /// Errors: those of [`Self::new`].
    pub fn new_after(
        previous: &PointWorld,
        destination: Vector2<f64>,
        obstacles: impl Into<Vec<Vector2<f64>>>,
    ) -> Result<Self, PotentialError> {
        let obstacles = obstacles.into();
        let old = previous.obstacles.len();
        match &previous.far {
            Some(far)
                if previous.destination == destination
                    && obstacles.len() > old
                    && obstacles.starts_with(&previous.obstacles) =>
            {
                check(destination, &obstacles)?;
                let far = far.extended(&obstacles, &obstacles[old..]);
                Ok(Self {
                    destination,
                    k: obstacles.len() as f64 + 1.0,
                    ln_destination: ln_destination(destination, &obstacles),
                    obstacles,
                    far,
                })
            }
            _ => Self::new(destination, obstacles),
        }
    }

    /// The same world with another `k`. Lemma `attactive`: `phi_k → +∞` far away iff `k > M`,
    /// so `k ≤ M` (or a non-finite `k`) is rejected with [`PotentialError::KNotAttractive`].
    pub fn with_k(mut self, k: f64) -> Result<Self, PotentialError> {
        let m = self.obstacles.len();
        if !(k.is_finite() && k > m as f64) {
            return Err(PotentialError::KNotAttractive { k, obstacles: m });
        }
        self.k = k;
        Ok(self)
    }

    /// The destination `P_d = Phi(x_d)`.
    pub fn destination(&self) -> Vector2<f64> {
        self.destination
    }

    /// The obstacle points `P_1..P_M`.
    pub fn obstacles(&self) -> &[Vector2<f64>] {
        &self.obstacles
    }

    /// The parameter `k` (> M).
    pub fn k(&self) -> f64 {
        self.k
    }

    /// Which singular point `h` is, if any: the destination or an obstacle point (exact
    /// equality; every other point of `R²` is a regular point of `phi_k`).
    pub fn singularity(&self, h: Vector2<f64>) -> Option<Singularity> {
        if h == self.destination {
            return Some(Singularity::Destination);
        }
        self.obstacles
            .iter()
            .position(|p| *p == h)
            .map(Singularity::Obstacle)
    }

    /// `phi_k(h) = ln|h − P_d|² − (1/k) Σ_i ln|h − P_i|²` (section `HFcontruction`).
    ///
    /// Evaluated as a sum of logarithms, so it is finite for every regular `h` including
    /// `|h| = 1e300`. Edges: `−∞` at `P_d`, `+∞` at an obstacle point (never NaN).
    pub fn phi_k(&self, h: Vector2<f64>) -> f64 {
        let obstacles: f64 = self.obstacles.iter().map(|p| ln_norm2(h - p)).sum();
        ln_norm2(h - self.destination) - obstacles / self.k
    }

    /// `phi_k(h)` and `∇phi_k(h)` together (eq. `gradient`), for the per-step hot path.
    ///
    /// `exact` optionally gives the offset `h − P_i` of one obstacle point exactly, for when
    /// `h` was formed as `P_i + ν u` with tiny `ν` (maths.md §4, pitfall C: subtracting `P_i`
    /// again would lose the direction).
    ///
    /// Numerical guard: the obstacle sum `Σ ln|h_i|²` is taken from the exact split
    /// `|h_i|² = m_i·2^{e_i}`, `m_i ∈ [1, 2)` (the bits of the `f64`), as
    /// `Σ_blocks ln Π m_i + (Σ e_i)·ln 2`: one logarithm per `PRODUCT_BLOCK` = 512 factors
    /// instead of one per factor, and no overflow whatever the distances (a block's product
    /// is below `2^512`). The branch-free loop tracks the smallest and largest factor and, if
    /// one is not a normal `f64`, the call falls back to the guarded sum of logarithms of
    /// [`Self::phi_k`] and [`Self::grad_phi_k`]. Agrees with them to rounding: each block's
    /// product carries a relative error of at most `512·ε/2`, so `|Δ ln_sum| ≤ M·ε/2 +
    /// ε·|Σ e_i|·ln 2` (tested, docs/maths.md §14). Before (until 2026-12), one product of
    /// the `|h_i|²` themselves was taken only while every factor lay in `[10^{−300/M},
    /// 10^{300/M}]`: at `M = 1 000` in a 100 m world that is `[0.5, 2]`, never met, and every
    /// call paid `M` logarithms (12 µs).
    pub fn phi_and_grad(
        &self,
        h: Vector2<f64>,
        exact: Option<(usize, Vector2<f64>)>,
    ) -> Result<(f64, Vector2<f64>), Singularity> {
        if let Some(far) = &self.far {
            match self.phi_and_grad_far(far, h, exact) {
                FarPath::Value(v) => return Ok(v),
                FarPath::Guarded => return self.phi_and_grad_guarded(h, exact),
                FarPath::Direct => {}
            }
        }
        let (before, after) = match exact {
            Some((j, _)) => (&self.obstacles[..j], &self.obstacles[j + 1..]),
            None => (&self.obstacles[..], &self.obstacles[..0]),
        };
        let (mut gx, mut gy, mut ln_prod, mut exponent) = (0.0, 0.0, 0.0, 0i64);
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for block in before
            .chunks(PRODUCT_BLOCK)
            .chain(after.chunks(PRODUCT_BLOCK))
        {
            let mut prod = 1.0f64;
            for p in block {
                let (vx, vy) = (h.x - p.x, h.y - p.y);
                let r2 = vx * vx + vy * vy;
                let inv = 1.0 / r2;
                gx += vx * inv;
                gy += vy * inv;
                let (m, e) = split(r2);
                prod *= m;
                exponent += e;
                lo = lo.min(r2);
                hi = hi.max(r2);
            }
            ln_prod += prod.ln();
        }
        if let Some((_, v)) = exact {
            let r2 = v.norm_squared();
            gx += v.x / r2;
            gy += v.y / r2;
            let (m, e) = split(r2);
            ln_prod += m.ln();
            exponent += e;
            lo = lo.min(r2);
            hi = hi.max(r2);
        }
        let vd = h - self.destination;
        let rd2 = vd.norm_squared();
        // Guard: the split is exact only for normal factors (and 1/r2 finite); else the sum of
        // guarded logarithms.
        if !(lo >= f64::MIN_POSITIVE && hi <= f64::MAX && rd2.is_normal()) {
            return self.phi_and_grad_guarded(h, exact);
        }
        let ln_sum = ln_prod + exponent as f64 * std::f64::consts::LN_2;
        let phi = rd2.ln() - ln_sum / self.k;
        let k2 = 2.0 / self.k;
        Ok((
            phi,
            Vector2::new(2.0 * vd.x / rd2 - k2 * gx, 2.0 * vd.y / rd2 - k2 * gy),
        ))
    }

    /// [`Self::phi_and_grad`] with the far points from the multipole tree (`crate::far`, eq.
    /// far): the near points by the same split product (blocks of [`PRODUCT_BLOCK`]) and guard,
    /// `exact` applied to its point. `None` when the exact offset's point is not among the near
    /// ones, or `h` is not finite ([`FarPath::Direct`]: the direct sum), and
    /// [`FarPath::Guarded`] where the split's guard fails.
    pub(crate) fn phi_and_grad_far(
        &self,
        far: &FarField,
        h: Vector2<f64>,
        exact: Option<(usize, Vector2<f64>)>,
    ) -> FarPath {
        if !(h.x.is_finite() && h.y.is_finite()) {
            return FarPath::Direct;
        }
        let (mut gx, mut gy, mut ln_prod, mut exponent) = (0.0, 0.0, 0.0, 0i64);
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        let (mut prod, mut in_block, mut seen_exact) = (1.0f64, 0usize, exact.is_none());
        let (far_sum, far_grad) = far.eval(h, |i| {
            let (vx, vy) = match exact {
                Some((j, v)) if j == i => {
                    seen_exact = true;
                    (v.x, v.y)
                }
                _ => (h.x - self.obstacles[i].x, h.y - self.obstacles[i].y),
            };
            let r2 = vx * vx + vy * vy;
            gx += vx / r2;
            gy += vy / r2;
            let (m, e) = split(r2);
            prod *= m;
            exponent += e;
            lo = lo.min(r2);
            hi = hi.max(r2);
            in_block += 1;
            if in_block == PRODUCT_BLOCK {
                ln_prod += prod.ln();
                (prod, in_block) = (1.0, 0);
            }
        });
        if !seen_exact {
            return FarPath::Direct;
        }
        ln_prod += prod.ln();
        let vd = h - self.destination;
        let rd2 = vd.norm_squared();
        // Guard: as the direct path (the split is exact only for normal factors).
        if !(lo >= f64::MIN_POSITIVE && hi <= f64::MAX && rd2.is_normal()) {
            return FarPath::Guarded;
        }
        let ln_sum = ln_prod + exponent as f64 * std::f64::consts::LN_2 + far_sum;
        let (gx, gy) = (gx + far_grad.x, gy + far_grad.y);
        let phi = rd2.ln() - ln_sum / self.k;
        let k2 = 2.0 / self.k;
        FarPath::Value((
            phi,
            Vector2::new(2.0 * vd.x / rd2 - k2 * gx, 2.0 * vd.y / rd2 - k2 * gy),
        ))
    }

    /// The same world with the multipole tree dropped: [`Self::phi_and_grad`] then sums every
    /// point directly (the reference of the multipole path, timed side by side with it by
    /// `cargo xtask bench --only many`). A world made from it by [`Self::new_after`] or
    /// [`Self::new`] gets a tree again.
    #[must_use]
    pub fn without_far_field(mut self) -> Self {
        self.far = None;
        self
    }

    /// The multipole tree, if the world has one (the census uses it, `crate::critical`).
    pub(crate) fn far_field(&self) -> Option<&FarField> {
        self.far.as_ref()
    }

    /// Whether [`Self::phi_and_grad`] sums the far points by multipoles (from
    /// [`FAR_MIN`] points on).
    pub fn has_far_field(&self) -> bool {
        self.far.is_some()
    }

    /// The guarded slow path of [`Self::phi_and_grad`]: a sum of logarithms.
    fn phi_and_grad_guarded(
        &self,
        h: Vector2<f64>,
        exact: Option<(usize, Vector2<f64>)>,
    ) -> Result<(f64, Vector2<f64>), Singularity> {
        let (mut acc, mut ln_sum) = (Vector2::zeros(), 0.0);
        for (i, p) in self.obstacles.iter().enumerate() {
            let v = match exact {
                Some((j, offset)) if j == i => offset,
                _ => h - p,
            };
            acc += reciprocal(v).ok_or(Singularity::Obstacle(i))?;
            ln_sum += ln_norm2(v);
        }
        let vd = h - self.destination;
        let d = reciprocal(vd).ok_or(Singularity::Destination)?;
        Ok((
            ln_norm2(vd) - ln_sum / self.k,
            2.0 * d - (2.0 / self.k) * acc,
        ))
    }

    /// Eq. (`gradient`): `∇phi_k(h) = 2 h_d/|h_d|² − (2/k) Σ_i h_i/|h_i|²`.
    ///
    /// Errors with the [`Singularity`] at `P_d` and at the obstacle points, where the gradient
    /// is unbounded.
    pub fn grad_phi_k(&self, h: Vector2<f64>) -> Result<Vector2<f64>, Singularity> {
        let mut acc = Vector2::zeros();
        for (i, p) in self.obstacles.iter().enumerate() {
            acc += reciprocal(h - p).ok_or(Singularity::Obstacle(i))?;
        }
        let d = reciprocal(h - self.destination).ok_or(Singularity::Destination)?;
        Ok(2.0 * d - (2.0 / self.k) * acc)
    }

    /// Eq. (`hessquadratic`): `H(phi_k) = H(ln|h_d|²) − (1/k) Σ_i H(ln|h_i|²)`, each term
    /// `(2/|v|²)(I − 2 v̂ v̂ᵀ)`. Its trace is zero (harmonicity, lemma `locminfree`).
    ///
    /// Errors with the [`Singularity`] at `P_d` and at the obstacle points.
    pub fn hess_phi_k(&self, h: Vector2<f64>) -> Result<Matrix2<f64>, Singularity> {
        let mut acc = Matrix2::zeros();
        for (i, p) in self.obstacles.iter().enumerate() {
            acc += hess_ln_norm2(h - p).ok_or(Singularity::Obstacle(i))?;
        }
        let d = hess_ln_norm2(h - self.destination).ok_or(Singularity::Destination)?;
        Ok(d - acc / self.k)
    }

    /// Eq. (`NFcand`) in the point world: `varphi(h) = sigma(phi_k(h))
    /// = |h_d|² / (|h_d|² + Π_i |h_i|^{2/k})`, computed through `phi_k` in log space.
    ///
    /// Edges: exactly `0` at `P_d`, exactly `1` at an obstacle point; in `[0, 1]` everywhere.
    pub fn varphi(&self, h: Vector2<f64>) -> f64 {
        sigma(self.phi_k(h))
    }

    /// `∇varphi = sigma'(phi_k) ∇phi_k` (chain rule of theorem `isNF`).
    ///
    /// At `P_d` the limit exists and is returned: `0`. At an obstacle point the gradient is
    /// unbounded for `k > 2` and the call errors with [`Singularity::Obstacle`]. Far from the
    /// destination `sigma'` may underflow to `0`; use [`Self::descent_direction`] for the
    /// direction.
    pub fn grad_varphi(&self, h: Vector2<f64>) -> Result<Vector2<f64>, Singularity> {
        match self.grad_phi_k(h) {
            Ok(g) => Ok(sigma_prime(self.phi_k(h)) * g),
            Err(Singularity::Destination) => Ok(Vector2::zeros()),
            Err(e) => Err(e),
        }
    }

    /// `H(varphi) = sigma'(phi_k) H(phi_k) + sigma''(phi_k) ∇phi_k ∇phi_kᵀ`.
    ///
    /// Numerical guard: written as `Σ_v c_v·2(σ'/|v|²)(I − 2v̂v̂ᵀ) + t·g gᵀ` with
    /// `g = √σ'·∇phi_k`, `t = sigma''/sigma' = −tanh(phi_k/2)` and every factor `σ'/|v|²`,
    /// `√σ'/|v|` formed as one exponential of a sum of logarithms, so that near `P_d` the
    /// huge `H(phi_k)` and the vanishing `σ'` never meet as `∞·0`.
    ///
    /// At `P_d` the limit [`Self::destination_hessian`] is returned. Errors at obstacle points,
    /// and near one (closer than ≈ 1e-150) where the Hessian, growing like `|h_i|^{2/k − 2}`,
    /// exceeds the range of `f64`: the error names that obstacle.
    pub fn hess_varphi(&self, h: Vector2<f64>) -> Result<Matrix2<f64>, Singularity> {
        match self.singularity(h) {
            Some(Singularity::Destination) => return Ok(self.destination_hessian()),
            Some(e) => return Err(e),
            None => {}
        }
        let s = self.phi_k(h);
        let ln_sp = ln_sigma_prime(s);
        let t = -(0.5 * s).tanh();
        let mut hess = Matrix2::zeros();
        let mut g = Vector2::zeros();
        let terms = std::iter::once((self.destination, 1.0))
            .chain(self.obstacles.iter().map(|&p| (p, -1.0 / self.k)));
        for (p, c) in terms {
            let v = h - p;
            let ln_r2 = ln_norm2(v);
            let n = unit(v).expect("h is not a singular point");
            let a = (ln_sp - ln_r2).exp(); // σ'/|v|²
            hess += (2.0 * c * a) * (Matrix2::identity() - 2.0 * n * n.transpose());
            g += (2.0 * c * (0.5 * (ln_sp - ln_r2)).exp()) * n; // √σ'·(2v/|v|²)
        }
        let out = hess + t * g * g.transpose();
        if out.iter().all(|x| x.is_finite()) {
            Ok(out)
        } else {
            Err(Singularity::Obstacle(self.nearest_obstacle(h)))
        }
    }

    /// Index of the obstacle point nearest to `h` (`0` if there is none).
    fn nearest_obstacle(&self, h: Vector2<f64>) -> usize {
        (0..self.obstacles.len())
            .min_by(|&i, &j| {
                ln_norm2(h - self.obstacles[i]).total_cmp(&ln_norm2(h - self.obstacles[j]))
            })
            .unwrap_or(0)
    }

    /// The Hessian of `varphi` at the destination (eq. `destphik2`, corrected):
    ///
    /// ```text
    /// H(varphi)(P_d) = 2 / Π_i |P_d − P_i|^{2/k} · I
    /// ```
    ///
    /// The paper prints the exponent `4/k`; corollary `critdamp` uses `2/k`. Finite differences
    /// of [`Self::varphi`] at `P_d` agree with `2/k` (tests `destination_hessian_*` and the
    /// verify check `potential.destination-hessian-exponent`; evidence in `docs/maths.md`).
    /// The product is formed in log space.
    pub fn destination_hessian(&self) -> Matrix2<f64> {
        Matrix2::identity() * self.destination_stiffness()
    }

    /// The radius `r*` of the far-field valley of `phi_k` about the point `c` (`docs/maths.md`
    /// §5, pitfall A): far from the points
    ///
    /// ```text
    /// phi_k ≈ 2(1 − M/k) ln r − (2/r) ĥ·D,   D = P_d − c − (1/k) Σ_i (P_i − c),
    /// r* = k/(k − M)·|D|
    /// ```
    ///
    /// is the largest radius of its radial minimum (on the side facing away from `D`). The
    /// navigation transformation places it inside its stretched outer band (stretch gain
    /// `A ≥ 2r*`). Finite because `k > M`.
    pub fn valley_radius(&self, c: Vector2<f64>) -> f64 {
        let m = self.obstacles.len() as f64;
        let sum = self.obstacles.iter().map(|p| p - c).sum::<Vector2<f64>>();
        valley(self.destination, c, sum, m, self.k)
    }

    /// The scalar `2 / Π_i |P_d − P_i|^{2/k}` of [`Self::destination_hessian`]: the spring
    /// constant per unit `μ` used by the critical damping `lambda_c` (eq. `critdamp`).
    pub fn destination_stiffness(&self) -> f64 {
        2.0 * (-self.ln_destination / self.k).exp()
    }

    /// `2/|h_d| + (2/k) Σ_i 1/|h_i|`: the sum of the magnitudes of the terms of eq.
    /// (`gradient`) at `h`, the natural scale against which an error in `∇phi_k` (or a
    /// "zero" gradient) is measured. `+∞` at the singular points.
    pub fn grad_term_scale(&self, h: Vector2<f64>) -> f64 {
        let obstacles: f64 = self.obstacles.iter().map(|p| 1.0 / (h - p).norm()).sum();
        2.0 / (h - self.destination).norm() + (2.0 / self.k) * obstacles
    }

    /// `2/|h_d|² + (2/k) Σ_i 1/|h_i|²`: the sum of the magnitudes of the terms of eq.
    /// (`hessquadratic`) at `h`, the scale against which a Hessian entry or eigenvalue counts
    /// as zero. `+∞` at the singular points.
    pub fn hess_term_scale(&self, h: Vector2<f64>) -> f64 {
        let obstacles: f64 = self
            .obstacles
            .iter()
            .map(|p| 1.0 / (h - p).norm_squared())
            .sum();
        2.0 / (h - self.destination).norm_squared() + (2.0 / self.k) * obstacles
    }

    /// The unit descent direction `−∇varphi/|∇varphi| = −∇phi_k/|∇phi_k|`.
    ///
    /// `sigma' > 0` is a scalar factor, so the direction is taken from `∇phi_k` and stays
    /// well defined where `sigma'` underflows (far from the destination, near obstacles).
    /// `None` at `P_d`, at obstacle points and at exact critical points (`∇phi_k = 0`); the
    /// kinematic law (eq. `kinctrl`) returns `u = 0` there.
    pub fn descent_direction(&self, h: Vector2<f64>) -> Option<Vector2<f64>> {
        let g = self.grad_phi_k(h).ok()?;
        // Guard: scale before normalising so that |g| neither overflows nor underflows.
        let s = g.x.abs().max(g.y.abs());
        if s == 0.0 || !s.is_finite() {
            return None;
        }
        let g = g / s;
        Some(-g / g.norm())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world() -> PointWorld {
        PointWorld::new(
            Vector2::new(1.0, 0.5),
            vec![Vector2::new(-1.0, 0.0), Vector2::new(0.5, -1.5)],
        )
        .unwrap()
    }

    #[test]
    fn default_k_is_m_plus_one_and_k_le_m_is_rejected() {
        let w = world();
        assert_eq!(w.k(), 3.0);
        assert_eq!(
            w.clone().with_k(2.0),
            Err(PotentialError::KNotAttractive {
                k: 2.0,
                obstacles: 2
            })
        );
        assert!(w.clone().with_k(f64::NAN).is_err());
        assert!(w.clone().with_k(f64::INFINITY).is_err());
        assert_eq!(w.with_k(2.5).unwrap().k(), 2.5);
    }

    #[test]
    fn invalid_worlds_are_typed_errors() {
        let d = Vector2::new(0.0, 0.0);
        let a = Vector2::new(1.0, 0.0);
        assert_eq!(
            PointWorld::new(d, vec![a, d]),
            Err(PotentialError::ObstacleAtDestination { index: 1 })
        );
        assert_eq!(
            PointWorld::new(d, vec![a, Vector2::new(2.0, 0.0), a]),
            Err(PotentialError::DuplicateObstacle {
                first: 0,
                second: 2
            })
        );
        assert_eq!(
            PointWorld::new(Vector2::new(f64::NAN, 0.0), vec![a]),
            Err(PotentialError::NonFinite { index: None })
        );
        assert_eq!(
            PointWorld::new(d, vec![Vector2::new(0.0, f64::INFINITY)]),
            Err(PotentialError::NonFinite { index: Some(0) })
        );
    }

    #[test]
    fn value_matches_the_closed_form_quotient() {
        // sigma(phi_k(h)) = |h_d|² / (|h_d|² + Π|h_i|^{2/k})
        let w = world();
        for h in [
            Vector2::new(0.3, 0.2),
            Vector2::new(-2.0, 3.0),
            Vector2::new(4.0, -1.0),
        ] {
            let hd2 = (h - w.destination()).norm_squared();
            let prod: f64 = w
                .obstacles()
                .iter()
                .map(|p| (h - p).norm_squared().powf(1.0 / w.k()))
                .product();
            let expected = hd2 / (hd2 + prod);
            assert!((w.varphi(h) - expected).abs() < 1e-15, "at {h:?}");
        }
    }

    #[test]
    fn singular_points_have_exact_limits() {
        let w = world();
        let d = w.destination();
        let p = w.obstacles()[1];
        assert_eq!(w.phi_k(d), f64::NEG_INFINITY);
        assert_eq!(w.phi_k(p), f64::INFINITY);
        assert_eq!(w.varphi(d), 0.0);
        assert_eq!(w.varphi(p), 1.0);
        assert_eq!(w.grad_varphi(d), Ok(Vector2::zeros()));
        assert_eq!(w.grad_varphi(p), Err(Singularity::Obstacle(1)));
        assert_eq!(w.grad_phi_k(d), Err(Singularity::Destination));
        assert_eq!(w.hess_varphi(d), Ok(w.destination_hessian()));
        assert_eq!(w.descent_direction(d), None);
        assert_eq!(w.descent_direction(p), None);
        assert_eq!(w.singularity(p), Some(Singularity::Obstacle(1)));
        assert_eq!(w.singularity(Vector2::new(9.0, 9.0)), None);
    }

    /// `r*` is where `phi_k` has its radial minimum along the ray facing away from `D`: a
    /// scan of `phi_k` finds the minimum within O(1) m of the closed form (0.2 % at
    /// `r* = 350`, 1.2 % at `r* = 72`).
    #[test]
    fn valley_radius_is_the_far_field_radial_minimum() {
        let c = Vector2::new(0.3, -0.2);
        for (k, offset) in [(2.01, 0.0), (2.05, 0.0), (2.02, 1.0)] {
            let w = world().with_k(k).unwrap();
            let r_star = w.valley_radius(c + Vector2::new(offset, 0.0));
            let cc = c + Vector2::new(offset, 0.0);
            let m = 2.0;
            let d = (w.destination() - cc)
                - w.obstacles().iter().map(|p| p - cc).sum::<Vector2<f64>>() / k;
            assert!((r_star - k / (k - m) * d.norm()).abs() < 1e-12 * r_star);
            assert!(r_star > 20.0, "k = {k}: r* = {r_star}");
            let away = -d.normalize();
            let (best, _) = (1..4000)
                .map(|i| r_star * (0.3 + i as f64 * 0.001))
                .map(|r| (r, w.phi_k(cc + r * away)))
                .fold((0.0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
            // The neglected terms are O(1/r²): the minimum moves by O(1) m, and the scan step is
            // 0.001 r*.
            assert!(
                (best - r_star).abs() < 1.0 + 0.001 * r_star,
                "k = {k}: minimum at {best}, r* = {r_star}"
            );
        }
    }
}
