//! Central differences: the step and the gradient and Jacobian they give. The numerical
//! derivative of a field where no closed form is at hand (the census's Newton steps,
//! `harmonav_field::census`), and the independent reference the checks (`crate::checks`,
//! feature `checks`) measure the analytic derivatives against.

use nalgebra::{Matrix2, Vector2};

/// Step of the central differences below: `≈ ε^{1/3}` for `O(1)` coordinates, where the
/// truncation error `O(step²)` and the rounding error `O(ε/step)` balance.
pub const FD_STEP: f64 = 1e-6;

/// Central-difference gradient of `f` at `x`: `(f(x + s e_i) − f(x − s e_i)) / 2s`.
pub fn fd_gradient(f: impl Fn(Vector2<f64>) -> f64, x: Vector2<f64>, step: f64) -> Vector2<f64> {
    let (ex, ey) = (Vector2::new(step, 0.0), Vector2::new(0.0, step));
    Vector2::new(
        (f(x + ex) - f(x - ex)) / (2.0 * step),
        (f(x + ey) - f(x - ey)) / (2.0 * step),
    )
}

/// Central-difference Jacobian of `f` at `x` (column `i` is `∂f/∂x_i`).
pub fn fd_jacobian(
    f: impl Fn(Vector2<f64>) -> Vector2<f64>,
    x: Vector2<f64>,
    step: f64,
) -> Matrix2<f64> {
    let (ex, ey) = (Vector2::new(step, 0.0), Vector2::new(0.0, step));
    Matrix2::from_columns(&[
        (f(x + ex) - f(x - ex)) / (2.0 * step),
        (f(x + ey) - f(x - ey)) / (2.0 * step),
    ])
}
