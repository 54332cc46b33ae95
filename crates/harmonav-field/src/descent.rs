//! Following the normalised descent direction `ẋ = −∇Θ/|∇Θ|` at unit speed with an
//! error-controlled integrator: the convergence study of the navigation function (and the
//! kinematic law's path with `K√(2Θ)` replaced by 1).

use nalgebra::Vector2;

use crate::field::Field;

/// Settings of [`follow`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowOptions {
    /// Arrival: distance to the destination below this.
    pub goal_tolerance: f64,
    /// Give up after this time (= path length at unit speed).
    pub max_time: f64,
    /// Local error tolerance per step (absolute, in length units).
    pub step_tolerance: f64,
    /// Largest step.
    pub max_step: f64,
}

impl Default for FollowOptions {
    fn default() -> Self {
        Self {
            goal_tolerance: 1e-3,
            max_time: 100.0,
            step_tolerance: 1e-6,
            max_step: 0.1,
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
    /// Stopped at a point where the direction is undefined (an exact critical point).
    Stuck,
    /// The step size collapsed (every retry left the free space).
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

/// Integrates `ẋ = −∇Θ/|∇Θ|` from `start` with the Bogacki–Shampine 3(2) pair and step-size
/// control. A step whose stages leave the free space is rejected and retried smaller, so
/// accepted points never leave it; each accepted point is also checked against the true
/// obstacles (`collision_free`).
pub fn follow(field: &Field, start: Vector2<f64>, options: &FollowOptions) -> Descent {
    let goal = field.workspace().destination();
    let dir = |x: Vector2<f64>| field.eval(x).ok().and_then(|e| e.direction);
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
    let Some(mut k1) = dir(x) else {
        let ending = if (x - goal).norm() < options.goal_tolerance {
            Ending::Reached
        } else {
            Ending::Stuck
        };
        return end(ending, t, x, steps, rejected, collision_free);
    };
    while t < options.max_time {
        let dist = (x - goal).norm();
        if dist < options.goal_tolerance {
            return end(Ending::Reached, t, x, steps, rejected, collision_free);
        }
        h = h.min(options.max_step).min(dist);
        if h < 1e-14 {
            return end(Ending::StepCollapsed, t, x, steps, rejected, collision_free);
        }
        let stages = dir(x + 0.5 * h * k1).and_then(|k2| {
            let k3 = dir(x + 0.75 * h * k2)?;
            let next = x + h * (2.0 / 9.0 * k1 + 1.0 / 3.0 * k2 + 4.0 / 9.0 * k3);
            let k4 = if (next - goal).norm() < options.goal_tolerance {
                Some(k3)
            } else {
                dir(next)
            }?;
            let err =
                (h * (-5.0 / 72.0 * k1 + 1.0 / 12.0 * k2 + 1.0 / 9.0 * k3 - 1.0 / 8.0 * k4)).norm();
            Some((next, k4, err))
        });
        match stages {
            Some((next, k4, err)) if err <= options.step_tolerance => {
                x = next;
                k1 = k4;
                t += h;
                steps += 1;
                collision_free &= field.workspace().check_free(x, "trajectory").is_ok()
                    || (x - goal).norm() < options.goal_tolerance;
                h *= (0.9 * (options.step_tolerance / err.max(1e-300)).cbrt()).clamp(0.2, 5.0);
            }
            Some((_, _, err)) => {
                rejected += 1;
                h *= (0.9 * (options.step_tolerance / err).cbrt()).clamp(0.1, 0.9);
            }
            None => {
                rejected += 1;
                h *= 0.25;
            }
        }
    }
    end(Ending::TimedOut, t, x, steps, rejected, collision_free)
}
