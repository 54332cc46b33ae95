//! How fast the kinematic law `u = −s(x)·∇Θ/|∇Θ|` moves along the flow lines of `Θ`
//! (`docs/maths.md` §6, "The speed policy").

/// `T_b` of [`SpeedPolicy::Auto`], s: the time it takes to brake from `v_max` to rest at the
/// goal. The braking distance is `d_b = v_max·T_b/2` and the deceleration `a = v_max/T_b`
/// (2.8 m/s² at the default `v_max = √2` m/s); braking costs `T_b/2` over a run at full speed
/// to the goal.
pub const BRAKING_TIME: f64 = 0.5;

/// The rule that sets the speed `s(x) > 0` of the kinematic law `u = −s(x)·∇Θ/|∇Θ|`
/// (eq. `kinctrl` is `s = K√(2Θ)`). Every positive `s` follows the flow lines of `−∇Θ`, so
/// each policy keeps the guarantees of the kinematic law: `dΘ/dt = −s|∇Θ| < 0` away from the
/// critical points, hence `Θ < 1` (no collision) and convergence to the goal from almost every
/// start. Each policy's speed is at most `v_max` and vanishes only at the goal.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum SpeedPolicy {
    /// Eq. `kinctrl`: `s = min(v_max, K√(2Θ))` (`= K√(2Θ)` with the default `v_max = K√2`).
    /// Near the goal `Θ ≈ ½σ|x − x_d|²`, so the speed falls in proportion to the distance and
    /// the goal is reached only asymptotically (exponentially).
    Paper,
    /// The default: full speed, then braking at a constant deceleration,
    ///
    /// ```text
    /// s(x) = min(v_max, √(2a·|x − x_d|)) = v_max·min(1, √(|x − x_d|/d_b)),
    /// a = v_max/T_b,  d_b = v_max²/(2a) = v_max·T_b/2   (T_b = BRAKING_TIME)
    /// ```
    ///
    /// On a straight approach `ṡ = −a`: the robot stops at the goal in the finite time
    /// `T_b = 2d_b/v_max` from `d_b`, with a bounded deceleration (`docs/maths.md` §6).
    #[default]
    Auto,
}

impl SpeedPolicy {
    /// Every policy, for reports and sweeps.
    pub const ALL: [SpeedPolicy; 2] = [SpeedPolicy::Paper, SpeedPolicy::Auto];

    /// The name used in scenario files, the CLI and JSON (`"paper"`, `"auto"`).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::Auto => "auto",
        }
    }
}

impl std::fmt::Display for SpeedPolicy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A name that is not a [`SpeedPolicy`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownSpeedPolicy(pub String);

impl std::fmt::Display for UnknownSpeedPolicy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "unknown speed policy \"{}\": expected \"paper\" or \"auto\"",
            self.0
        )
    }
}

impl std::error::Error for UnknownSpeedPolicy {}

impl std::str::FromStr for SpeedPolicy {
    type Err = UnknownSpeedPolicy;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|p| p.as_str() == s)
            .ok_or_else(|| UnknownSpeedPolicy(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_rejected() {
        for p in SpeedPolicy::ALL {
            assert_eq!(p.as_str().parse::<SpeedPolicy>(), Ok(p));
            assert_eq!(p.to_string(), p.as_str());
        }
        assert_eq!(SpeedPolicy::default(), SpeedPolicy::Auto);
        let e = "fast".parse::<SpeedPolicy>().unwrap_err();
        assert!(e.to_string().contains("\"fast\""), "{e}");
    }
}
