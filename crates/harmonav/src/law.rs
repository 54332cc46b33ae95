//! The robot model and its law, as the user gives it to a [`crate::Navigator`].

/// The robot model and its law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Law {
    /// `ẋ = u` under eq. `kinctrl` with the speed of [`crate::Options::speed`]: `u = −s(x)∇Θ/|∇Θ|`,
    /// `s = K√(2Θ)` (`"paper"`) or `min(v_max, √(2a|x − x_d|))` with a linear core at the goal
    /// (`"auto"`, the default; `v_max` from [`crate::Options::v_max`], default `K√2`; `docs/maths.md`
    /// §6); [`crate::Navigator::command`] returns the velocity `u`. On a floor plan the
    /// direction turns towards the shortest path within 60° of `−∇Θ` under the default
    /// [`crate::Options::heading`] (`docs/maths.md` §13.3).
    Kinematic {
        /// `K > 0`.
        gain: f64,
    },
    /// `mẍ = f` under eq. `dynctrllocal`, `f = −μ∇Ψ − λẋ` with the damping of
    /// [`crate::Options::damping`]; [`crate::Navigator::command`] returns the force `f`. On a
    /// floor plan the default [`crate::Options::heading`] adds the gyroscopic force
    /// `m·ω·Jẋ` that turns `ẋ` towards the shortest path and does no work
    /// (`docs/maths.md` §13.4).
    Dynamic {
        /// `m > 0`, kg.
        mass: f64,
        /// `μ > 0`: the speed bound is `√(2μ/m)`.
        mu: f64,
    },
}

impl Law {
    /// The kinematic law with gain `K` (speed at most `v_max`, by default `K√2`).
    pub fn kinematic(gain: f64) -> Self {
        Self::Kinematic { gain }
    }

    /// The dynamic law for mass `m` and gain `μ`.
    pub fn dynamic(mass: f64, mu: f64) -> Self {
        Self::Dynamic { mass, mu }
    }
}
