//! The navigator's settings ([`Options`]), their valid ranges, and how a command is made safe
//! to hold for the user's control period ([`HoldPolicy`]).

use harmonav_control::{DampingPolicy, HeadingPolicy, SpeedPolicy};
use harmonav_field::KPolicy;
use harmonav_sensing::Sector;
use harmonav_transform::{MAX_LENGTH, StarShape};
use nalgebra::Vector2;

use crate::base::Base;
use crate::error::NavError;
pub(crate) use crate::error::in_range;
use crate::law::Law;
use crate::ranges::MIN_APERTURE_DEG;
use crate::scanning::{FIT_BEYOND_DEPTH, FIT_SCANS_AHEAD, ScanOptions};

/// The control period assumed for [`Law::Kinematic`] when none is given: 100 Hz, s.
pub const DEFAULT_KINEMATIC_PERIOD: f64 = 0.01;

/// The control period assumed for [`Law::Dynamic`] when none is given: 1 kHz, s.
pub const DEFAULT_DYNAMIC_PERIOD: f64 = 0.001;

/// How [`crate::Navigator::command`] turns the continuous law into a command that the robot
/// holds for the control period `h` (a sampled-data loop, `docs/maths.md` §10).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum HoldPolicy {
    /// The continuous law evaluated at the sampled state, as the paper states it. Safe only for
    /// a small enough `h`: at 100 Hz the kinematic robot stepped into obstacles whose barrier
    /// was thinner than one step (`docs/maths.md` §10).
    Paper,
    /// The default: every command is safe when held for `h`, by construction.
    ///
    /// - Kinematic (`x⁺ = x + h·u`): the step `h|u|` is at most half the certified distance
    ///   `d(x)` to the nearest known grown shape or the shrunk boundary, and shortened further
    ///   until `phi_k∘Phi` (so `Θ`) strictly decreases over it.
    /// - Dynamic (semi-implicit Euler `v⁺ = v + h f/m`, `x⁺ = x + h v⁺`, or the exact hold of
    ///   `f`): the damping is applied implicitly (`v⁺ = (I + hΛ/m)⁻¹(v − hμ∇Ψ/m)`, stable for
    ///   every `h`), and `|v⁺| ≤ d(x)/(4h)` and `|v⁺| < √(2μ/m)`.
    #[default]
    Auto,
}

harmonav_potential::named_policy!(
    HoldPolicy,
    UnknownHoldPolicy,
    "hold policy",
    [Paper => "paper", Auto => "auto"]
);

/// The navigator's settings, all with defaults (`Options::default()`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Robot disc radius, m (default 0: a point robot). Obstacles are grown and the boundary
    /// shrunk by `radius + margin`.
    pub radius: f64,
    /// Clearance kept to the true shapes, m (default 0). A robot found inside this band (after
    /// a disturbance or a late perception) is steered back out
    /// ([`crate::Mode::Recovering`]).
    pub margin: f64,
    /// Sensor range `r`, m (default 1, the paper's).
    pub sensor_range: f64,
    /// Sensor aperture `θ`, degrees, in `[MIN_APERTURE_DEG, 360]` (default 60, the paper's).
    pub sensor_aperture_deg: f64,
    /// A-priori lower bound on the obstacles' curvature radius, m, for `d_min` (eq. `dmin`;
    /// default 0.05, the paper's). Also the prior (A2) of [`crate::Navigator::observe_scan`]'s
    /// fits (the sagitta between beams).
    pub rho_min: f64,
    /// The priors and parameters of [`crate::Navigator::observe_scan`] (noise bound, depth
    /// prior, growth threshold; [`ScanOptions`]).
    pub scan: ScanOptions,
    /// How `k` follows the number of known obstacles (default `"auto"`).
    pub k: KPolicy,
    /// The dynamic law's damping (default `"governed"`).
    pub damping: DampingPolicy,
    /// The kinematic law's speed policy (default `"auto"`: `min(v_max, √(2a|x − x_d|))`,
    /// `docs/maths.md` §6).
    pub speed: SpeedPolicy,
    /// The kinematic law's top speed `v_max`, m/s; `None` (the default) means `K√2`, the paper
    /// law's top speed.
    pub v_max: Option<f64>,
    /// Both laws' heading policy (default `"auto"`: on a floor plan the shortest path's
    /// direction within 60° of `−∇Θ`, followed by the kinematic law and turned towards by the
    /// dynamic law's gyroscopic force; `docs/maths.md` §13.3–13.4).
    pub heading: HeadingPolicy,
    /// The period `h` for which the robot holds each command, s; `None` (the default) means
    /// [`DEFAULT_KINEMATIC_PERIOD`] (100 Hz) or [`DEFAULT_DYNAMIC_PERIOD`] (1 kHz) by law.
    pub control_period: Option<f64>,
    /// How a command is made safe to hold for `control_period` (default `"auto"`).
    pub hold: HoldPolicy,
    /// The robot's base (default [`Base::Holonomic`]: [`crate::Navigator::command`]); a
    /// differential-drive base ([`Base::Diff`]) is commanded by
    /// [`crate::Navigator::command_pose`] (docs/unicycle.md).
    pub base: Base,
    /// The dynamic law's force bound `F`, N: every force commanded has `|f| ≤ F`, and every
    /// certified one leaves the robot a way to brake to rest at `a = F/m` within the known free
    /// space and out of every mover's reach (passive safety, docs/movers.md §2), but a way out
    /// of the margin band ([`crate::Mode::Recovering`]: inside a grown shape nothing is
    /// certified against it; it leads out). `None` (the default): no bound, the hold may stop
    /// the robot within one period. Refused with the kinematic law, which commands velocities.
    pub force_bound: Option<f64>,
    /// Comfort distance `c`, m (default 0: none): the nominal command keeps `c` more than the
    /// margin from every non-cooperative mover when it can (docs/movers.md §7, "Comfort"). It
    /// turns the nominal only; the mover filter certifies the result, so every guarantee is
    /// unchanged. In `[0, MAX_LENGTH]`.
    pub comfort: f64,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            radius: 0.0,
            margin: 0.0,
            sensor_range: 1.0,
            sensor_aperture_deg: 60.0,
            rho_min: 0.05,
            scan: ScanOptions::default(),
            k: KPolicy::default(),
            damping: DampingPolicy::default(),
            speed: SpeedPolicy::default(),
            v_max: None,
            heading: HeadingPolicy::default(),
            control_period: None,
            hold: HoldPolicy::default(),
            base: Base::default(),
            force_bound: None,
            comfort: 0.0,
        }
    }
}

impl Options {
    /// The sensor: range `r` (m) and aperture (degrees). It sets `d_min` (eq. `dmin`), the
    /// distance within which the dynamic law must be able to stop after a discovery.
    #[must_use]
    pub fn with_sensor(self, range: f64, aperture_deg: f64) -> Self {
        Self {
            sensor_range: range,
            sensor_aperture_deg: aperture_deg,
            ..self
        }
    }

    /// `radius + margin`, m: what every known shape is grown by (and the boundary shrunk by).
    #[must_use]
    pub fn inflation(&self) -> f64 {
        self.radius + self.margin
    }

    /// The robot's radius and the clearance margin, m.
    #[must_use]
    pub fn with_robot(self, radius: f64, margin: f64) -> Self {
        Self {
            radius,
            margin,
            ..self
        }
    }

    /// The a-priori curvature bound `ρ_min` of `d_min`, m.
    #[must_use]
    pub fn with_rho_min(self, rho_min: f64) -> Self {
        Self { rho_min, ..self }
    }

    /// The scan perception's priors and parameters ([`crate::Navigator::observe_scan`]).
    #[must_use]
    pub fn with_scan(self, scan: ScanOptions) -> Self {
        Self { scan, ..self }
    }

    /// The `k` policy.
    #[must_use]
    pub fn with_k(self, k: KPolicy) -> Self {
        Self { k, ..self }
    }

    /// The damping policy of the dynamic law.
    #[must_use]
    pub fn with_damping(self, damping: DampingPolicy) -> Self {
        Self { damping, ..self }
    }

    /// The speed policy of the kinematic law (ignored by the dynamic law).
    #[must_use]
    pub fn with_speed(self, speed: SpeedPolicy) -> Self {
        Self { speed, ..self }
    }

    /// The heading policy of both laws ([`Options::heading`]).
    #[must_use]
    pub fn with_heading(self, heading: HeadingPolicy) -> Self {
        Self { heading, ..self }
    }

    /// The kinematic law's top speed `v_max`, m/s, in [`PARAMETER_RANGE`](crate::tuning::PARAMETER_RANGE) (ignored by the
    /// dynamic law, whose speed bound is `√(2μ/m)`).
    #[must_use]
    pub fn with_v_max(self, v_max: f64) -> Self {
        Self {
            v_max: Some(v_max),
            ..self
        }
    }

    /// The control period `h`, s: the robot holds each command for `h` (`x += h·u`, or
    /// `v += h·f/m, x += h·v`), and every command is made safe for it ([`HoldPolicy::Auto`]).
    #[must_use]
    pub fn with_control_period(self, h: f64) -> Self {
        Self {
            control_period: Some(h),
            ..self
        }
    }

    /// The dynamic law's force bound `F`, N ([`Options::force_bound`]), in
    /// [`PARAMETER_RANGE`](crate::tuning::PARAMETER_RANGE).
    #[must_use]
    pub fn with_force_bound(self, force_bound: f64) -> Self {
        Self {
            force_bound: Some(force_bound),
            ..self
        }
    }

    /// The comfort distance `c`, m ([`Options::comfort`]).
    #[must_use]
    pub fn with_comfort(self, comfort: f64) -> Self {
        Self { comfort, ..self }
    }

    /// The hold policy.
    #[must_use]
    pub fn with_hold(self, hold: HoldPolicy) -> Self {
        Self { hold, ..self }
    }

    /// The robot's base ([`Options::base`]). A differential-drive base also caps the kinematic
    /// law's top speed [`Options::v_max`] at its own `v_max` (the smaller of the two if both
    /// are given), so that the held direction's speed is one the base can drive.
    #[must_use]
    pub fn with_base(self, base: Base) -> Self {
        let v_max = match base {
            Base::Diff { v_max, .. } => Some(self.v_max.map_or(v_max, |v| v.min(v_max))),
            Base::Holonomic => self.v_max,
        };
        Self {
            base,
            v_max,
            ..self
        }
    }

    /// The recommended [`ScanOptions::fit_range`] `r_f` for `law`, with scans every
    /// `scan_period` s from a lidar whose closest return is `range_min` m (docs/maths.md
    /// §12.11, §12.16):
    ///
    /// ```text
    /// r_f = max(r + m, r_min) + ε + FIT_SCANS_AHEAD·v_max·T                      (eq. fitnear)
    /// r_f = D + FIT_BEYOND_DEPTH      the dynamic law under the paper's damping (d_min = r_f − D)
    /// ```
    ///
    /// `r + m` the robot's radius and margin, `ε` the noise bound
    /// ([`ScanOptions::range_noise`]), `v_max` the top speed (the kinematic law's, the dynamic
    /// law's bound `√(2μ/m)`), `T` the scan period, `r_min` the closest return (a hit never
    /// reads nearer, so a fit range below `r_min + ε` would fit nothing). An obstacle need only
    /// be fitted before the robot can come within its margin of it, and between two scans the
    /// robot moves at most `v_max·T`; an obstacle fitted from nearer is seen wider, with more
    /// free space left out, and one the robot never comes near is never fitted. The dynamic
    /// law then brakes within each event's own room (eq. eventstop, §12.18), except under the
    /// paper's damping, which brakes by the switched damping alone while `V ≥ μ` and crawls
    /// after a near event: it keeps `D + 0.5` and `d_min = r_f − D` (§12.11). The result may
    /// exceed the lidar's range when scans are sparse: the robot then outruns its lidar, and
    /// should slow down or scan faster.
    #[must_use]
    pub fn recommended_fit_range(&self, law: &Law, scan_period: f64, range_min: f64) -> f64 {
        let far = self.scan.max_obstacle_depth + FIT_BEYOND_DEPTH;
        // The top speed: the kinematic law's `v_max`, the dynamic law's bound `√(2μ/m)`.
        let v_max = match *law {
            // The paper's damping brakes by `(m/d_e)|ẋ(T_n)|` alone while `V ≥ μ` (no
            // `max` with `λ(x)`): heavy after a near event, and slow to let `V` fall (§12.18).
            Law::Dynamic { .. } if self.damping == DampingPolicy::Paper => return far,
            Law::Dynamic { mass, mu } => Some((2.0 * mu / mass).sqrt()),
            Law::Kinematic { gain } => self.v_max.or_else(|| {
                harmonav_control::Kinematic::new(gain)
                    .ok()
                    .map(|k| k.v_max())
            }),
        };
        let near = self.inflation().max(range_min) + self.scan.range_noise;
        match v_max {
            Some(v) if (v * scan_period).is_finite() => near + FIT_SCANS_AHEAD * v * scan_period,
            _ => far,
        }
    }

    /// The control period in force for `law`: [`Options::control_period`], or the law's
    /// default.
    #[must_use]
    pub fn period_for(&self, law: &Law) -> f64 {
        self.control_period.unwrap_or(match law {
            Law::Kinematic { .. } => DEFAULT_KINEMATIC_PERIOD,
            Law::Dynamic { .. } => DEFAULT_DYNAMIC_PERIOD,
        })
    }

    /// `d_min(θ)` of eq. `dmin` for this sensor and `ρ_min`, after checking both against
    /// [`PARAMETER_RANGE`](crate::tuning::PARAMETER_RANGE) and [`MIN_APERTURE_DEG`](crate::tuning::MIN_APERTURE_DEG); errors name the field.
    ///
    /// Under the paper's damping ([`DampingPolicy::Paper`]) with a finite
    /// [`ScanOptions::fit_range`] `r_f`, the sector reaches at most `r_f − D`: an obstacle seen
    /// by scans is first known within `r_f` of the sensor, and its first fit may reach `D` in
    /// front of it (docs/maths.md §12.6, §12.11); `r_f ≤ D` is then an error naming
    /// `fit_range`. Under the other policies a scan event's own room sets its stopping
    /// distance (eq. eventstop, §12.18), so the sector is not cut.
    pub fn d_min(&self) -> Result<f64, NavError> {
        self.d_min_cut(self.damping == DampingPolicy::Paper)
    }

    /// Whether `law` takes its `d_min` from `r_f − D`: the dynamic law under the paper's
    /// damping ([`Options::d_min`]; the kinematic law uses no `d_min`, and its fit range may lie
    /// below `D`, eq. fitnear).
    fn cuts_d_min(&self, law: &Law) -> bool {
        matches!(law, Law::Dynamic { .. }) && self.damping == DampingPolicy::Paper
    }

    /// [`Options::d_min`], the sector cut to `r_f − D` only when `cut`.
    fn d_min_cut(&self, cut: bool) -> Result<f64, NavError> {
        in_range("sensor_range", self.sensor_range)?;
        let (fit_range, depth) = (self.scan.fit_range, self.scan.max_obstacle_depth);
        let range = if cut && fit_range.is_finite() {
            if fit_range <= depth {
                return Err(NavError::InvalidOption {
                    field: "fit_range",
                    value: fit_range,
                });
            }
            self.sensor_range.min(fit_range - depth)
        } else {
            self.sensor_range
        };
        let aperture = self.sensor_aperture_deg;
        if !(aperture.is_finite() && (MIN_APERTURE_DEG..=360.0).contains(&aperture)) {
            return Err(NavError::InvalidOption {
                field: "sensor_aperture_deg",
                value: aperture,
            });
        }
        in_range("rho_min", self.rho_min)?;
        let sector = Sector::new(range, aperture.to_radians()).map_err(NavError::Sensor)?;
        let d_min = sector.d_min(self.rho_min);
        // Guard: within the ranges above d_min ≥ min(1e-9·sin(5e-4°)... , ρ_min) > 0; checked
        // rather than assumed, as every quantity derived from it divides by it.
        if d_min.is_finite() && d_min > 0.0 {
            Ok(d_min)
        } else {
            Err(NavError::InvalidOption {
                field: "d_min",
                value: d_min,
            })
        }
    }

    /// Checks every option against its range, with `law` (which sets the default period):
    /// `radius`, `margin` and `comfort` finite, `≥ 0` and at most [`MAX_LENGTH`]; the sensor and `ρ_min` as
    /// in [`Options::d_min`]; the control period and `v_max` (if given) in [`PARAMETER_RANGE`](crate::tuning::PARAMETER_RANGE);
    /// the scan options as in [`ScanOptions::validate`]; a differential-drive base's `v_max` and
    /// `omega_max` in [`PARAMETER_RANGE`](crate::tuning::PARAMETER_RANGE), and only with the kinematic law (else `base`).
    pub fn validate(&self, law: &Law) -> Result<(), NavError> {
        if let Some(v) = self.v_max {
            in_range("v_max", v)?;
        }
        for (field, value) in [
            ("radius", self.radius),
            ("margin", self.margin),
            ("comfort", self.comfort),
        ] {
            if !(value.is_finite() && (0.0..=MAX_LENGTH).contains(&value)) {
                return Err(NavError::InvalidOption { field, value });
            }
        }
        self.d_min_cut(self.cuts_d_min(law))?;
        self.scan.validate(self.rho_min)?;
        in_range("control_period", self.period_for(law))?;
        self.base.validate(law)?;
        if let Some(f) = self.force_bound {
            in_range("force_bound", f)?;
            // A kinematic robot is commanded velocities: a force bound would not bind.
            if matches!(law, Law::Kinematic { .. }) {
                return Err(NavError::InvalidOption {
                    field: "force_bound",
                    value: f,
                });
            }
        }
        Ok(())
    }
}

impl Options {
    /// A perceived obstacle as a navigator keeps it: `shape` grown by `radius + margin` (what
    /// `Θ` is built on), and, with a margin, grown by `radius` alone (the robot's body must
    /// not already overlap it). The one place the shapes are grown.
    ///
    /// # Errors
    /// The shape cannot be grown ([`NavError::Shape`]); the body contains the robot's last
    /// position `last` ([`NavError::ContainsRobot`]).
    pub(crate) fn grow(
        &self,
        shape: &StarShape,
        last: Option<Vector2<f64>>,
    ) -> Result<(StarShape, Option<StarShape>), NavError> {
        let grown = shape.offset(self.inflation()).map_err(NavError::Shape)?;
        let inner = if self.margin > 0.0 {
            Some(shape.offset(self.radius).map_err(NavError::Shape)?)
        } else {
            None
        };
        let body = inner.as_ref().unwrap_or(&grown);
        if last.is_some_and(|x| body.contains(x)) {
            return Err(NavError::ContainsRobot);
        }
        Ok((grown, inner))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hold_names_round_trip_and_unknown_names_are_rejected() {
        for p in HoldPolicy::ALL {
            assert_eq!(p.as_str().parse::<HoldPolicy>(), Ok(p));
        }
        assert_eq!(HoldPolicy::default(), HoldPolicy::Auto);
        let e = "exact".parse::<HoldPolicy>().unwrap_err();
        assert!(e.to_string().contains("\"exact\""), "{e}");
    }

    /// A finite fit range cuts the sector of `d_min` to `r_f − D` (and only cuts it), and one
    /// at or below `D` is refused by name.
    #[test]
    fn a_fit_range_cuts_the_sector_of_d_min() {
        let base = Options::default().with_sensor(3.0, 360.0).with_rho_min(0.1);
        let with_fit = |fit_range: f64| {
            base.with_scan(ScanOptions {
                max_obstacle_depth: 1.0,
                fit_range,
                ..ScanOptions::default()
            })
        };
        let sector = |range: f64| {
            Options::default()
                .with_sensor(range, 360.0)
                .with_rho_min(0.1)
        };
        // The cut is the paper's damping's; under the others each event's room counts.
        let paper = |fit_range: f64| with_fit(fit_range).with_damping(DampingPolicy::Paper);
        assert_eq!(paper(1.5).d_min(), sector(0.5).d_min());
        assert_eq!(with_fit(1.5).d_min(), base.d_min());
        assert!(with_fit(0.5).validate(&Law::dynamic(1.0, 2.0)).is_ok());
        assert!(sector(0.5).d_min().unwrap() < base.d_min().unwrap());
        // Beyond the sensor's own range nothing changes.
        assert_eq!(with_fit(10.0).d_min(), base.d_min());
        assert_eq!(with_fit(f64::INFINITY).d_min(), base.d_min());
        for bad in [1.0, 0.5] {
            assert!(matches!(
                paper(bad).d_min(),
                Err(NavError::InvalidOption {
                    field: "fit_range",
                    ..
                })
            ));
            // Only the dynamic law takes `d_min` from `r_f − D`: the kinematic law may fit
            // from nearer than `D` (eq. fitnear).
            assert!(paper(bad).validate(&Law::kinematic(1.0)).is_ok());
            let e = paper(bad).validate(&Law::dynamic(1.0, 2.0)).unwrap_err();
            assert!(e.to_string().contains("above max_obstacle_depth"), "{e}");
        }
    }

    /// Eq. fitnear: the robot's radius and margin (or the closest return, if farther) and the
    /// noise bound, plus three scans at top speed (`K√2`, or `v_max`; the dynamic law's
    /// `√(2μ/m)`); `D + 0.5` under the paper's damping.
    #[test]
    fn the_recommended_fit_range_is_nearer_for_the_kinematic_law() {
        let options = Options::default()
            .with_robot(0.1, 0.05)
            .with_scan(ScanOptions {
                max_obstacle_depth: 1.2,
                range_noise: 0.02,
                ..ScanOptions::default()
            });
        let paper = options.with_damping(DampingPolicy::Paper);
        let dynamic = paper.recommended_fit_range(&Law::dynamic(1.0, 2.0), 0.1, 0.05);
        assert_eq!(dynamic, 1.7);
        let dynamic = options.recommended_fit_range(&Law::dynamic(1.0, 2.0), 0.1, 0.05);
        assert!(
            (dynamic - (0.15 + 0.02 + 3.0 * 2.0 * 0.1)).abs() < 1e-12,
            "{dynamic}"
        );
        let kinematic = options.recommended_fit_range(&Law::kinematic(2.0), 0.1, 0.05);
        let expected = 0.15 + 0.02 + 3.0 * 2.0 * 2f64.sqrt() * 0.1;
        assert!((kinematic - expected).abs() < 1e-12, "{kinematic}");
        let capped = options.with_v_max(0.5);
        let kinematic = capped.recommended_fit_range(&Law::kinematic(2.0), 0.1, 0.05);
        assert!((kinematic - 0.32).abs() < 1e-12, "{kinematic}");
        // A point robot on a fast lidar: never below the closest return and the noise.
        let point = options.with_robot(0.0, 0.0);
        let fast = point.recommended_fit_range(&Law::kinematic(1.0), 1e-3, 0.05);
        assert!(fast > 0.05 + 0.02, "{fast}");
        // Sparse scans: beyond the paper's dynamic range, as the robot's travel asks.
        assert!(options.recommended_fit_range(&Law::kinematic(2.0), 1.0, 0.05) > 1.7);
    }
}
