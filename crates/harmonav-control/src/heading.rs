//! Which way the kinematic law moves: along `−∇Θ`, or along a nominal heading kept within a
//! cone about it (`docs/maths.md` §13.3, "The heading policy").

use nalgebra::Vector2;

/// `α` of [`HeadingPolicy::Auto`], degrees: the half-angle of the cone about `−∇Θ/|∇Θ|`
/// within which the nominal heading is followed. Along the law
/// `dΘ/dt ≤ −s·cos α·|∇Θ|`: at 60°, half the paper's rate. Chosen on the floor-plan suite, an L
/// room and the office of `scenarios/floorplans/limits/` (`docs/maths.md` §13.3: 45°, 60°, 75°
/// and 85° on the suite, 60°, 75° and 80° in the L room; under 75° the office's runs time out).
pub const HEADING_CONE_DEG: f64 = 60.0;

/// The rule that sets the unit direction `d(x)` of the kinematic law `u = s(x)·d(x)`.
///
/// Both keep the kinematic law's safety: `d·(−∇Θ)/|∇Θ| ≥ cos α > 0` away from the critical
/// points, so `Θ` strictly decreases along every motion (no collision, never leaving the
/// workspace: `Θ < 1` stays below its start). Convergence: the continuous law ends at a
/// critical point of `Θ` under both; the goal from almost every start is the paper's theorem
/// under [`HeadingPolicy::Paper`], and under [`HeadingPolicy::Auto`] rests on an assumption
/// stated in `docs/maths.md` §13.3 (and, on a floor plan, the held law can stop on the edge of
/// the certified region under either policy, §13.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum HeadingPolicy {
    /// Eq. `kinctrl`: `d = −∇Θ/|∇Θ|`, the flow lines of `Θ` (the paper's law).
    Paper,
    /// The default: the nominal heading `g(x)` given with the evaluation (on a floor plan the
    /// shortest-path direction, `harmonav_floorplan::Geodesic::heading`), rotated towards
    /// `−∇Θ` until it lies within [`HEADING_CONE_DEG`] of it ([`steer`]); `−∇Θ/|∇Θ|` where
    /// there is no nominal heading (every star world, whose flow lines are already within 2–11 %
    /// of the shortest path at the median, docs/benchmarks.md).
    #[default]
    Auto,
}

harmonav_potential::named_policy!(
    HeadingPolicy,
    UnknownHeadingPolicy,
    "heading policy",
    [Paper => "paper", Auto => "auto"]
);

/// The unit vector closest to `nominal` within the angle `α` (`cos_alpha = cos α`, `α ∈ (0,
/// π/2)`) of the unit descent direction `descent` (both unit vectors; every caller passes
/// them so):
///
/// ```text
///          ⎧ g                          if g·d ≥ cos α
/// steer =  ⎨
///          ⎩ cos α·d + sin α·σ·d⊥       otherwise,   d⊥ = (−d_y, d_x),  σ = sign(d × g)
/// ```
///
/// (`d = descent`, `g = nominal`): the edge of the cone on `g`'s side, exactly at `α` from `d`
/// (`d⊥` is orthogonal to `d` by construction, with no division, so rounding cannot tilt it
/// uphill), hence `steer·d ≥ cos α` to rounding. When `g` lies on `d`'s line (`d × g = 0`, so
/// `g = −d` here, no side to turn to) or is not finite it is `d`.
#[must_use]
pub fn steer(descent: Vector2<f64>, nominal: Vector2<f64>, cos_alpha: f64) -> Vector2<f64> {
    let c = nominal.dot(&descent);
    if c >= cos_alpha {
        return nominal;
    }
    let side = descent.x * nominal.y - descent.y * nominal.x;
    if !(side != 0.0 && side.is_finite()) {
        return descent;
    }
    let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
    let perp = Vector2::new(-descent.y, descent.x);
    cos_alpha * descent + (sin_alpha * side.signum()) * perp
}

/// `τ` of the dynamic law's heading, s: under [`HeadingPolicy::Auto`] the gyroscopic force
/// `f_g = m·ω·J ẋ` turns the velocity towards the steered heading `d` at the rate
/// `ω = χ(Θ)·∠(ẋ, d)/τ` ([`turn_angle`], [`turn_fade`] `χ`; `J` the quarter turn). `f_g ⟂ ẋ`, so it does no work:
/// `V̇ = −λ|ẋ|²` and the speed bound are the paper's (`docs/maths.md` §13.4). Chosen on the
/// floor-plan suite, the office included (§13.4 lists the times at 0.25, 0.5 and 1 s).
pub const TURN_TIME: f64 = 0.5;

/// `Θ₀` of the dynamic law's heading: below `Θ = Θ₀` the turn rate fades as `Θ/Θ₀`
/// ([`turn_fade`]), so that the heading force is `O(Θ|ẋ|) = O(|x − x_d|²|ẋ|)` at the goal: of
/// higher order, the closed loop's linearisation there is the paper's, and with it `λ_c`'s
/// critical damping (corollary `critdamp`).
pub const TURN_FADE: f64 = 0.1;

/// `min(1, Θ/`[`TURN_FADE`]`)` (0 for a non-finite or negative `Θ`).
#[must_use]
pub fn turn_fade(theta: f64) -> f64 {
    if theta > 0.0 {
        (theta / TURN_FADE).min(1.0)
    } else {
        0.0
    }
}

/// The signed angle from `v` to `d` (`atan2(v × d, v·d)`, in `[−π, π]`); 0 when either is zero
/// or not finite, where there is nothing to turn.
#[must_use]
pub fn turn_angle(v: Vector2<f64>, d: Vector2<f64>) -> f64 {
    let a = (v.x * d.y - v.y * d.x).atan2(v.dot(&d));
    if a.is_finite() { a } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_turn_angle_is_signed_and_zero_where_undefined() {
        let v = Vector2::new(2.0, 0.0);
        for deg in [-170.0f64, -90.0, -1.0, 0.0, 30.0, 120.0] {
            let a = deg.to_radians();
            let d = Vector2::new(a.cos(), a.sin());
            assert!((turn_angle(v, d) - a).abs() < 1e-12, "{deg}");
        }
        assert_eq!(turn_angle(Vector2::zeros(), Vector2::new(0.0, 1.0)), 0.0);
        assert_eq!(turn_angle(v, Vector2::new(f64::NAN, 1.0)), 0.0);
    }

    #[test]
    fn names_round_trip_and_unknown_names_are_rejected() {
        for p in HeadingPolicy::ALL {
            assert_eq!(p.as_str().parse::<HeadingPolicy>(), Ok(p));
        }
        assert_eq!(HeadingPolicy::default(), HeadingPolicy::Auto);
        assert!("straight".parse::<HeadingPolicy>().is_err());
    }

    #[test]
    fn the_steered_heading_is_the_nominal_one_inside_the_cone_and_on_its_edge_outside() {
        let cos = HEADING_CONE_DEG.to_radians().cos();
        let d = Vector2::new(1.0, 0.0);
        for deg in [
            -179.0f64, -120.0, -61.0, -59.0, -10.0, 0.0, 30.0, 59.9, 60.1, 90.0, 179.0,
        ] {
            let a = deg.to_radians();
            let g = Vector2::new(a.cos(), a.sin());
            let s = steer(d, g, cos);
            assert!((s.norm() - 1.0).abs() < 1e-12, "{deg}");
            let angle = s.y.atan2(s.x).to_degrees();
            let want = deg.clamp(-HEADING_CONE_DEG, HEADING_CONE_DEG);
            assert!((angle - want).abs() < 1e-9, "{deg}: {angle} against {want}");
        }
        // Exactly opposite: no side to turn to, the descent itself.
        assert_eq!(steer(d, -d, cos), d);
        // Within rounding of opposite, on either side, for any descent: still in the cone.
        for k in 0..2000 {
            let a = 0.001 * f64::from(k);
            let d = Vector2::new(a.cos(), a.sin());
            for eps in [1e-17, -1e-17, 1e-12, -1e-12] {
                let g = -Vector2::new((a + eps).cos(), (a + eps).sin());
                let s = steer(d, g, cos);
                assert!(s.dot(&d) >= cos - 1e-12 && (s.norm() - 1.0).abs() < 1e-12);
            }
        }
        // A nominal heading that is not finite is ignored.
        assert_eq!(steer(d, Vector2::new(f64::NAN, 0.0), cos), d);
    }
}
