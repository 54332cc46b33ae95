//! Restarted GMRES with right preconditioning, written as a state machine that asks its caller
//! for each product `A t`, so that the two components of the harmonic map (`u` and `v`, the
//! same matrix, two right-hand sides) can share one pass over the near matrix per iteration
//! (`super::solve`).
//!
//! `A M⁻¹ y = b`, `x = M⁻¹ y`; modified Gram–Schmidt and Givens rotations; a cycle of at most
//! [`RESTART`] iterations ends at `‖b − A x‖₂ ≤ rtol‖b‖₂` (the recursive estimate) or at the
//! restart, then `x += M⁻¹ V y` and the true residual `b − A x` starts the next cycle. The
//! arithmetic is that of one loop calling `A` and `M⁻¹` in turn, operation for operation, so
//! the iterates do not depend on how the caller schedules the products.

/// The Krylov basis kept between restarts.
const RESTART: usize = 60;

/// Most GMRES iterations per right-hand side.
pub(super) const MAX_ITERATIONS: usize = 600;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>()
}

/// What the solver waits for.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Stage {
    /// Nothing asked yet.
    Start,
    /// `output = A·t`, `t = M⁻¹ v_k`: the next Arnoldi step.
    Arnoldi,
    /// `output = A·x` after a cycle's update: the true residual.
    Residual,
    /// Converged, or out of iterations.
    Done,
}

/// One right-hand side's GMRES (module docs). [`Gmres::advance`] runs until it needs a
/// product, then [`Gmres::input`] is the vector to multiply and [`Gmres::output`] takes `A`
/// times it.
pub(super) struct Gmres<'b> {
    b: &'b [f64],
    rtol: f64,
    norm_b: f64,
    x: Vec<f64>,
    r: Vec<f64>,
    /// The product's input when it is `M⁻¹ v_k`.
    t: Vec<f64>,
    /// The product `A·input`, written by the caller.
    w: Vec<f64>,
    v: Vec<Vec<f64>>,
    h: Vec<Vec<f64>>,
    cs: Vec<f64>,
    sn: Vec<f64>,
    g: Vec<f64>,
    k: usize,
    iterations: usize,
    stage: Stage,
    /// The residual estimate `‖r_k‖` when the Arnoldi product was asked for.
    estimate: f64,
}

impl<'b> Gmres<'b> {
    /// The solver of `A x = b` to `‖b − A x‖₂ ≤ rtol‖b‖₂`, from `x = 0`.
    pub(super) fn new(b: &'b [f64], rtol: f64) -> Self {
        let n = b.len();
        Self {
            b,
            rtol,
            norm_b: dot(b, b).sqrt(),
            x: vec![0.0; n],
            r: b.to_vec(),
            t: vec![0.0; n],
            w: vec![0.0; n],
            v: Vec::new(),
            h: Vec::new(),
            cs: Vec::new(),
            sn: Vec::new(),
            g: Vec::new(),
            k: 0,
            iterations: 0,
            stage: Stage::Start,
            estimate: 0.0,
        }
    }

    /// Takes the product written into [`Gmres::output`] (none at the start) and runs to the
    /// next one it needs (`true`) or to the end (`false`). `apply_m` is `z = M⁻¹ r`.
    pub(super) fn advance(&mut self, mut apply_m: impl FnMut(&[f64], &mut [f64])) -> bool {
        match self.stage {
            Stage::Start => {
                if self.norm_b == 0.0 {
                    self.stage = Stage::Done;
                    return false;
                }
                self.begin_cycle(&mut apply_m)
            }
            Stage::Arnoldi => self.arnoldi_step(&mut apply_m),
            Stage::Residual => {
                for ((ri, bi), wi) in self.r.iter_mut().zip(self.b).zip(&self.w) {
                    *ri = bi - wi;
                }
                self.begin_cycle(&mut apply_m)
            }
            Stage::Done => false,
        }
    }

    /// The vector whose product is asked for, and where the product goes.
    pub(super) fn input_output(&mut self) -> (&[f64], &mut [f64]) {
        match self.stage {
            Stage::Residual => (&self.x, &mut self.w),
            _ => (&self.t, &mut self.w),
        }
    }

    /// How much less accurate the product asked for may be than the final residual asks,
    /// `‖b‖/‖r_k‖ ≥ 1` with `‖r_k‖` the residual estimate when an Arnoldi product is asked
    /// for, and 1 for the true residual's product `A x` (module docs, "Relaxation").
    pub(super) fn relaxation(&self) -> f64 {
        match self.stage {
            Stage::Arnoldi if self.estimate > 0.0 => (self.norm_b / self.estimate).max(1.0),
            _ => 1.0,
        }
    }

    /// The solution and the iterations taken (each one product `A M⁻¹ v_k`).
    pub(super) fn finish(self) -> (Vec<f64>, usize) {
        (self.x, self.iterations)
    }

    /// The start of a cycle from the residual `r`: done when it is small enough or the
    /// iterations are spent, else `v_0 = r/β` and its product asked for.
    fn begin_cycle(&mut self, apply_m: &mut impl FnMut(&[f64], &mut [f64])) -> bool {
        let beta = dot(&self.r, &self.r).sqrt();
        if beta <= self.rtol * self.norm_b || self.iterations >= MAX_ITERATIONS {
            self.stage = Stage::Done;
            return false;
        }
        self.v = vec![self.r.iter().map(|ri| ri / beta).collect()];
        self.h = vec![vec![0.0; RESTART]; RESTART + 1];
        self.cs = vec![0.0; RESTART];
        self.sn = vec![0.0; RESTART];
        self.g = vec![0.0; RESTART + 1];
        self.g[0] = beta;
        self.k = 0;
        self.estimate = beta;
        self.ask(apply_m)
    }

    /// Asks for `A M⁻¹ v_k`.
    fn ask(&mut self, apply_m: &mut impl FnMut(&[f64], &mut [f64])) -> bool {
        apply_m(&self.v[self.k], &mut self.t);
        self.iterations += 1;
        self.stage = Stage::Arnoldi;
        true
    }

    /// One Arnoldi step with `w = A M⁻¹ v_k`: orthogonalise, rotate, and ask for the next
    /// product or end the cycle.
    fn arnoldi_step(&mut self, apply_m: &mut impl FnMut(&[f64], &mut [f64])) -> bool {
        let k = self.k;
        let (h, w) = (&mut self.h, &mut self.w);
        for (i, vi) in self.v.iter().enumerate() {
            let hik = dot(w, vi);
            h[i][k] = hik;
            for (wj, vj) in w.iter_mut().zip(vi) {
                *wj -= hik * vj;
            }
        }
        let hn = dot(w, w).sqrt();
        h[k + 1][k] = hn;
        let (cs, sn, g) = (&mut self.cs, &mut self.sn, &mut self.g);
        for i in 0..k {
            let (a, bb) = (h[i][k], h[i + 1][k]);
            h[i][k] = cs[i] * a + sn[i] * bb;
            h[i + 1][k] = -sn[i] * a + cs[i] * bb;
        }
        let (a, bb) = (h[k][k], h[k + 1][k]);
        let d = a.hypot(bb);
        (cs[k], sn[k]) = if d == 0.0 {
            (1.0, 0.0)
        } else {
            (a / d, bb / d)
        };
        h[k][k] = d;
        h[k + 1][k] = 0.0;
        g[k + 1] = -sn[k] * g[k];
        g[k] *= cs[k];
        self.k = k + 1;
        if g[k + 1].abs() <= self.rtol * self.norm_b || hn == 0.0 {
            return self.end_cycle(apply_m);
        }
        self.v.push(w.iter().map(|wi| wi / hn).collect());
        self.estimate = g[k + 1].abs();
        if self.k < RESTART && self.iterations < MAX_ITERATIONS {
            self.ask(apply_m)
        } else {
            self.end_cycle(apply_m)
        }
    }

    /// `y = H⁻¹ g` (upper triangular, `k × k`), `x += M⁻¹ V y`, and the product `A x` asked
    /// for (the true residual).
    fn end_cycle(&mut self, apply_m: &mut impl FnMut(&[f64], &mut [f64])) -> bool {
        let k = self.k;
        let mut y = vec![0.0; k];
        for i in (0..k).rev() {
            let mut s = self.g[i];
            for (hij, yj) in self.h[i][i + 1..k].iter().zip(&y[i + 1..k]) {
                s -= hij * yj;
            }
            y[i] = s / self.h[i][i];
        }
        let mut u = vec![0.0; self.b.len()];
        for (vi, yi) in self.v.iter().zip(&y) {
            for (uj, vj) in u.iter_mut().zip(vi) {
                *uj += yi * vj;
            }
        }
        apply_m(&u, &mut self.t);
        for (xi, ti) in self.x.iter_mut().zip(&self.t) {
            *xi += ti;
        }
        self.stage = Stage::Residual;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A nonsymmetric, diagonally dominant system with a Jacobi preconditioner: the solution
    /// solves it to the tolerance, and a restart is taken (more unknowns than [`RESTART`] and
    /// a slowly converging spectrum); the relaxation grows as the residual falls.
    #[test]
    fn solves_a_nonsymmetric_system_across_restarts() {
        let n = 150;
        let a = |i: usize, j: usize| -> f64 {
            if i == j {
                2.0 + (i as f64 * 0.37).sin()
            } else if j == i + 1 {
                -0.9
            } else if i == j + 1 {
                -0.6
            } else if (i * 7 + j * 3).is_multiple_of(29) {
                0.05
            } else {
                0.0
            }
        };
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.1).cos()).collect();
        let mut solver = Gmres::new(&b, 1e-12);
        let mut products = 0;
        let mut relaxations = Vec::new();
        while solver.advance(|r, z| {
            for (i, (zi, ri)) in z.iter_mut().zip(r).enumerate() {
                *zi = ri / a(i, i);
            }
        }) {
            relaxations.push(solver.relaxation());
            let (x, y) = solver.input_output();
            for (i, yi) in y.iter_mut().enumerate() {
                *yi = (0..n).map(|j| a(i, j) * x[j]).sum();
            }
            products += 1;
        }
        let (x, iterations) = solver.finish();
        assert!(
            iterations > RESTART,
            "{iterations} iterations: no restart tested"
        );
        assert!(
            products > iterations,
            "each cycle's residual is a product too"
        );
        // The first product is unrelaxed, each later one by ‖b‖/‖r_k‖ ≥ 1, and each cycle's
        // true residual (a product of x) unrelaxed.
        assert_eq!(relaxations[0], 1.0);
        assert!(relaxations.iter().all(|&r| r >= 1.0));
        assert!(relaxations.iter().any(|&r| r > 1e6), "{relaxations:?}");
        assert!(relaxations.iter().filter(|&&r| r == 1.0).count() >= 2);
        let residual: f64 = (0..n)
            .map(|i| {
                let ax: f64 = (0..n).map(|j| a(i, j) * x[j]).sum();
                (ax - b[i]).powi(2)
            })
            .sum::<f64>()
            .sqrt();
        let norm_b = dot(&b, &b).sqrt();
        assert!(residual <= 1e-11 * norm_b, "residual {residual:e}");
    }

    /// `b = 0` is solved by `x = 0` without a product.
    #[test]
    fn a_zero_right_hand_side_asks_nothing() {
        let b = vec![0.0; 5];
        let mut solver = Gmres::new(&b, 1e-12);
        assert!(!solver.advance(|_, _| unreachable!()));
        assert_eq!(solver.finish(), (vec![0.0; 5], 0));
    }
}
