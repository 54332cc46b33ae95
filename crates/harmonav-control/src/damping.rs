//! How the dynamic law `f = −μ_p∇Ψ − λẋ` damps, and what it descends (`docs/maths.md` §9);
//! `μ_p` is the pull, `μ` but under [`DampingPolicy::Governed`] (`Dynamic::pull`).

/// The rule that sets the damping `λ ≥ 0` of the dynamic law, and with it the navigation
/// function `Ψ` the law descends. Every policy keeps `λ ≥ 0` and `Ψ` a navigation function with
/// values in `[0, 1]`, so `V = μ_pΨ + ½m|ẋ|²` has `V̇ = −λ|ẋ|² ≤ 0` between discoveries
/// (eq. `totalenergy`): `V < μ_p` and with it no collision hold under each of them, and the
/// speed bound of corollary `boundedvel` (from `V < μ` where `μ_p = μ`, from the governor under
/// [`DampingPolicy::Governed`]). After a discovery that lifts `V` to `μ_p` or above, each applies at least the paper's `(m/d_min)|ẋ(T_n)|`, the
/// damping whose stopping distance is `d_min` (proof of proposition 3, eq. `solpos`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum DampingPolicy {
    /// Eq. `dissipationfun` exactly: `λ_c` (critical at the goal) while `V < μ`, else
    /// `(m/d_min)|ẋ(T_n)|`.
    Paper,
    /// The policy of 2026-11 (the default until the scale-free [`DampingPolicy::Auto`]), three
    /// changes measured on the motion-quality benchmark:
    ///
    /// - the law descends `Ψ = 1 − √(1 − Θ)` instead of `Θ` (`Ψ ≈ Θ/2` at the goal, and a far
    ///   stronger pull where `Θ` saturates near the outer boundary, where the paper's robot
    ///   starts at almost no force);
    /// - `λ(x) = 2√(mμ)·|∇Ψ|/√(2Ψ) = 2√(mμ)·|∇√(2Ψ)|` while `V < μ`, else at least
    ///   `(m/d_min)|ẋ(T_n)|`. It tends to the critical damping at the goal (damping ratio 1)
    ///   and gives the terminal speed `½√(μ/m)·√(2Ψ)`, where `λ_c` over-damps wherever `|∇Ψ|`
    ///   is small;
    /// - a brake `c·λ(x)` on the velocity component that climbs `Ψ` only (`Dynamic::force`),
    ///   so that the robot slides along an obstacle's thin barrier instead of running into it,
    ///   and cannot overshoot the goal.
    ///
    /// Tuned in worlds of radius 5 m; in larger ones `Θ` saturates over most of the world
    /// (`1 − Θ ∝ 1/|x − x_d|²` beyond a few metres) and the robot starts at almost no force.
    Shaped,
    /// The default until 2026-12-03: [`DampingPolicy::Shaped`] on the scale-free `Θ_s = sigma(phi − s)`,
    /// `s = (1 − n/k)·ln(ρ²/ρ_ref²)` (`Dynamic::scale_shift`), instead of `Θ = sigma(phi)`.
    /// `phi_k` of a world scaled by `α` is `phi_k + (1 − n/k)·ln α²`, so `Θ_s` of every scaled
    /// copy of a world is the same function of `x/α`: the law moves through a 50 m world as
    /// through the 5 m one at 10 times the length and time scale, and its speed does not depend
    /// on the size of the world. In worlds of radius `ρ_ref` = 5 m it is `"shaped"`.
    Auto,
    /// A research policy (issue 27, `docs/maths.md` §9, "fast"), not the default: the law
    /// descends `Ψ = w·q/(q + L) + (1 − w)·q/√(q² + L_A²)`, `q = √(r̃² + b²) − b`,
    /// `r̃ = √(2e^{phi}/σ)` (`|x − x_d|` near the goal, in metres): a goal bowl a braking
    /// distance wide and a ramp linear in `q` out to `L_A` = twice the world's radius, with
    /// `"auto"`'s damping `λ(x) = 2√(mμ)|∇√(2Ψ)|` and uphill brake (`Dynamic::potential_for`).
    Fast,
    /// The default: [`DampingPolicy::Auto`]'s `Ψ` and damping with the pull
    /// `μ_p = βμ·max(1, ρ/ρ_ref)`, `β = 4` ([`PULL_GAIN`](crate::PULL_GAIN),
    /// [`Dynamic::pull`](crate::Dynamic::pull); `ρ` the world's radius, `ρ_ref` = 5 m):
    /// `f = −μ_p∇Ψ − (λ(x) + λ_g)ẋ − λ_up(ẋ·n)₊n`, `λ(x) = 2√(mμ_p)|∇√(2Ψ)|`. In a world of
    /// 5 m or less the terminal speed of the damping, `½√(μ_p/m)·√(2Ψ) = √(2μ/m)·√Ψ`, spans
    /// the whole speed bound of corollary `boundedvel` instead of half of it, and the motion is
    /// `"auto"`'s in half the time (the law is exactly time-scaled by `√(μ_p/μ)`); in a larger
    /// one the pull keeps the force of a 5 m world, and the governor holds the speed. The
    /// energy is `V = μ_pΨ + ½m|ẋ|²`, so `V < μ_p` keeps `Ψ < 1` (no collision) but bounds the
    /// speed by `√(2μ_p/m) ≥ 2√(2μ/m)` only; the governor `λ_g = χ(|ẋ|/v_b)·μ_p|∇Ψ|/|ẋ|`,
    /// `v_b = √(2μ/m)`, `χ` rising smoothly from 0 at 0.8 to 1 at 0.9
    /// ([`GOVERNOR_BAND`](crate::GOVERNOR_BAND)), cancels the pull's power at `0.9·v_b`, so the
    /// speed never exceeds `max(|ẋ(0)|, 0.9·v_b) < √(2μ/m)`: the bound of corollary
    /// `boundedvel` for the user's `μ` (`docs/maths.md` §9, part 5). Preconditions, the paper's
    /// with `μ_p` for `μ`: `V(0) < μ_p` for no collision, and `|ẋ(0)| < √(2μ/m)` for the speed
    /// bound (neither implies the other).
    #[default]
    Governed,
}

harmonav_potential::named_policy!(
    DampingPolicy,
    UnknownDampingPolicy,
    "damping policy",
    [
        Paper => "paper",
        Shaped => "shaped",
        Auto => "auto",
        Fast => "fast",
        Governed => "governed"
    ]
);

/// Which branch of the damping is in force.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Branch {
    /// `V < μ_p`: the policy's own damping (`λ_c`, or `λ(x)` under `"auto"`), critical at
    /// the goal.
    Critical,
    /// `V ≥ μ_p` after a discovery: at least `(m/d_min)|ẋ(T_n)|` (eq. `dissipationfun`).
    Switched,
}

/// The damping in force and its branch: the damping force is `−λẋ − λ_up·(ẋ·n)₊·n`,
/// `n = ∇Ψ/|∇Ψ|` (`Dynamic::force`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Damping {
    /// `λ ≥ 0`, kg/s (under [`DampingPolicy::Governed`] with the governor `λ_g` added).
    pub lambda: f64,
    /// `λ_up ≥ 0`, kg/s: the extra damping of the velocity component that climbs `Ψ` (0 under
    /// the paper's policy).
    pub uphill: f64,
    /// Which branch gave it.
    pub branch: Branch,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_rejected() {
        for p in DampingPolicy::ALL {
            assert_eq!(p.as_str().parse::<DampingPolicy>(), Ok(p));
        }
        assert_eq!(DampingPolicy::default(), DampingPolicy::Governed);
        let e = "critical".parse::<DampingPolicy>().unwrap_err();
        assert!(e.to_string().contains("\"critical\""), "{e}");
    }
}
