//! Guarantee checks of `harmonav-transform` (issue: navigation transformations), so far the
//! radial maps `Phi` is built from.

use harmonav_potential::checks::fd_jacobian;
use harmonav_transform::radial::{obstacle_map, outer_map};
use nalgebra::Vector2;

use super::{Check, Outcome, outcome};
use crate::rng::Rng;

pub fn checks() -> Vec<Check> {
    vec![Check::new(
        "transform.radial-maps-are-diffeomorphisms",
        radial_maps,
    )]
}

/// Dense samples of both radial maps on random star boundaries `R(θ) = r0 + a cos(nθ + φ)`,
/// including points 1e-9 (relative) from the boundary: `det J > 0`, `ν_ρ ≥ 1`, the obstacle
/// boundary collapses to the centre, and `J` agrees with central differences of `Phi`.
fn radial_maps() -> Outcome {
    let mut rng = Rng::new(11);
    let (mut min_det, mut worst_fd, mut samples) = (f64::INFINITY, 0.0f64, 0usize);
    for _ in 0..200 {
        let (r0, n, phase) = (
            rng.uniform(0.2, 2.0),
            rng.uniform(1.0, 6.0).floor(),
            rng.uniform(0.0, 6.3),
        );
        let a = rng.uniform(0.0, 0.6) * r0;
        let eps = rng.uniform(0.05, 1.0);
        let (big, gain) = (rng.uniform(3.0, 8.0), rng.uniform(0.1, 50.0));
        let shape = move |th: f64| {
            (
                r0 + a * (n * th + phase).cos(),
                -a * n * (n * th + phase).sin(),
            )
        };
        let outer = move |th: f64| {
            (
                big + 0.1 * big * (n * th).cos(),
                -0.1 * big * n * (n * th).sin(),
            )
        };
        let boundary = |which: usize, th: f64| if which == 0 { shape(th) } else { outer(th) };
        let radial = |which: usize, rho: f64, r: f64, dr: f64| {
            if which == 0 {
                obstacle_map(rho, r, dr, eps)
            } else {
                outer_map(rho, r, dr, eps, gain)
            }
        };
        for i in 0..500 {
            let th = rng.uniform(-3.1, 3.1);
            let t = if i % 10 == 0 {
                1e-9
            } else {
                rng.uniform(0.0, 1.0)
            };
            for which in [0, 1] {
                let (r, dr) = boundary(which, th);
                let rho = if which == 0 { r + t * eps } else { r - t * eps };
                let m = radial(which, rho, r, dr);
                if which == 0 && obstacle_map(r, r, dr, eps).nu != 0.0 {
                    return Err(format!("boundary point at θ = {th} not collapsed"));
                }
                let det = m.det(rho);
                if !(det > 0.0 && m.nu_rho >= 1.0 - 1e-12) {
                    return Err(format!(
                        "det J = {det}, ν_ρ = {} at θ = {th}, t = {t}",
                        m.nu_rho
                    ));
                }
                min_det = min_det.min(det);
                samples += 1;
                if t > 1e-3 && t < 0.9 {
                    let x = rho * Vector2::new(th.cos(), th.sin());
                    let phi = |y: Vector2<f64>| {
                        let (r, dr) = boundary(which, y.y.atan2(y.x));
                        radial(which, y.norm(), r, dr).nu * y / y.norm()
                    };
                    let fd = fd_jacobian(phi, x, 1e-7);
                    let j = m.jacobian(x / rho, rho);
                    let err = (j.column(0) - fd.column(0))
                        .norm()
                        .max((j.column(1) - fd.column(1)).norm())
                        / j.norm().max(1.0);
                    worst_fd = worst_fd.max(err);
                }
            }
        }
    }
    outcome(
        worst_fd < 1e-5,
        format!(
            "{samples} samples (10 % at 1e-9 from a boundary): min det J {min_det:.1e} > 0, worst relative J − FD {worst_fd:.1e}"
        ),
    )
}
