//! Following the normalised descent direction `ẋ = −∇Θ/|∇Θ|` at unit speed with an
//! error-controlled, L-stable integrator: the convergence study of the navigation function
//! (and the kinematic law's path with `K√(2Θ)` replaced by 1).

use nalgebra::{Matrix2, Vector2};

use crate::field::Field;

/// Stall detection of [`follow`]: over each stretch of this much path (= time at unit speed)
/// the net displacement must exceed [`CHATTER_RATIO`] times it. A descent of Θ cannot turn back
/// on itself, so only chatter about a critical point fails the test: in the stiff outer band a
/// path can be squeezed onto a saddle's stable manifold and lose the direction across the valley
/// floor in rounding next to the saddle (1 in 10⁴ random starts of the 20-obstacle study); it
/// would otherwise chatter there until `max_time`.
pub const CHATTER_PATH: f64 = 0.1;

/// See [`CHATTER_PATH`].
pub const CHATTER_RATIO: f64 = 1e-3;

/// Settings of [`follow`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowOptions {
    /// Arrival: distance to the destination below this.
    pub goal_tolerance: f64,
    /// Give up after this time (= path length at unit speed); the last step ends exactly there.
    pub max_time: f64,
    /// Local error tolerance per step (absolute, in length units).
    pub step_tolerance: f64,
    /// Largest step.
    pub max_step: f64,
    /// Give up (`TimedOut`) after this many step attempts, accepted or rejected: a bound on the
    /// work of one descent whatever the field's stiffness.
    pub max_attempts: usize,
}

impl Default for FollowOptions {
    fn default() -> Self {
        Self {
            goal_tolerance: 1e-3,
            max_time: 100.0,
            step_tolerance: 1e-6,
            max_step: 0.1,
            max_attempts: usize::MAX,
        }
    }
}

/// How a descent ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ending {
    /// Within the goal tolerance.
    Reached,
    /// `max_time` elapsed.
    TimedOut,
    /// Stopped at a critical point: the direction is undefined there, or the path chatters
    /// about it (see [`CHATTER_PATH`]).
    Stuck,
    /// The step size collapsed with every retry leaving the free space.
    StepCollapsed,
}

/// The result of [`follow`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Descent {
    /// How it ended.
    pub ending: Ending,
    /// Time (= path length) at the end.
    pub time: f64,
    /// Final position.
    pub end: Vector2<f64>,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (error too large or a stage outside the free space).
    pub rejected: usize,
    /// Whether every accepted point was in the free space of the *true* obstacles.
    pub collision_free: bool,
}

/// Jacobian of the direction field `f` at `x` by one-sided differences (forward, or backward
/// where the forward point leaves the free space); zero columns where neither is defined. A
/// W-method stays second order with any Jacobian, so this only affects the step sizes.
fn direction_jacobian(
    dir: &impl Fn(Vector2<f64>) -> Option<Vector2<f64>>,
    x: Vector2<f64>,
    f: Vector2<f64>,
) -> Matrix2<f64> {
    let delta = 1e-8 * x.norm().max(1.0);
    let mut jac = Matrix2::zeros();
    for j in 0..2 {
        let e = Vector2::ith(j, delta);
        let column = dir(x + e)
            .map(|fp| (fp - f) / delta)
            .or_else(|| dir(x - e).map(|fm| (f - fm) / delta));
        if let Some(c) = column {
            jac.set_column(j, &c);
        }
    }
    jac
}

/// Integrates `ẋ = f(x) = −∇Θ/|∇Θ|` from `start` with the Rosenbrock W-method 2(3) of
/// Shampine & Reichelt (MATLAB's `ode23s`) and step-size control:
///
/// ```text
/// d = 1/(2 + √2),  W = I − h d J,  J ≈ ∂f/∂x
/// k1 = W⁻¹ f(x),   k2 = W⁻¹(f(x + h k1/2) − k1) + k1,   x' = x + h k2
/// k3 = W⁻¹(f(x') − (6 + √2)(k2 − f(x + h k1/2)) − 2(k1 − f(x))),   err = h|k1 − 2k2 + k3|/6
/// ```
///
/// Why not an explicit pair: the far-field valley of `phi_k` (maths.md §5, pitfall A) lies in
/// the stretched outer band, where the normalised field is stiff (it pulls onto the valley
/// floor over a width of ~1e-4 m while sliding along it); an explicit method is held to steps
/// at its stability limit there (up to 10⁶ steps for one descent), the L-stable W-method is not.
///
/// A step any of whose stages leaves the free space is rejected and retried smaller, so
/// accepted points never leave it; each accepted point is also checked against the true
/// obstacles (`collision_free`).
pub fn follow(field: &Field, start: Vector2<f64>, options: &FollowOptions) -> Descent {
    const D: f64 = 0.292_893_218_813_452_5; // 1/(2 + √2)
    const E32: f64 = 6.0 + std::f64::consts::SQRT_2;
    let goal = field.workspace().destination();
    // Whether the last failed direction was outside the free space (else: a critical point).
    let outside = std::cell::Cell::new(false);
    let dir = |x: Vector2<f64>| match field.eval(x) {
        Ok(e) => e.direction,
        Err(_) => {
            outside.set(true);
            None
        }
    };
    let mut x = start;
    let (mut t, mut h) = (0.0, options.max_step.min(0.01));
    let (mut steps, mut rejected) = (0, 0);
    let mut collision_free = field.workspace().check_free(x, "start").is_ok();
    let end = |ending, t, x, steps, rejected, collision_free| Descent {
        ending,
        time: t,
        end: x,
        steps,
        rejected,
        collision_free,
    };
    let Some(mut f0) = dir(x) else {
        let ending = if (x - goal).norm() < options.goal_tolerance {
            Ending::Reached
        } else {
            Ending::Stuck
        };
        return end(ending, t, x, steps, rejected, collision_free);
    };
    let mut jac = direction_jacobian(&dir, x, f0);
    let mut window = (0.0, x);
    let mut left_free_space = false;
    // Within rounding of max_time counts as there (the last step is clipped to end at it).
    while options.max_time - t > 1e-12 * options.max_time.max(1.0)
        && steps + rejected < options.max_attempts
    {
        if t - window.0 >= CHATTER_PATH {
            if (x - window.1).norm() < CHATTER_RATIO * (t - window.0) {
                return end(Ending::Stuck, t, x, steps, rejected, collision_free);
            }
            window = (t, x);
        }
        let dist = (x - goal).norm();
        if dist < options.goal_tolerance {
            return end(Ending::Reached, t, x, steps, rejected, collision_free);
        }
        h = h.min(options.max_step).min(dist).min(options.max_time - t);
        if h < 1e-14 {
            // Steps failing down to 1e-14 by the error test or at a stage where the direction
            // is undefined: x sits on a critical point. By leaving the free space: the path is
            // pressed against a wall.
            let ending = if left_free_space {
                Ending::StepCollapsed
            } else {
                Ending::Stuck
            };
            return end(ending, t, x, steps, rejected, collision_free);
        }
        // The linearly implicit stages solve with W = I − h d J (closed-form 2×2 inverse); a
        // singular W fails the step, which is retried smaller (where W → I).
        outside.set(false);
        let stages = (|| {
            let w_inv = (Matrix2::identity() - h * D * jac).try_inverse()?;
            let k1 = w_inv * f0;
            let f1 = dir(x + 0.5 * h * k1)?;
            let k2 = w_inv * (f1 - k1) + k1;
            let next = x + h * k2;
            // At the goal the direction is undefined; the step ends there anyway.
            let f2 = if (next - goal).norm() < options.goal_tolerance {
                f1
            } else {
                dir(next)?
            };
            let k3 = w_inv * (f2 - E32 * (k2 - f1) - 2.0 * (k1 - f0));
            let err = (h / 6.0 * (k1 - 2.0 * k2 + k3)).norm();
            Some((next, f2, err))
        })();
        match stages {
            Some((next, f2, err)) if err <= options.step_tolerance => {
                x = next;
                f0 = f2;
                t += h;
                steps += 1;
                collision_free &= field.workspace().check_free(x, "trajectory").is_ok()
                    || (x - goal).norm() < options.goal_tolerance;
                if (x - goal).norm() >= options.goal_tolerance {
                    jac = direction_jacobian(&dir, x, f0);
                }
                h *= (0.9 * (options.step_tolerance / err.max(1e-300)).cbrt()).clamp(0.2, 5.0);
            }
            Some((_, _, err)) => {
                rejected += 1;
                left_free_space = false;
                h *= (0.9 * (options.step_tolerance / err).cbrt()).clamp(0.1, 0.9);
            }
            None => {
                rejected += 1;
                left_free_space = outside.get();
                h *= 0.25;
            }
        }
    }
    end(Ending::TimedOut, t, x, steps, rejected, collision_free)
}
