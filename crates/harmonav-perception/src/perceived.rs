//! Perceived shapes: radial hulls or low-order Fourier stars ([`StarForm`]), the certified
//! construction of a star that contains a sampled region, the kernel test and the merge.
//!
//! **Containment by boundary samples.** Let `Y` be a bounded region and `X ⊂ ℝ²` a finite set
//! such that every point of `∂Y` lies within `h/2` of a point of `X`. If a star `F` satisfies
//!
//! ```text
//! hi_F(x) ≤ −h/2  for every x ∈ X        (hi_F of StarShape::signed_distance_bounds)   (eq. certify)
//! ```
//!
//! then `B(x, h/2) ⊂ F` for every sample, so `∂Y ⊂ F`, and `Y ⊂ F`: a point of `Y` outside `F`
//! could be joined to infinity outside `F` (the complement of a star is connected), and that
//! path would leave the bounded `Y` through `∂Y ⊂ F`. Every shape this crate returns has
//! passed eq. certify for the region it claims to contain.

use std::f64::consts::{PI, TAU};

use harmonav_transform::{ShapeError, StarShape};
use nalgebra::Vector2;

/// Number of angular bins of the requirement `g` (eq. fit).
const BINS: usize = 512;

/// Raise-and-recheck rounds before falling back to a disc.
const ROUNDS: usize = 8;

/// One harmonic `(n, a_n, b_n)` of a Fourier star: `a_n cos nθ + b_n sin nθ`.
pub type Harmonic = (u32, f64, f64);

/// How a perceived star is represented ([`crate::Options::form`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StarForm {
    /// A Fourier star of order `≤ Options::order` (eq. fit), raised until it contains its
    /// region (the default).
    #[default]
    Fourier,
    /// The radial hull of the cover's discs (eq. radialhull of
    /// `harmonav_transform::hull`): a tabulated star that follows the region to within two
    /// cells' turn, with no Gibbs undershoot to raise away. Opt-in: it follows merged
    /// shapes' wedges, in front of which the kinematic law stalls (docs/maths.md §12.10).
    Hull,
}

/// A perceived obstacle: a star about `centre` that contains what it was fitted to, either the
/// Fourier star `R(θ) = r0 + Σ (a_n cos nθ + b_n sin nθ)` ([`StarShape::fourier_star`]) or a
/// radial hull ([`StarShape::radial_hull`]), with the bounds of `R'` and `R''` kept for the
/// kernel test and the boundary cover.
#[derive(Clone, Debug)]
pub struct Perceived {
    shape: StarShape,
    form: Form,
    /// `L1 ≥ max|R'|` and `L2 ≥ max|R''|`.
    l1: f64,
    l2: f64,
}

#[derive(Clone, Debug)]
enum Form {
    Fourier {
        r0: f64,
        harmonics: Vec<(u32, f64, f64)>,
    },
    Hull {
        radii: Vec<f64>,
        /// Per cell `[θ_i, θ_{i+1}]`: bounds of `|p'| = √(R² + R'²)` on it (the cover's speed).
        speeds: Vec<f64>,
    },
}

/// `Σ|c_n|`, `L1 = Σ n|c_n|` (bounds `|R'|`) and `L2 = Σ n²|c_n|` (bounds `|R''|`),
/// `|c_n| = √(a_n² + b_n²)`.
fn sums(harmonics: &[(u32, f64, f64)]) -> (f64, f64, f64) {
    harmonics
        .iter()
        .fold((0.0, 0.0, 0.0), |(s, l1, l2), &(n, a, b)| {
            let (n, c) = (n as f64, a.hypot(b));
            (s + c, l1 + n * c, l2 + n * n * c)
        })
}

impl Perceived {
    /// The Fourier star `r0, harmonics` about `centre`; errors as [`StarShape::fourier_star`].
    pub fn new(
        centre: Vector2<f64>,
        r0: f64,
        harmonics: Vec<(u32, f64, f64)>,
    ) -> Result<Self, ShapeError> {
        let shape = StarShape::fourier_star(centre, r0, &harmonics)?;
        let (_, l1, l2) = sums(&harmonics);
        Ok(Self {
            shape,
            form: Form::Fourier { r0, harmonics },
            l1,
            l2,
        })
    }

    /// The radial hull ([`StarShape::radial_hull`]) of `discs` about `centre` as a perceived
    /// shape. `L1`, `L2` from its table's cells: `R'` at most twice the cell's secant (the
    /// cells are monotone, with end slopes at most twice the secant), `R''` linear on each
    /// cell, so largest at its ends.
    fn hull(centre: Vector2<f64>, discs: &[(Vector2<f64>, f64)]) -> Result<Self, ShapeError> {
        let radii = harmonav_transform::hull::radial_hull_radii(centre, discs)?;
        Self::tabulated(centre, radii)
    }

    /// The tabulated star of `radii` about `centre` ([`StarShape::tabulated`]) as a perceived
    /// shape: how a radial hull is rebuilt from its radii ([`Perceived::radii`]).
    pub fn tabulated(centre: Vector2<f64>, radii: Vec<f64>) -> Result<Self, ShapeError> {
        let shape = StarShape::tabulated(centre, &radii)?;
        let g = radii.len();
        let step = TAU / g as f64;
        let nodes: Vec<(f64, f64)> = (0..g).map(|i| shape.radius(i as f64 * step)).collect();
        let (mut l1, mut l2) = (0.0f64, 0.0f64);
        let mut speeds = Vec::with_capacity(g);
        // The slopes are read back through the shape's own evaluation: a relative pad for
        // its rounding.
        let pad = 1.0 + 1e-9;
        for i in 0..g {
            let ((ra, da), (rb, db)) = (nodes[i], nodes[(i + 1) % g]);
            let slope = da.abs().max(db.abs()).max(2.0 * (rb - ra).abs() / step) * pad;
            l1 = l1.max(slope);
            let d2a = (-6.0 * ra - 4.0 * step * da + 6.0 * rb - 2.0 * step * db) / (step * step);
            let d2b = (6.0 * ra + 2.0 * step * da - 6.0 * rb + 4.0 * step * db) / (step * step);
            l2 = l2.max(d2a.abs()).max(d2b.abs());
            // `R ≤ max(R_i, R_{i+1}) + ½·step·max|R'|` on the cell (from the nearer end).
            let r = (ra.max(rb) + 0.5 * step * slope) * pad;
            speeds.push(r.hypot(slope));
        }
        Ok(Self {
            shape,
            form: Form::Hull { radii, speeds },
            l1,
            l2: l2 * pad,
        })
    }

    /// A radial hull's radii `R_i` at `θ_i = 2πi/G` ([`Perceived::tabulated`] rebuilds it);
    /// `None` for a Fourier star.
    #[must_use]
    pub fn radii(&self) -> Option<&[f64]> {
        match &self.form {
            Form::Hull { radii, .. } => Some(radii),
            Form::Fourier { .. } => None,
        }
    }

    /// Which representation this is.
    #[must_use]
    pub fn form(&self) -> StarForm {
        match self.form {
            Form::Fourier { .. } => StarForm::Fourier,
            Form::Hull { .. } => StarForm::Hull,
        }
    }

    /// The star shape (hand it to `Navigator::add_obstacle`, which grows it by the robot).
    #[must_use]
    pub fn shape(&self) -> &StarShape {
        &self.shape
    }

    /// The star's centre `c`.
    #[must_use]
    pub fn centre(&self) -> Vector2<f64> {
        self.shape.centre()
    }

    /// A Fourier star's mean radius `r0` and harmonics `(n, a_n, b_n)`; `None` for a hull.
    #[must_use]
    pub fn fourier(&self) -> Option<(f64, &[Harmonic])> {
        match &self.form {
            Form::Fourier { r0, harmonics } => Some((*r0, harmonics)),
            Form::Hull { .. } => None,
        }
    }

    /// A certified bound of `max R`, the one the covers use (`r0 + Σ|c_n|` for a Fourier star).
    fn r_max(&self) -> f64 {
        match &self.form {
            Form::Fourier { r0, harmonics } => r0 + sums(harmonics).0,
            Form::Hull { .. } => self.shape.radius_bounds().1,
        }
    }

    /// The area `½∮R² dθ`, m²: `π(r0² + ½Σ|c_n|²)` for a Fourier star (Parseval),
    /// [`StarShape::area`] for a hull.
    #[must_use]
    pub fn area(&self) -> f64 {
        match &self.form {
            Form::Fourier { r0, harmonics } => {
                let h: f64 = harmonics.iter().map(|&(_, a, b)| a * a + b * b).sum();
                PI * (r0 * r0 + 0.5 * h)
            }
            Form::Hull { .. } => self.shape.area(),
        }
    }

    /// Whether the star is star-shaped about `p` (certified): the boundary `p(θ) = c + R u`
    /// turns monotonically about `p`,
    ///
    /// ```text
    /// f(θ) = (p(θ) − p) × p'(θ) > 0,   p' = R'u + R u⊥                         (eq. kernel)
    /// |f'| = |(p(θ) − p) × p''| ≤ (|c − p| + R_max)(L2 + 2L1 + R_max)
    /// ```
    ///
    /// checked on a grid of `G` directions with the margin `max|f'|·π/G` between grid points
    /// (`G` doubled up to 65 536 while the margin is what fails). `p` must be inside.
    #[must_use]
    pub fn star_about(&self, p: Vector2<f64>) -> bool {
        if !self.shape.contains(p) {
            return false;
        }
        let (l1, l2) = (self.l1, self.l2);
        let rmax = self.r_max();
        let c = self.centre();
        let slope = ((c - p).norm() + rmax) * (l2 + 2.0 * l1 + rmax);
        let mut g = 4096usize;
        loop {
            let margin = slope * PI / g as f64;
            let mut min = f64::INFINITY;
            for j in 0..g {
                let t = TAU * j as f64 / g as f64;
                let u = Vector2::new(t.cos(), t.sin());
                let (r, dr) = self.shape.radius_along(u);
                let q = c + r * u - p;
                let dp = dr * u + r * Vector2::new(-u.y, u.x);
                min = min.min(q.x * dp.y - q.y * dp.x);
                if min <= 0.0 {
                    return false;
                }
            }
            if min > margin {
                return true;
            }
            if g >= 65_536 {
                return false;
            }
            g *= 2;
        }
    }

    /// Points of the boundary such that every boundary point lies within `h/2` of one:
    /// `p(θ_j)` with `Δθ = h/√(R_max² + L1²)` (the arc between samples is at most `h` long,
    /// `|p'| = √(R² + R'²)`). A hull is sampled cell by cell, with its own cell's bound of
    /// `|p'|`: one radial jump no longer sets the spacing of the whole turn (docs/maths.md
    /// §12.11: a merged hull's cover went from about 10⁵ samples to a few thousand).
    #[must_use]
    pub fn boundary_cover(&self, h: f64) -> Vec<Vector2<f64>> {
        if let Form::Hull { speeds, .. } = &self.form {
            let step = TAU / speeds.len() as f64;
            return speeds
                .iter()
                .enumerate()
                .flat_map(|(i, &speed)| {
                    let n = ((step * speed / h).ceil() as usize).max(1);
                    (0..n).map(move |k| {
                        self.shape
                            .boundary_point(step * (i as f64 + k as f64 / n as f64))
                    })
                })
                .collect();
        }
        let speed = self.r_max().hypot(self.l1);
        let count = ((TAU * speed / h).ceil() as usize).max(16);
        (0..count)
            .map(|j| self.shape.boundary_point(TAU * j as f64 / count as f64))
            .collect()
    }
}

/// How a certified star was obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Certification {
    /// Samples checked with eq. certify.
    pub samples: usize,
    /// Raise-and-recheck rounds after the first construction.
    pub raises: usize,
    /// Whether the harmonics were dropped (a disc about the centre) after `ROUNDS` = 8 rounds.
    pub disc_fallback: bool,
}

/// The least Fourier star of order `≤ order` about `c` found by eq. fit that passes eq.
/// certify for `samples` with spacing `h`.
///
/// ```text
/// g_j = max { |x − c| + h/2 : x ∈ samples, angle(x − c) in bin j }   (512 bins)   (eq. fit)
/// R̃ = a Fourier sum of order ≤ `order` (the least-squares sum of g, or a smoothed envelope
///     of g: the candidate of least area, `tightest_candidate`)
/// r0 = a_0 + max_j (g_j − R̃(θ_j))⁺ + L1·π/512          (R ≥ g on every bin: |R'| ≤ L1)
/// ```
///
/// Then eq. certify is checked; while some sample fails by `v`, `r0` grows by
/// `1.05·v·√(R_min² + L1²)/R_min` (growing `R` by `Δ` moves the boundary outward along the
/// normal by at least `Δ·R/√(R² + R'²)`). After `ROUNDS` = 8 rounds the harmonics are dropped:
/// the disc `r0 = max|x − c| + h` passes eq. certify by construction. Empty bins (directions
/// with no sample) take the largest neighbouring requirement.
pub fn certified_star(
    c: Vector2<f64>,
    samples: &[Vector2<f64>],
    h: f64,
    order: u32,
) -> Result<(Perceived, Certification), ShapeError> {
    let mut g = [f64::NEG_INFINITY; BINS];
    let mut reach = 0.0f64;
    for x in samples {
        let v = x - c;
        let rho = v.norm() + 0.5 * h;
        reach = reach.max(v.norm());
        let t = v.y.atan2(v.x);
        let j = (((t + PI) / TAU * BINS as f64).floor() as usize).min(BINS - 1);
        g[j] = g[j].max(rho);
    }
    // Empty bins: the larger of the nearest filled bins on either side.
    if g.iter().all(|v| !v.is_finite()) {
        return Err(ShapeError::Invalid {
            field: "samples",
            problem: "no sample to contain".into(),
        });
    }
    let filled = g;
    for j in 0..BINS {
        if filled[j].is_finite() {
            continue;
        }
        let left = (1..BINS)
            .map(|k| filled[(j + BINS - k) % BINS])
            .find(|v| v.is_finite());
        let right = (1..BINS)
            .map(|k| filled[(j + k) % BINS])
            .find(|v| v.is_finite());
        g[j] = left.unwrap_or(0.0).max(right.unwrap_or(0.0));
    }
    crate::work::count(|w| w.certifications += 1);
    let (mut r0, harmonics, sum_c, l1) = tightest_candidate(&g, order, h);
    for round in 0..ROUNDS {
        // A star too detailed for its outline cap cannot arise at these orders and sizes; if
        // it does, the disc below is the answer.
        let Ok(p) = Perceived::new(c, r0, harmonics.clone()) else {
            break;
        };
        let worst = uncertified(&p, samples, h);
        if worst <= 0.0 {
            return Ok((
                p,
                Certification {
                    samples: samples.len(),
                    raises: round,
                    disc_fallback: false,
                },
            ));
        }
        let r_min = (r0 - sum_c).max(1e-9);
        r0 += 1.05 * worst * r_min.hypot(l1) / r_min + 1e-9 * r0;
    }
    disc_fallback(c, samples, h, reach)
}

/// The certified star of `form` about `c` for `samples` with spacing `h` ([`certified_star`]
/// of order `order`, or [`certified_hull`]).
pub fn certified(
    form: StarForm,
    c: Vector2<f64>,
    samples: &[Vector2<f64>],
    h: f64,
    order: u32,
) -> Result<(Perceived, Certification), ShapeError> {
    match form {
        StarForm::Fourier => certified_star(c, samples, h, order),
        StarForm::Hull => certified_hull(c, samples, h),
    }
}

/// The radial hull about `c` of the discs `B(x, h/2 + τ)`, `x ∈ samples`
/// ([`StarShape::radial_hull`], eq. radialhull), checked by eq. certify.
///
/// The hull holds each disc exactly, so a sample lies `h/2 + τ` inside it; `τ` absorbs the
/// bracket of the certified distance (twice the outline's chord bound `δ ≤ 5e-5·max R`):
/// `τ = 2.5e-4·(max|x − c| + h)`, multiplied by 4 while eq. certify fails (`ROUNDS` = 8 times;
/// then the disc `r = max|x − c| + h` about `c`, as [`certified_star`]). `raises` counts the
/// rounds.
pub fn certified_hull(
    c: Vector2<f64>,
    samples: &[Vector2<f64>],
    h: f64,
) -> Result<(Perceived, Certification), ShapeError> {
    if samples.is_empty() {
        return Err(ShapeError::Invalid {
            field: "samples",
            problem: "no sample to contain".into(),
        });
    }
    crate::work::count(|w| w.certifications += 1);
    let reach = samples.iter().map(|x| (x - c).norm()).fold(0.0, f64::max);
    let mut pad = 2.5e-4 * (reach + h);
    for round in 0..ROUNDS {
        let discs: Vec<(Vector2<f64>, f64)> = samples.iter().map(|&x| (x, 0.5 * h + pad)).collect();
        // A hull too detailed for its outline cap, or a centre on a disc's circle: the disc
        // below is the answer, as for a Fourier star.
        let Ok(p) = Perceived::hull(c, &discs) else {
            break;
        };
        if uncertified(&p, samples, h) <= 0.0 {
            return Ok((
                p,
                Certification {
                    samples: samples.len(),
                    raises: round,
                    disc_fallback: false,
                },
            ));
        }
        pad *= 4.0;
    }
    disc_fallback(c, samples, h, reach)
}

/// The disc `r = reach + h` about `c` (`reach = max|x − c|`), which passes eq. certify by
/// construction: the answer after `ROUNDS` failed rounds.
fn disc_fallback(
    c: Vector2<f64>,
    samples: &[Vector2<f64>],
    h: f64,
    reach: f64,
) -> Result<(Perceived, Certification), ShapeError> {
    let p = Perceived::new(c, reach + h, Vec::new())?;
    debug_assert!(uncertified(&p, samples, h) <= 0.0);
    Ok((
        p,
        Certification {
            samples: samples.len(),
            raises: ROUNDS,
            disc_fallback: true,
        },
    ))
}

/// How far eq. certify fails for `p` over `samples`: `max_x hi_F(x) + h/2` (`≤ 0`: passed).
fn uncertified(p: &Perceived, samples: &[Vector2<f64>], h: f64) -> f64 {
    samples
        .iter()
        .map(|&x| p.shape().signed_distance_bounds(x).1 + 0.5 * h)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The direction of bin `j`, rad.
fn theta(j: usize) -> f64 {
    -PI + (j as f64 + 0.5) * TAU / BINS as f64
}

/// `(cos nθ_j, sin nθ_j)` for `n = 1..=order` (row `n − 1`) at the bins' directions.
fn basis(order: u32) -> Vec<Vec<(f64, f64)>> {
    (1..=order)
        .map(|n| {
            (0..BINS)
                .map(|j| (f64::from(n) * theta(j)).sin_cos())
                .map(|(s, c)| (c, s))
                .collect()
        })
        .collect()
}

/// `a_0` and the harmonics `n ≤ order` of the binned function `f` (`basis` of that order),
/// each multiplied by `w_n`.
fn fourier(
    f: &[f64; BINS],
    basis: &[Vec<(f64, f64)>],
    w: impl Fn(u32) -> f64,
) -> (f64, Vec<(u32, f64, f64)>) {
    let a0 = f.iter().sum::<f64>() / BINS as f64;
    let harmonics = (1u32..)
        .zip(basis)
        .map(|(n, row)| {
            let (a, b) = f
                .iter()
                .zip(row)
                .fold((0.0, 0.0), |(a, b), (fj, &(c, s))| (a + fj * c, b + fj * s));
            let k = 2.0 * w(n) / BINS as f64;
            (n, k * a, k * b)
        })
        .collect();
    (a0, harmonics)
}

/// The normalised Jackson kernel of degree `≤ order`, `J(t) ∝ (sin(mt/2)/sin(t/2))⁴`,
/// `m = ⌊order/2⌋ + 1`, by its Fourier weights `ĵ_n` (`ĵ_0 = 1`; exact on the bins, `J` being a
/// trigonometric polynomial of degree `2m − 2 < BINS`), and `m`.
fn jackson(order: u32) -> (Vec<f64>, u32) {
    let m = order / 2 + 1;
    let kernel: Vec<f64> = (0..BINS)
        .map(|j| {
            let t = TAU * j as f64 / BINS as f64;
            let s = (0.5 * t).sin();
            if s.abs() < 1e-12 {
                f64::from(m).powi(4)
            } else {
                ((0.5 * f64::from(m) * t).sin() / s).powi(4)
            }
        })
        .collect();
    let mass: f64 = kernel.iter().sum();
    let weights = (0..=order)
        .map(|n| {
            kernel
                .iter()
                .enumerate()
                .map(|(j, k)| k * (f64::from(n) * TAU * j as f64 / BINS as f64).cos())
                .sum::<f64>()
                / mass
        })
        .collect();
    (weights, m)
}

/// Of eq. fit's candidates, the one of least `Σ_j R(θ_j)²` (the area, to the bins) once raised to
/// `R ≥ g` on every bin: `(r0, harmonics, Σ|c_n|, L1)`.
///
/// ```text
/// least squares:  R̃ = the partial sum of g of order `order`                      (eq. fit)
/// smoothed:       R̃ = J ∗ G_w,  G_w(θ) = max { g(φ) : |φ − θ| ≤ w },  w ∈ {0, π/2m, π/m, 2π/m}
/// ```
///
/// `J` is the Jackson kernel ([`jackson`]), non-negative with most of its mass within `±π/m`,
/// so for `w > 0`, `J ∗ G_w ≥ g` but for the kernel's tail (`w = 0` is plain smoothing): the
/// raise `max(g − R̃)⁺` that follows is small, where the least-squares sum undershoots every
/// peak of `g` (Gibbs) and its raise lifts every direction, the robot's side of a merged shape
/// included. Any candidate is sound: eq. certify decides containment ([`certified_star`]);
/// this only picks the tightest (before certification, which may raise it further).
fn tightest_candidate(
    g: &[f64; BINS],
    order: u32,
    h: f64,
) -> (f64, Vec<(u32, f64, f64)>, f64, f64) {
    let (weights, m) = jackson(order);
    let basis = basis(order);
    let mut candidates = vec![fourier(g, &basis, |_| 1.0)];
    for window in [0.0, 0.5, 1.0, 2.0] {
        let w = (window * PI / f64::from(m) / (TAU / BINS as f64)).round() as usize;
        let mut dilated = *g;
        if w > 0 {
            for (j, d) in dilated.iter_mut().enumerate() {
                *d = (0..=2 * w)
                    .map(|k| g[(j + BINS + k - w) % BINS])
                    .fold(f64::NEG_INFINITY, f64::max);
            }
        }
        candidates.push(fourier(&dilated, &basis, |n| weights[n as usize]));
    }
    candidates
        .into_iter()
        .map(|(a0, harmonics)| {
            let (sum_c, l1, _) = sums(&harmonics);
            let radius = |j: usize| {
                a0 + harmonics
                    .iter()
                    .zip(&basis)
                    .map(|(&(_, a, b), row)| a * row[j].0 + b * row[j].1)
                    .sum::<f64>()
            };
            let short = (0..BINS).map(|j| g[j] - radius(j)).fold(0.0f64, f64::max);
            // The least r0 that keeps R > 0 with room: R ≥ r0 − Σ|c_n|.
            let r0 = (a0 + short + l1 * PI / BINS as f64).max(sum_c + 0.5 * h);
            let area: f64 = (0..BINS).map(|j| (radius(j) - a0 + r0).powi(2)).sum();
            (area, (r0, harmonics, sum_c, l1))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c)| c)
        .expect("five candidates")
}

/// Why two overlapping perceived shapes could not be merged.
#[derive(Clone, Debug, PartialEq)]
pub enum MergeFailure {
    /// The merged star could not be built.
    Shape(ShapeError),
}

/// The merge of two overlapping perceived shapes `A`, `B` into one star `M ⊃ A ∪ B`:
/// [`certified_star`] about a point `p` over the boundary covers of both shapes, less the
/// samples more than `h` inside the other shape (they are not on `∂(A ∪ B)`, nor within `h/2`
/// of it). Eq. certify puts every point of `∂(A ∪ B)` inside `M`, and that is enough for any
/// `p` (eq. hull): a point `y ∈ A ∪ B` lies on the ray from `p` before the ray's last point
/// `z` of the closed, bounded `A ∪ B`, which is a boundary point, so in `M`; `M` is star-shaped
/// about `p`, so `[p, z] ⊂ M` holds `y`.
///
/// ```text
/// R_M(θ) ≥ sup { ρ : p + ρ u(θ) ∈ A ∪ B }        (the radial hull of A ∪ B about p)   (eq. hull)
/// ```
///
/// Candidates for `p`: the two centres and seven points evenly between them. For overlapping
/// shapes a point of both kernels (eq. kernel) makes the hull the union itself (`max(R_A,
/// R_B)` about `p`; shapes merged across a gap, `Options::merge_gap`, also get the gap's
/// shadow): the one nearest the midpoint is kept. When there is none (two bow ties touching at their tips), the
/// hull also fills the union's shadows about `p`: every candidate is tried and the merged star
/// of least area is kept, so two overlapping shapes always merge (issue 26: a merge instead of
/// "not a star world").
pub fn merge(
    a: &Perceived,
    b: &Perceived,
    h: f64,
    order: u32,
) -> Result<(Perceived, Certification), MergeFailure> {
    merge_clear_of(a, b, h, order, None)
}

/// The number of directions, and the fractions of the radius along each, of the points inside
/// each shape that [`merge_clear_of`] also tries as centres.
const CLEAR_DIRECTIONS: usize = 16;
const CLEAR_FRACTIONS: [f64; 3] = [0.3, 0.6, 0.9];

/// [`merge`] that keeps the sensor `s` out when it can (`clear = Some((s, r_k))`): when the
/// merged star of [`merge`]'s choice comes nearer than `r_k` to `s` (the robot would be in the
/// star grown by its radius and margin), the radial hull about further centres is tried, points
/// `c + f·R(θ)·u(θ)` inside either shape (`f ∈ {0.3, 0.6, 0.9}`, 16 directions θ), and the one
/// of least area whose certified distance to `s` is at least `r_k` is kept; if none is, [`merge`]'s
/// choice stands. Any centre gives a star that holds both shapes (eq. hull), so the choice
/// changes the shape, never what it holds. Radial hulls only (a Fourier merge is [`merge`]'s).
///
/// Why another centre helps (docs/maths.md §12.13): the star about `p` holds every segment from
/// `p` to a point of `A ∪ B`, so a sensor between two shapes, in a gap they leave, is held by
/// the star about any `p` that sees a part of the union behind the sensor, and by none that
/// sees the gap's line of sight through the sensor clear.
pub fn merge_clear_of(
    a: &Perceived,
    b: &Perceived,
    h: f64,
    order: u32,
    clear: Option<(Vector2<f64>, f64)>,
) -> Result<(Perceived, Certification), MergeFailure> {
    crate::work::count(|w| w.merges += 1);
    let (ca, cb) = (a.centre(), b.centre());
    let mid = 0.5 * (ca + cb);
    let candidates: Vec<Vector2<f64>> =
        (0..=8).map(|k| ca + (cb - ca) * (k as f64 / 8.0)).collect();
    let mut samples: Vec<Vector2<f64>> = a
        .boundary_cover(h)
        .into_iter()
        .filter(|&x| b.shape.signed_distance_bounds(x).1 >= -h)
        .collect();
    samples.extend(
        b.boundary_cover(h)
            .into_iter()
            .filter(|&x| a.shape.signed_distance_bounds(x).1 >= -h),
    );
    if a.form() == StarForm::Hull || b.form() == StarForm::Hull {
        let first = least_hull(&candidates, &samples, h, None)
            .unwrap_or_else(|| Err(no_candidate()))
            .map_err(MergeFailure::Shape)?;
        let Some((s, keep)) = clear else {
            return Ok(first);
        };
        if first.0.shape().signed_distance_bounds(s).0 >= keep {
            return Ok(first);
        }
        let inside: Vec<Vector2<f64>> = [a, b]
            .iter()
            .flat_map(|p| {
                (0..CLEAR_DIRECTIONS).flat_map(move |j| {
                    let theta = std::f64::consts::TAU * j as f64 / CLEAR_DIRECTIONS as f64;
                    let r = p.shape().radius(theta).0;
                    let u = Vector2::new(theta.cos(), theta.sin());
                    CLEAR_FRACTIONS.map(|f| p.centre() + (f * r) * u)
                })
            })
            .collect();
        return Ok(match least_hull(&inside, &samples, h, Some((s, keep))) {
            Some(Ok(clear)) => clear,
            _ => first,
        });
    }
    let kernel = candidates
        .iter()
        .copied()
        .filter(|&p| a.star_about(p) && b.star_about(p))
        .min_by(|p, q| (p - mid).norm().total_cmp(&(q - mid).norm()));
    if let Some(p) = kernel {
        return certified_star(p, &samples, h, order).map_err(MergeFailure::Shape);
    }
    let mut best: Option<(Perceived, Certification)> = None;
    for p in candidates {
        let merged = certified_star(p, &samples, h, order).map_err(MergeFailure::Shape)?;
        if best.as_ref().is_none_or(|b| merged.0.area() < b.0.area()) {
            best = Some(merged);
        }
    }
    Ok(best.expect("nine candidates"))
}

/// [`merge`] of hulls (and a fit's centre clear of the sensor, `fit::clear_of_sensor`): the
/// radial hull of the kept samples' discs about each candidate, the one
/// of least area that passes eq. certify (about a common kernel point the hull is the union
/// itself, so the least area finds one when the candidates hold it) and, with `clear =
/// Some((s, r_k))`, lies at least `r_k` from `s` by its certified distance. Every candidate's
/// hull holds both shapes (eq. hull); the area only picks. `None` when no candidate qualifies
/// and none failed; the last failure when none qualifies.
///
/// With `clear`, a candidate whose star certainly comes nearer than `r_k` to `s`
/// ([`held_near`]: a segment from it to a sample passes that near) is skipped without building
/// its star: it could not qualify, so the choice is the same, to the bit. A skipped candidate
/// counts as neither qualifying nor failed; both callers with `clear` take a failure as they
/// take `None` (the first choice stands, or no clear fit). Where the sensor is walled in by the
/// samples (a noisy scan's fits all round it) this skips nearly every candidate, which cost a
/// certified hull each: 96 per merge and 48 per fit, 0.1–0.5 s, before 2026-12-06 (the hostile
/// round's D2).
///
/// The others are tried by their area floors ([`area_floor`], least first), and one whose floor
/// exceeds the least area found so far is skipped too: its star could not be smaller. The
/// choice is the loop's (the least area, the lowest index among equal areas; the failure of the
/// highest index when none qualifies), with most of a merge's nine stars never built.
pub(crate) fn least_hull(
    candidates: &[Vector2<f64>],
    samples: &[Vector2<f64>],
    h: f64,
    clear: Option<(Vector2<f64>, f64)>,
) -> Option<Result<(Perceived, Certification), ShapeError>> {
    // The candidates that may qualify, each with a floor of its star's area, least first
    // (candidates without one first, then by index).
    let mut order: Vec<(usize, Vector2<f64>, Option<f64>)> = Vec::with_capacity(candidates.len());
    for (i, &p) in candidates.iter().enumerate() {
        if clear.is_some_and(|(s, keep)| held_near(p, samples, 0.5 * h, s, keep)) {
            crate::work::count(|w| w.skipped += 1);
        } else {
            order.push((i, p, area_floor(p, samples, h)));
        }
    }
    order.sort_by(|a, b| {
        let key = |f: Option<f64>| f.unwrap_or(f64::NEG_INFINITY);
        key(a.2).total_cmp(&key(b.2))
    });
    let mut best: Option<(usize, (Perceived, Certification))> = None;
    let mut last_error: Option<(usize, ShapeError)> = None;
    for (i, p, floor) in order {
        if let (Some(f), Some((_, b))) = (floor, &best)
            && f > b.0.area()
        {
            // This star and every later one are larger than the best (`area_floor`).
            crate::work::count(|w| w.skipped += 1);
            continue;
        }
        match certified_hull(p, samples, h) {
            Ok(merged) => {
                let clear_of = |(s, keep): (Vector2<f64>, f64)| {
                    merged.0.shape().signed_distance_bounds(s).0 >= keep
                };
                let area = merged.0.area();
                let better = best
                    .as_ref()
                    .is_none_or(|(j, b)| area < b.0.area() || (area == b.0.area() && i < *j));
                if better && clear.is_none_or(clear_of) {
                    best = Some((i, merged));
                }
            }
            Err(e) => {
                if last_error.as_ref().is_none_or(|(j, _)| i > *j) {
                    last_error = Some((i, e));
                }
            }
        }
    }
    match (best, last_error) {
        (Some((_, b)), _) => Some(Ok(b)),
        (None, Some((_, e))) => Some(Err(e)),
        (None, None) => None,
    }
}

/// A floor of the area of [`certified_hull`]'s star about `c` (the area [`Perceived::area`]
/// compares), from the radii of its first round alone (one `radial_hull_radii`, no star
/// built, no sample certified): `½·Σ l_i²·2π/G·(1 − 10⁻⁹)`, `l_i = R⁰_i` where a disc reaches
/// the cell and 0 where none may (the radius equal to the least of the table: a cell no disc
/// reaches takes the table's floor, `harmonav_transform::hull`). A later round's discs are
/// larger (`τ` × 4), so each exit and each reached cell's radius only grows; the disc fallback
/// `max|x − c| + h` holds every first-round disc when `τ < h/2` (`None` otherwise, and when
/// the radii cannot be built); `10⁻⁹` covers the table's evaluation at its nodes. So no star
/// [`certified_hull`] returns about `c` has a smaller area.
///
/// [`least_hull`] tries its candidates by their floors and stops where the floor exceeds the
/// best area found: the same choice (the least area, the lowest index among equals), with
/// most of a merge's nine stars never built.
fn area_floor(c: Vector2<f64>, samples: &[Vector2<f64>], h: f64) -> Option<f64> {
    // As `certified_hull`'s first round.
    let reach = samples.iter().map(|x| (x - c).norm()).fold(0.0, f64::max);
    let pad = 2.5e-4 * (reach + h);
    if samples.is_empty() || pad >= 0.45 * h {
        return None;
    }
    let discs: Vec<(Vector2<f64>, f64)> = samples.iter().map(|&x| (x, 0.5 * h + pad)).collect();
    let radii = harmonav_transform::hull::radial_hull_radii(c, &discs).ok()?;
    let least = radii.iter().copied().fold(f64::INFINITY, f64::min);
    let sum: f64 = radii
        .iter()
        .map(|&r| if r > least { r * r } else { 0.0 })
        .sum();
    Some(0.5 * TAU * sum / radii.len() as f64 * (1.0 - 1e-9))
}

/// Whether every star about `p` that holds the discs `B(x, ρ)`, `x ∈ samples`, comes nearer
/// than `keep` to `s` (its true signed distance at `s` below `keep`): a star about `p` holds the
/// segment from `p` to each point it holds, so it holds the cone `conv(p, B(x, ρ))` and in it the
/// disc `B(p + t(x − p), tρ)` for every `t ∈ [0, 1]`. With `t` the parameter of the point of the
/// segment `[p, x]` nearest `s` and `d` their distance,
///
/// ```text
/// sd_F(s) ≤ max(0, d − tρ)  (or < 0, s inside F),   so   d − tρ < keep − η  ⇒  lo_F(s) ≤ sd_F(s) < keep
/// ```
///
/// (`η = 1e-9·(1 + |s|∞ + |p|∞ + |x − p|)` for the rounding of `d`; `lo_F` the certified lower
/// bound of `StarShape::signed_distance_bounds`). [`certified_hull`] about `p` returns such a
/// star (the radial hull of the discs of radius `h/2 + τ ≥ ρ = h/2` holds each disc, and the
/// disc fallback of radius `max|x − p| + h` holds them all), so a candidate for which this holds
/// fails `lo ≥ r_k` in [`least_hull`]. `false` for `keep ≤ 0`.
fn held_near(
    p: Vector2<f64>,
    samples: &[Vector2<f64>],
    rho: f64,
    s: Vector2<f64>,
    keep: f64,
) -> bool {
    keep > 0.0
        && samples.iter().any(|&x| {
            let v = x - p;
            let len2 = v.norm_squared();
            let t = if len2 > 0.0 {
                ((s - p).dot(&v) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let d = (p + t * v - s).norm();
            let eta = 1e-9 * (1.0 + s.amax() + p.amax() + len2.sqrt());
            d - t * rho < keep - eta
        })
}

/// The error of a merge with no candidate centre (never: [`merge`] tries nine).
fn no_candidate() -> ShapeError {
    ShapeError::Invalid {
        field: "centre",
        problem: "a merge needs at least one candidate centre".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two bow ties `R = 0.3 + 0.25 cos 2θ` (lobes along `x`, waists 0.05 m) about (0, ±0.6),
    /// as radial hulls, and a sensor between their lobes at (0.2, 0): [`merge`]'s choice among
    /// the nine centres on the segment between the centres holds the sensor (the star about a
    /// point on the axis fills the bay between the lobes); [`merge_clear_of`] finds a centre
    /// inside a lobe whose star keeps it `r_k` = 0.02 m out, and that star still holds both
    /// shapes (4 000 boundary points of each, eq. hull). Where no centre can (the sensor
    /// between the waists, or `r_k` = 0.3 m) [`merge`]'s choice stands.
    #[test]
    fn a_merge_keeps_a_sensor_in_a_bay_out_when_a_centre_allows() {
        let h = 0.01;
        let tie = |cy: f64| {
            let c = Vector2::new(0.0, cy);
            let samples: Vec<Vector2<f64>> = (0..2000)
                .map(|j| {
                    let t = std::f64::consts::TAU * j as f64 / 2000.0;
                    c + (0.3 + 0.25 * (2.0 * t).cos()) * Vector2::new(t.cos(), t.sin())
                })
                .collect();
            certified_hull(c, &samples, h).unwrap().0
        };
        let (upper, lower) = (tie(0.6), tie(-0.6));
        let (first, _) = merge(&upper, &lower, h, 6).unwrap();
        let s = Vector2::new(0.2, 0.0);
        assert!(
            first.shape().contains(s),
            "merge's choice must hold the sensor here"
        );
        let keep = 0.02;
        let (clear, _) = merge_clear_of(&upper, &lower, h, 6, Some((s, keep))).unwrap();
        let gap = clear.shape().signed_distance(s);
        assert!(gap >= keep, "{gap}");
        for p in [&upper, &lower] {
            for j in 0..4000 {
                let t = std::f64::consts::TAU * j as f64 / 4000.0;
                let x = p.shape().boundary_point(t);
                assert!(clear.shape().signed_distance(x) <= 1e-9, "{x:?} outside");
            }
        }
        for (s, keep) in [(Vector2::zeros(), 0.02), (s, 0.3)] {
            let (stands, _) = merge_clear_of(&upper, &lower, h, 6, Some((s, keep))).unwrap();
            assert_eq!(stands.area(), first.area());
        }
    }

    /// The skips of [`least_hull`]: every candidate [`held_near`] skips has a certified hull
    /// that fails the clear test (`lo(s) < r_k`), over random clouds of samples, centres and
    /// sensors near them; and [`least_hull`], which also skips the candidates whose area floor
    /// ([`area_floor`]) exceeds the best area found, returns what the loop over every candidate
    /// returns, to the bit, with and without the clear test. Both outcomes of the first skip
    /// occur, and the floors skip candidates (the checks bite).
    #[test]
    fn a_skipped_candidate_could_not_have_qualified() {
        let mut rng = harmonav_transform::random::Rng::new(11);
        let h = 0.01;
        let (mut skipped, mut built, mut floored) = (0, 0, 0);
        for _ in 0..40 {
            // A few arcs of samples at spacing h about random points.
            let samples: Vec<Vector2<f64>> = (0..rng.below(3) + 1)
                .flat_map(|_| {
                    let (c, r) = (rng.point(1.0), rng.uniform(0.1, 0.6));
                    let (a, span) = (rng.uniform(0.0, TAU), rng.uniform(0.5, TAU));
                    let n = (span * r / h).ceil() as usize;
                    (0..=n)
                        .map(move |k| {
                            let t = a + span * k as f64 / n as f64;
                            c + r * Vector2::new(t.cos(), t.sin())
                        })
                        .collect::<Vec<_>>()
                })
                .collect();
            let candidates: Vec<Vector2<f64>> = (0..6).map(|_| rng.point(1.2)).collect();
            let s = rng.point(1.5);
            let keep = rng.uniform(0.01, 0.3);
            for &p in &candidates {
                if held_near(p, &samples, 0.5 * h, s, keep) {
                    skipped += 1;
                    let (star, _) = certified_hull(p, &samples, h).unwrap();
                    assert!(star.shape().signed_distance_bounds(s).0 < keep);
                } else {
                    built += 1;
                }
            }
            // The loop over every candidate, with and without the clear test.
            for clear in [Some((s, keep)), None] {
                let mut best: Option<(Perceived, Certification)> = None;
                for &p in &candidates {
                    if let Ok(merged) = certified_hull(p, &samples, h) {
                        let clear_of = |(s, keep): (Vector2<f64>, f64)| {
                            merged.0.shape().signed_distance_bounds(s).0 >= keep
                        };
                        let smaller = best.as_ref().is_none_or(|b| merged.0.area() < b.0.area());
                        if smaller && clear.is_none_or(clear_of) {
                            best = Some(merged);
                        }
                    }
                }
                let before = crate::work::work();
                let quick = least_hull(&candidates, &samples, h, clear);
                if clear.is_none() {
                    floored += crate::work::work().since(before).skipped;
                }
                match (best, quick) {
                    (None, None | Some(Err(_))) => {}
                    (Some(a), Some(Ok(b))) => {
                        assert_eq!(a.0.radii(), b.0.radii());
                        assert_eq!(a.0.centre(), b.0.centre());
                        assert_eq!(a.1, b.1);
                    }
                    (a, b) => panic!(
                        "{:?} against {:?}",
                        a.map(|x| x.1),
                        b.map(|x| x.map(|y| y.1))
                    ),
                }
            }
        }
        assert!(
            skipped >= 20 && built >= 20,
            "{skipped} skipped, {built} built"
        );
        assert!(floored >= 40, "{floored} skipped by their area floors");
    }

    /// A hull with a radial jump (a far disc beside a near one): its per-cell cover leaves no
    /// boundary point more than `h/2` from a sample (200 000 points checked, including the
    /// jump's cells), with far fewer samples than the uniform spacing that the largest `|R'|`
    /// would set. With half the samples in each cell some point is farther (the check bites).
    #[test]
    fn a_hulls_cover_is_sampled_per_cell_and_still_covers() {
        let c = Vector2::new(0.0, 0.0);
        let discs = [
            (Vector2::new(0.3, 0.0), 0.1),
            (Vector2::new(-1.2, 0.4), 0.3),
            (Vector2::new(0.0, 2.0), 0.05),
        ];
        let hull = Perceived::hull(c, &discs).unwrap();
        let h = 0.01;
        let cover = hull.boundary_cover(h);
        let uniform = (TAU * hull.r_max().hypot(hull.l1) / h).ceil();
        assert!(
            (cover.len() as f64) < 0.5 * uniform,
            "{} {uniform}",
            cover.len()
        );
        let farthest = |samples: &[Vector2<f64>]| {
            (0..200_000)
                .map(|j| {
                    let p = hull.shape().boundary_point(TAU * j as f64 / 200_000.0);
                    samples
                        .iter()
                        .map(|x| (x - p).norm())
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max)
        };
        assert!(farthest(&cover) <= 0.5 * h, "{}", farthest(&cover));
        let halved: Vec<_> = cover.iter().step_by(2).copied().collect();
        assert!(farthest(&halved) > 0.5 * h);
    }
}
