//! How fast the kinematic law `u = −s(x)·∇Θ/|∇Θ|` moves along the flow lines of `Θ`
//! (`docs/maths.md` §6, "The speed policy").

/// `T_b` of [`SpeedPolicy::Auto`], s: the time it takes to brake from `v_max` to rest at the
/// goal. The braking distance is `d_b = v_max·T_b/2` and the deceleration `a = v_max/T_b`
/// (2.8 m/s² at the default `v_max = √2` m/s); braking costs `T_b/2` over a run at full speed
/// to the goal.
pub const BRAKING_TIME: f64 = 0.5;

/// `r_0/d_b` of [`SpeedPolicy::Auto`]: within `r_0 = LINEAR_CORE·d_b` of the goal the speed
/// falls linearly, `s = λ_0·r` with `λ_0 = v_max/√(r_0 d_b) = 2/(T_b·√LINEAR_CORE)` (400 s⁻¹),
/// so that the law is Lipschitz at the goal: solutions are unique, and an integrator or a
/// sampled hold converges there as under the paper's law, instead of stepping across the goal
/// and back (the √ profile alone is not Lipschitz at `r = 0`). It costs `ln(r_0/ε)/λ_0` to
/// arrive within `ε < r_0` (26 ms to 1e-9 m at the default `v_max`; `r_0` = 35 µm there).
pub const LINEAR_CORE: f64 = 1e-4;

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
    /// The default: full speed, then braking at a constant deceleration, then a linear core,
    /// with `r = |x − x_d|`,
    ///
    /// ```text
    ///         ⎧ v_max              r ≥ d_b        a = v_max/T_b,  d_b = v_max·T_b/2
    /// s(r) =  ⎨ v_max·√(r/d_b)     r_0 ≤ r < d_b  (T_b = BRAKING_TIME)
    ///         ⎩ v_max·r/√(r_0 d_b) r < r_0        r_0 = LINEAR_CORE·d_b
    /// ```
    ///
    /// Continuous and increasing in `r`, Lipschitz. On a straight approach `ṡ = −a` in the
    /// braking zone: the robot comes within `r_0` of the goal in at most `(D + d_b)/v_max` from
    /// `D`, and within any `ε < r_0` after `ln(r_0/ε)/λ_0` more ([`LINEAR_CORE`];
    /// `docs/maths.md` §6).
    #[default]
    Auto,
}

harmonav_potential::named_policy!(
    SpeedPolicy,
    UnknownSpeedPolicy,
    "speed policy",
    [Paper => "paper", Auto => "auto"]
);

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
