//! One control period of the held-command loops, either base (the star world's `crate::held`,
//! the floor plan's `crate::floor`, the golden traces): the step a user's loop takes.

use harmonav::{Controller, unicycle_arc};
use nalgebra::Vector2;

/// The held step of `controller` over `h` from `(x, v)` under `command`.
pub(crate) fn held(
    controller: &Controller,
    h: f64,
    x: Vector2<f64>,
    v: Vector2<f64>,
    command: Vector2<f64>,
) -> (Vector2<f64>, Vector2<f64>) {
    match controller {
        Controller::Kinematic(_) => (x + h * command, command),
        Controller::Dynamic(law) => {
            let v = v + h * command / law.mass();
            (x + h * v, v)
        }
    }
}

/// `(v, ω)` held for `h` from the pose `(x, yaw)`: the position and heading at the arc's end
/// ([`unicycle_arc`]) and the velocity there, `v·e(θ)`.
pub(crate) fn arc_step(
    x: Vector2<f64>,
    yaw: f64,
    v: f64,
    omega: f64,
    h: f64,
) -> (Vector2<f64>, f64, Vector2<f64>) {
    let (x1, yaw1) = unicycle_arc(x, yaw, v, omega, h);
    (x1, yaw1, v * Vector2::new(yaw1.cos(), yaw1.sin()))
}
