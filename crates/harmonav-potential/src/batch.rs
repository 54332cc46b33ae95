//! Batched eq. (`gradient`): `∇phi_k` for `N` query points against `M` obstacle points.
//!
//! Structure of arrays (`hx`, `hy` in; `gx`, `gy` out). Query points are processed in chunks
//! of [`CHUNK`]: for each obstacle point the inner loop runs over the chunk with no branches
//! and no bounds checks, so the compiler vectorises it (one division per obstacle–point pair,
//! which is the throughput limit). No `unsafe`, no intrinsics.
//!
//! Domain: every distance `|h − P|` in `[1e-150, 1e150]`, where `|v|²` is a normal `f64`
//! (no per-pair guards, unlike [`crate::PointWorld::grad_phi_k`]). A query point at `P_d` or
//! at an obstacle point, or a non-finite one, is reported as
//! [`PotentialError::SingularQuery`] — never returned as NaN.

use nalgebra::Vector2;

use crate::error::PotentialError;
use crate::world::{PRODUCT_BLOCK, PointWorld, split};

/// Number of query points per chunk: the accumulators (2 × 64 f64 = 1 KiB) stay in L1.
pub const CHUNK: usize = 64;

/// The obstacle points of a [`PointWorld`] laid out for the batched gradient.
#[derive(Clone, Debug)]
pub struct BatchGradient {
    px: Vec<f64>,
    py: Vec<f64>,
    dx: f64,
    dy: f64,
    two_over_k: f64,
}

impl BatchGradient {
    /// Copies the points of `world` into structure-of-arrays form.
    pub fn new(world: &PointWorld) -> Self {
        Self {
            px: world.obstacles().iter().map(|p| p.x).collect(),
            py: world.obstacles().iter().map(|p| p.y).collect(),
            dx: world.destination().x,
            dy: world.destination().y,
            two_over_k: 2.0 / world.k(),
        }
    }

    /// Eq. (`gradient`) for every query point: `(gx[n], gy[n]) = ∇phi_k(hx[n], hy[n])`.
    ///
    /// Errors: [`PotentialError::LengthMismatch`] if the four slices differ in length (nothing
    /// is written); [`PotentialError::SingularQuery`] naming the first query point whose
    /// gradient is not finite (the destination, an obstacle point, or outside the domain in
    /// the module docs); the outputs of the other points are still written.
    pub fn eval(
        &self,
        hx: &[f64],
        hy: &[f64],
        gx: &mut [f64],
        gy: &mut [f64],
    ) -> Result<(), PotentialError> {
        let n = hx.len();
        if hy.len() != n || gx.len() != n || gy.len() != n {
            return Err(PotentialError::LengthMismatch {
                lengths: [n, hy.len(), gx.len(), gy.len()],
            });
        }
        let mut first_bad = None;
        let chunks = hx
            .chunks(CHUNK)
            .zip(hy.chunks(CHUNK))
            .zip(gx.chunks_mut(CHUNK).zip(gy.chunks_mut(CHUNK)));
        for (c, ((hx, hy), (gx, gy))) in chunks.enumerate() {
            if hx.len() == CHUNK {
                // Fixed-length arrays let the compiler drop bounds checks and unroll.
                let hx: &[f64; CHUNK] = hx.try_into().expect("full chunk");
                let hy: &[f64; CHUNK] = hy.try_into().expect("full chunk");
                let gx: &mut [f64; CHUNK] = gx.try_into().expect("full chunk");
                let gy: &mut [f64; CHUNK] = gy.try_into().expect("full chunk");
                self.chunk(hx, hy, gx, gy);
            } else {
                self.chunk(hx, hy, gx, gy);
            }
            // Guard: 0/0 at a singular query point gives NaN; report it instead of returning it.
            if first_bad.is_none() {
                let ok = gx.iter().chain(gy.iter()).all(|g| g.is_finite());
                if !ok {
                    let i = (0..gx.len())
                        .find(|&i| !(gx[i].is_finite() && gy[i].is_finite()))
                        .expect("a non-finite entry exists");
                    first_bad = Some(c * CHUNK + i);
                }
            }
        }
        match first_bad {
            Some(index) => Err(PotentialError::SingularQuery { index }),
            None => Ok(()),
        }
    }

    #[inline(always)]
    fn chunk<H, G>(&self, hx: &H, hy: &H, gx: &mut G, gy: &mut G)
    where
        H: AsRef<[f64]> + ?Sized,
        G: AsMut<[f64]> + ?Sized,
    {
        let (hx, hy) = (hx.as_ref(), hy.as_ref());
        let (gx, gy) = (gx.as_mut(), gy.as_mut());
        let mut ax = [0.0f64; CHUNK];
        let mut ay = [0.0f64; CHUNK];
        let len = hx.len();
        let (ax, ay) = (&mut ax[..len], &mut ay[..len]);
        for (&px, &py) in self.px.iter().zip(&self.py) {
            for (((ax, ay), &x), &y) in ax.iter_mut().zip(ay.iter_mut()).zip(hx).zip(hy) {
                let dx = x - px;
                let dy = y - py;
                let inv = 1.0 / (dx * dx + dy * dy);
                *ax += dx * inv;
                *ay += dy * inv;
            }
        }
        let k2 = self.two_over_k;
        for (((((gx, gy), &x), &y), &ax), &ay) in gx
            .iter_mut()
            .zip(gy.iter_mut())
            .zip(hx)
            .zip(hy)
            .zip(ax.iter())
            .zip(ay.iter())
        {
            let dx = x - self.dx;
            let dy = y - self.dy;
            let inv = 2.0 / (dx * dx + dy * dy);
            *gx = dx * inv - k2 * ax;
            *gy = dy * inv - k2 * ay;
        }
    }
}

impl PointWorld {
    /// [`PointWorld::phi_and_grad`] (without an exact offset) at many points: `out[n]` is
    /// `Some((phi_k, ∇phi_k))` at `hs[n]` where the fast path (one logarithm per 512 factors) applies, bit for
    /// bit what `phi_and_grad(hs[n], None)` returns, and `None` where it does not (a factor
    /// `|h − P_i|²` that is not a normal `f64`, `h` at or extremely near `P_d`, or a non-finite `h`):
    /// the caller then takes the guarded scalar path for that point.
    ///
    /// Points are processed in chunks of [`CHUNK`] in structure-of-arrays form with the
    /// obstacle loop outside, so the compiler vectorises across points (the scalar path is
    /// latency-bound on its running product). No allocation. A world with a far field
    /// ([`PointWorld::has_far_field`]) takes [`PointWorld::phi_and_grad`] point by point.
    ///
    /// Errors: [`PotentialError::LengthMismatch`] if `out` is not as long as `hs` (nothing is
    /// written).
    pub fn phi_and_grad_many(
        &self,
        hs: &[Vector2<f64>],
        out: &mut [Option<(f64, Vector2<f64>)>],
    ) -> Result<(), PotentialError> {
        if hs.len() != out.len() {
            return Err(PotentialError::LengthMismatch {
                lengths: [hs.len(), hs.len(), out.len(), out.len()],
            });
        }
        if self.has_far_field() {
            // A large world: each point through the multipole path, the same numbers as
            // `phi_and_grad` (the kernel below would be `O(M)` a point);
            // `None` where that path would not apply (the guard, a non-finite h), as below.
            for (h, o) in hs.iter().zip(out.iter_mut()) {
                *o = match self
                    .far_field()
                    .map(|far| self.phi_and_grad_far(far, *h, None))
                {
                    Some(crate::world::FarPath::Value(v)) => Some(v),
                    _ => None,
                };
            }
            return Ok(());
        }
        let (k, k2) = (self.k(), 2.0 / self.k());
        let d = self.destination();
        for (hs, out) in hs.chunks(CHUNK).zip(out.chunks_mut(CHUNK)) {
            let len = hs.len();
            let mut hx = [0.0f64; CHUNK];
            let mut hy = [0.0f64; CHUNK];
            for (i, h) in hs.iter().enumerate() {
                hx[i] = h.x;
                hy[i] = h.y;
            }
            let mut gx = [0.0f64; CHUNK];
            let mut gy = [0.0f64; CHUNK];
            let mut ln_prod = [0.0f64; CHUNK];
            let mut exponent = [0i64; CHUNK];
            let mut lo = [f64::INFINITY; CHUNK];
            let mut hi = [0.0f64; CHUNK];
            // The blocks, the split and the order of the sums are those of `phi_and_grad`.
            for block in self.obstacles().chunks(PRODUCT_BLOCK) {
                let mut prod = [1.0f64; CHUNK];
                for p in block {
                    for i in 0..CHUNK {
                        let (vx, vy) = (hx[i] - p.x, hy[i] - p.y);
                        let r2 = vx * vx + vy * vy;
                        let inv = 1.0 / r2;
                        gx[i] += vx * inv;
                        gy[i] += vy * inv;
                        let (m, e) = split(r2);
                        prod[i] *= m;
                        exponent[i] += e;
                        lo[i] = lo[i].min(r2);
                        hi[i] = hi[i].max(r2);
                    }
                }
                for i in 0..len {
                    ln_prod[i] += prod[i].ln();
                }
            }
            for i in 0..len {
                let (vx, vy) = (hx[i] - d.x, hy[i] - d.y);
                let rd2 = vx * vx + vy * vy;
                // The guard of `phi_and_grad`: every factor and |h − P_d|² normal.
                let normal = lo[i] >= f64::MIN_POSITIVE && hi[i] <= f64::MAX;
                out[i] = (normal && rd2.is_normal()).then(|| {
                    let ln_sum = ln_prod[i] + exponent[i] as f64 * std::f64::consts::LN_2;
                    let phi = rd2.ln() - ln_sum / k;
                    let g = Vector2::new(2.0 * vx / rd2 - k2 * gx[i], 2.0 * vy / rd2 - k2 * gy[i]);
                    (phi, g)
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world() -> PointWorld {
        let pts: Vec<_> = (0..7)
            .map(|i| {
                let a = i as f64 * 0.9;
                Vector2::new(3.0 * a.cos(), 2.0 * a.sin())
            })
            .collect();
        PointWorld::new(Vector2::new(0.2, -0.1), pts).unwrap()
    }

    #[test]
    fn agrees_with_the_scalar_gradient_including_the_tail_chunk() {
        let w = world();
        let b = BatchGradient::new(&w);
        let n = 2 * CHUNK + 13;
        let hx: Vec<f64> = (0..n)
            .map(|i| -4.0 + 8.0 * (i as f64 + 0.5) / n as f64)
            .collect();
        let hy: Vec<f64> = (0..n).map(|i| 1.7 * ((i as f64) * 0.37).sin()).collect();
        let (mut gx, mut gy) = (vec![0.0; n], vec![0.0; n]);
        b.eval(&hx, &hy, &mut gx, &mut gy).unwrap();
        for i in 0..n {
            let g = w.grad_phi_k(Vector2::new(hx[i], hy[i])).unwrap();
            let err = ((gx[i] - g.x).powi(2) + (gy[i] - g.y).powi(2)).sqrt();
            assert!(err <= 1e-12 * g.norm().max(1.0), "point {i}: {err}");
        }
    }

    #[test]
    fn many_points_equal_the_scalar_fast_path_bit_for_bit() {
        let w = world();
        let n = 3 * CHUNK + 7;
        let mut hs: Vec<Vector2<f64>> = (0..n)
            .map(|i| {
                Vector2::new(
                    -4.0 + 8.0 * (i as f64 + 0.5) / n as f64,
                    1.7 * (i as f64 * 0.37).sin(),
                )
            })
            .collect();
        // Singular and extreme points take the guarded path: None here.
        hs[5] = w.destination();
        hs[CHUNK + 1] = w.obstacles()[2];
        hs[2 * CHUNK] = Vector2::new(1e200, 0.0);
        hs[2 * CHUNK + 3] = Vector2::new(f64::NAN, 0.0);
        let mut out = vec![None; n];
        w.phi_and_grad_many(&hs, &mut out).unwrap();
        for (i, (h, o)) in hs.iter().zip(&out).enumerate() {
            if [5, CHUNK + 1, 2 * CHUNK, 2 * CHUNK + 3].contains(&i) {
                assert_eq!(*o, None, "point {i}");
            } else {
                let (phi, g) = o.expect("fast path");
                assert_eq!((phi, g), w.phi_and_grad(*h, None).unwrap(), "point {i}");
            }
        }
        let mut short = vec![None; n - 1];
        assert!(matches!(
            w.phi_and_grad_many(&hs, &mut short),
            Err(PotentialError::LengthMismatch { .. })
        ));
    }

    #[test]
    fn singular_query_and_length_mismatch_are_reported() {
        let w = world();
        let b = BatchGradient::new(&w);
        let p = w.obstacles()[3];
        let mut hx = vec![0.5; CHUNK + 5];
        let mut hy = vec![0.5; CHUNK + 5];
        hx[CHUNK + 2] = p.x;
        hy[CHUNK + 2] = p.y;
        let (mut gx, mut gy) = (vec![0.0; CHUNK + 5], vec![0.0; CHUNK + 5]);
        assert_eq!(
            b.eval(&hx, &hy, &mut gx, &mut gy),
            Err(PotentialError::SingularQuery { index: CHUNK + 2 })
        );
        assert!(gx[0].is_finite() && gx[CHUNK + 4].is_finite());
        assert!(matches!(
            b.eval(&hx, &hy[1..], &mut gx, &mut gy),
            Err(PotentialError::LengthMismatch { .. })
        ));
    }
}
