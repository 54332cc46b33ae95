//! The guarantees a run is judged by, typed: each carries what its monitor measured, and its
//! name and detail line are derived from that. No consumer matches a guarantee by its text.

use harmonav::NavError;
use harmonav_transform::Shown;
use serde::Serialize;
use serde::ser::{SerializeStruct, Serializer};

/// How far below `robot.margin` the measured clearance may fall and still pass: the offset
/// outlines of non-circular shapes are Hermite tables (`StarShape::offset`) and the exact
/// distances are refined to ~1e-9 m, so the grown shapes sit within this of the true offset.
pub const MARGIN_TOLERANCE: f64 = 1e-6;

/// A guarantee's kind, for consumers that group them (the verify matrix, the sweep's outcome).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// The goal was reached within tolerance and time.
    ReachedGoal,
    /// No collision with the true shapes, and the margin kept.
    NoCollision,
    /// Strictly inside the true boundary.
    StayedInWorkspace,
    /// `Θ ∈ [0, 1]`.
    ThetaInUnitInterval,
    /// The discoveries (informational; always holds).
    Discoveries,
    /// The dynamic law's speed below `√(2μ/m)` (corollary `boundedvel`).
    SpeedBelowBound,
    /// `V` non-increasing between discoveries.
    EnergyNonIncreasing,
    /// No overshoot at the goal (corollary `critdamp`).
    NoOvershoot,
    /// The integrator could go on (no step-size collapse).
    Integrated,
    /// The robot stayed in the free space of the obstacles it knew.
    StayedInFreeSpace,
    /// The rapier cross-check saw no contact.
    PhysicsNoContact,
    /// How far the rapier path strayed from the built-in one (informational; always holds).
    PhysicsDeviation,
    /// The energy rapier's own corrections added beyond the semi-implicit Euler step
    /// (informational; always holds).
    PhysicsEngineEnergy,
    /// An `[expect]` entry of the scenario file.
    Expect,
    /// A floor plan: the robot stayed in the certified region `W_δ` of the harmonic map.
    StayedInCertifiedRegion,
    /// A floor plan: the robot's disc stayed clear of the truth along every held step, not
    /// only at the states.
    NoCollisionBetweenStates,
    /// A lidar: after every scan, the true boundary points the sensor sees lie in a perceived
    /// shape.
    PerceivedCoversTruth,
    /// A lidar: the perceived shapes only grow.
    PerceivedOnlyGrows,
    /// A lidar: the navigator accepted every scan.
    ScansAccepted,
    /// A differential drive: every `(v, ω)` held within `0 ≤ v ≤ v_max`, `|ω| ≤ ω_max`.
    DiffBounds,
    /// A differential drive with acceleration limits: consecutive commands within
    /// `|Δv| ≤ a_max h`, `|Δω| ≤ α_max h`, from rest.
    DiffAccel,
    /// A force-bounded dynamic robot (`[robot] force_bound`): every force held `|f| ≤ F`.
    ForceWithinBound,
}

/// Why the robot lost the free space of its known obstacles.
#[derive(Clone, Debug, PartialEq)]
pub enum FreeSpaceLoss {
    /// It moved out of it (only a controller other than the law does).
    Left,
    /// The navigator rejected a newly sensed obstacle (the robot is inside it).
    Discovery {
        /// The obstacle's name.
        obstacle: String,
        /// The navigator's error.
        error: NavError,
    },
}

/// One guarantee with what was measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Check {
    /// [`Kind::ReachedGoal`].
    ReachedGoal {
        /// Distance to the goal at the end, m.
        final_distance: f64,
        /// `sim.goal_tolerance`, m.
        tolerance: f64,
        /// Time at the end, s.
        time_s: f64,
        /// `sim.max_time`, s.
        max_time_s: f64,
    },
    /// [`Kind::NoCollision`].
    NoCollision {
        /// Smallest clearance to the true obstacles and boundary, m.
        min_clearance: f64,
        /// `robot.margin`, m.
        margin: f64,
    },
    /// [`Kind::StayedInWorkspace`].
    StayedInWorkspace {
        /// Smallest clearance to the true boundary, m.
        min_boundary_distance: f64,
    },
    /// [`Kind::ThetaInUnitInterval`].
    ThetaInUnitInterval {
        /// Smallest `Θ`.
        min: f64,
        /// Largest `Θ`.
        max: f64,
    },
    /// [`Kind::Discoveries`]: `(name, time)` in order.
    Discoveries {
        /// The discoveries.
        discoveries: Vec<(String, f64)>,
    },
    /// [`Kind::SpeedBelowBound`].
    SpeedBelowBound {
        /// Largest speed, m/s.
        max_speed: f64,
        /// `√(2μ/m)`, m/s.
        bound: f64,
    },
    /// [`Kind::EnergyNonIncreasing`].
    EnergyNonIncreasing {
        /// Largest relative rise of `V` between states.
        largest_rise: f64,
        /// The same beyond the integration tolerance (`> 0` fails).
        beyond_tolerance: f64,
    },
    /// [`Kind::NoOvershoot`].
    NoOvershoot {
        /// Samples in the last, critically damped approach (`< 2`: not entered).
        samples: usize,
        /// Largest increase of the distance to the goal there, m.
        largest_increase: f64,
    },
    /// [`Kind::Integrated`]: the step size collapsed here.
    StepCollapsed {
        /// When, s.
        time_s: f64,
        /// Where.
        position: [f64; 2],
    },
    /// [`Kind::StayedInFreeSpace`]: it was lost here.
    LeftFreeSpace {
        /// When, s.
        time_s: f64,
        /// Where.
        position: [f64; 2],
        /// Why.
        #[serde(skip)]
        reason: FreeSpaceLoss,
    },
    /// [`Kind::PhysicsNoContact`].
    PhysicsContacts {
        /// Contact events in rapier.
        contacts: usize,
    },
    /// [`Kind::PhysicsDeviation`].
    PhysicsDeviation {
        /// Largest distance between the rapier and the built-in positions at equal times, m.
        max_deviation: f64,
    },
    /// [`Kind::PhysicsEngineEnergy`] (informational): the energy rapier's own corrections added
    /// to a step beyond the semi-implicit Euler step of the law's force (its speculative
    /// contacts and position update), the largest relative to `V`. The energy monitor
    /// allows for it as the integrator's, not the law's (`rapier.rs`).
    PhysicsEngineEnergy {
        /// Largest `(V(rapier's step) − V(Euler's step)) / V`, 0 if none.
        largest_rise: f64,
    },
    /// [`Kind::StayedInCertifiedRegion`] (floor plans, docs/maths.md §13): the smallest
    /// `sd(x) − δ` over the states, `sd` the signed distance to the shrunk walls `∂W_s`.
    StayedInCertifiedRegion {
        /// Smallest `sd − δ`, m (`≥ 0` holds).
        min_layer_clearance: f64,
        /// `δ`, m.
        delta: f64,
    },
    /// [`Kind::NoCollision`] on a ROS map: the robot's disc never touched one of the map's own
    /// occupied or unknown pixels, whatever the pipeline dropped (specks), simplified or cut
    /// (issue 56, D1). The margin is kept from the floor plan's walls ([`Check::NoCollision`]);
    /// from the pixels it may be less by how far the outline strays into them (at most
    /// `res/(2√2)` at a pixel's corner plus the simplification's movement, docs/maths.md
    /// §13.1).
    NoCollisionWithMap {
        /// Smallest clearance of the disc to the map's non-free pixels, m (`> 0` holds).
        min_pixel_clearance: f64,
    },
    /// [`Kind::NoCollisionBetweenStates`] (floor plans): a lower bound on the robot disc's
    /// clearance from the true walls and obstacles along every straight step between two
    /// states. The clearance `c` is 1-Lipschitz, so on a step of length `L` from `c₀` to `c₁`
    /// it is at least `(c₀ + c₁ − L)/2`.
    NoCollisionBetweenStates {
        /// The smallest such bound over the run, m (`> 0` holds).
        swept_clearance: f64,
    },
    /// [`Kind::PerceivedCoversTruth`] (`[sensor] type = "lidar"`): after every scan,
    /// noise-free rays ten times denser than the lidar's beams, cast from the same pose, hit
    /// `seen_points` true boundary points; `uncovered_points` of them lay outside every
    /// perceived shape (`0` holds).
    PerceivedCoversTruth {
        /// True boundary points seen, over all scans.
        seen_points: usize,
        /// Of those, outside every perceived shape.
        uncovered_points: usize,
    },
    /// [`Kind::PerceivedOnlyGrows`]: boundary points of a perceived shape outside every
    /// perceived shape after an event (`0` holds).
    PerceivedOnlyGrows {
        /// Such points, over all events.
        shrunk_points: usize,
    },
    /// [`Kind::ScansAccepted`]: the navigator observed every scan, or refused one (the run
    /// stops there: the robot cannot go on with what it saw).
    ScansAccepted {
        /// Scans observed.
        scans: usize,
        /// When a scan was refused, s.
        refused_at_s: Option<f64>,
        /// The navigator's refusal.
        #[serde(skip)]
        error: Option<NavError>,
    },
    /// [`Kind::NoCollision`] with the file's movers (`[[movers]]`, docs/movers.md §8): the
    /// true clearance between the robot's disc and every mover's disc, exact along every held
    /// step. Judged as Theorem 1 of docs/movers.md: a contact in a period whose command was
    /// certified fails; a contact after an `Overwhelmed` (or refused) command is counted, not
    /// failed.
    NoCollisionWithMovers {
        /// Contact episodes (clearance ≤ 0).
        contacts: usize,
        /// Periods with a contact whose command was certified (`0` holds).
        after_certified: usize,
        /// Commands that were not certified (`Overwhelmed`, or refused: the robot's disc
        /// overlapped a mover's as reported).
        overwhelmed_commands: usize,
        /// The least true clearance to a mover's body, m.
        min_clearance: f64,
        /// `robot.margin`, m (Theorem 1 keeps it while commands are certified).
        margin: f64,
    },
    /// [`Kind::NoCollision`] between the robots of a file with `[[robots]]` (docs/movers.md
    /// §8): the exact least clearance between every two robots' discs along every held step. A
    /// contact in a period where both commands were certified fails it (Theorem 2, F2), and so
    /// does a robot other than the first that lost a guarantee of its own (arrival aside).
    NoCollisionBetweenRobots {
        /// Robots in the run.
        robots: usize,
        /// Contact episodes between two robots.
        contacts: usize,
        /// Periods with a contact between two robots whose commands were both certified
        /// (`0` holds).
        after_certified: usize,
        /// The least clearance between two robots' bodies, m.
        min_clearance: f64,
        /// The other robots that lost a guarantee of their own (`0` holds).
        others_unsafe: usize,
    },
    /// `[expect] reached`.
    ExpectReached {
        /// The file's value.
        expected: bool,
        /// The run's.
        got: bool,
    },
    /// `[expect] discovery_order`.
    ExpectDiscoveryOrder {
        /// The file's value.
        expected: Vec<String>,
        /// The run's.
        got: Vec<String>,
    },
    /// `[expect] damping_switched`.
    ExpectDampingSwitched {
        /// The file's value.
        expected: bool,
        /// The run's.
        got: bool,
    },
    /// [`Kind::DiffBounds`] (`[robot] base = "diff"`): the extremes of the commands held,
    /// against the base's bounds (`0 ≤ v ≤ v_max`, `|ω| ≤ ω_max`; holds when none is exceeded).
    DiffBounds {
        /// The smallest forward speed `v` held, m/s (`≥ 0` holds: forward only).
        min_v: f64,
        /// The largest forward speed `v` held, m/s.
        max_v: f64,
        /// `v_max`, m/s.
        v_max: f64,
        /// The largest turn rate `|ω|` held, rad/s.
        max_omega: f64,
        /// `ω_max`, rad/s.
        omega_max: f64,
    },
    /// [`Kind::DiffAccel`] (`[robot] a_max` and `alpha_max`): the largest change between
    /// consecutive commands (the first from rest), per second, against the limits (holds when
    /// neither is exceeded by more than `1e-12` relative, the rounding of `v ± a_max h`).
    DiffAccel {
        /// The largest `|v⁺ − v|/h`, m/s².
        max_dv: f64,
        /// `a_max`, m/s².
        a_max: f64,
        /// The largest `|ω⁺ − ω|/h`, rad/s².
        max_domega: f64,
        /// `alpha_max`, rad/s².
        alpha_max: f64,
    },
    /// [`Kind::ForceWithinBound`].
    ForceWithinBound {
        /// The largest `|f|` held, N.
        max_force: f64,
        /// `F`, N.
        bound: f64,
    },
    /// `[expect] max_speed_below`.
    ExpectMaxSpeedBelow {
        /// Largest speed, m/s.
        max_speed: f64,
        /// The file's limit, m/s.
        limit: f64,
    },
}

impl Check {
    /// The kind.
    pub fn kind(&self) -> Kind {
        match self {
            Self::ReachedGoal { .. } => Kind::ReachedGoal,
            Self::NoCollision { .. } => Kind::NoCollision,
            Self::StayedInWorkspace { .. } => Kind::StayedInWorkspace,
            Self::ThetaInUnitInterval { .. } => Kind::ThetaInUnitInterval,
            Self::Discoveries { .. } => Kind::Discoveries,
            Self::SpeedBelowBound { .. } => Kind::SpeedBelowBound,
            Self::EnergyNonIncreasing { .. } => Kind::EnergyNonIncreasing,
            Self::NoOvershoot { .. } => Kind::NoOvershoot,
            Self::StepCollapsed { .. } => Kind::Integrated,
            Self::LeftFreeSpace { .. } => Kind::StayedInFreeSpace,
            Self::PhysicsContacts { .. } => Kind::PhysicsNoContact,
            Self::PhysicsDeviation { .. } => Kind::PhysicsDeviation,
            Self::PhysicsEngineEnergy { .. } => Kind::PhysicsEngineEnergy,
            Self::ExpectReached { .. }
            | Self::ExpectDiscoveryOrder { .. }
            | Self::ExpectDampingSwitched { .. }
            | Self::ExpectMaxSpeedBelow { .. } => Kind::Expect,
            Self::StayedInCertifiedRegion { .. } => Kind::StayedInCertifiedRegion,
            Self::NoCollisionWithMap { .. }
            | Self::NoCollisionWithMovers { .. }
            | Self::NoCollisionBetweenRobots { .. } => Kind::NoCollision,
            Self::NoCollisionBetweenStates { .. } => Kind::NoCollisionBetweenStates,
            Self::PerceivedCoversTruth { .. } => Kind::PerceivedCoversTruth,
            Self::PerceivedOnlyGrows { .. } => Kind::PerceivedOnlyGrows,
            Self::ScansAccepted { .. } => Kind::ScansAccepted,
            Self::DiffBounds { .. } => Kind::DiffBounds,
            Self::DiffAccel { .. } => Kind::DiffAccel,
            Self::ForceWithinBound { .. } => Kind::ForceWithinBound,
        }
    }

    /// The name in `summary.json` and the CLI's table.
    pub fn name(&self) -> &'static str {
        match self {
            Self::ReachedGoal { .. } => "reached-goal",
            Self::NoCollision { .. } => "no-collision",
            Self::StayedInWorkspace { .. } => "stayed-in-workspace",
            Self::ThetaInUnitInterval { .. } => "theta-in-unit-interval",
            Self::Discoveries { .. } => "discoveries",
            Self::SpeedBelowBound { .. } => "speed-below-bound",
            Self::EnergyNonIncreasing { .. } => "energy-non-increasing-between-discoveries",
            Self::NoOvershoot { .. } => "no-overshoot-at-goal",
            Self::StepCollapsed { .. } => "integrated",
            Self::LeftFreeSpace { .. } => "stayed-in-free-space",
            Self::PhysicsContacts { .. } => "physics-no-contact",
            Self::PhysicsDeviation { .. } => "physics-deviation",
            Self::PhysicsEngineEnergy { .. } => "physics-engine-energy",
            Self::ExpectReached { .. } => "expect.reached",
            Self::ExpectDiscoveryOrder { .. } => "expect.discovery-order",
            Self::ExpectDampingSwitched { .. } => "expect.damping-switched",
            Self::ExpectMaxSpeedBelow { .. } => "expect.max-speed-below",
            Self::StayedInCertifiedRegion { .. } => "stayed-in-certified-region",
            Self::NoCollisionWithMap { .. } => "no-collision-with-map-pixels",
            Self::NoCollisionWithMovers { .. } => "no-collision-with-movers",
            Self::NoCollisionBetweenRobots { .. } => "no-collision-between-robots",
            Self::NoCollisionBetweenStates { .. } => "no-collision-between-states",
            Self::PerceivedCoversTruth { .. } => "perceived-covers-seen-truth",
            Self::PerceivedOnlyGrows { .. } => "perceived-shapes-only-grow",
            Self::ScansAccepted { .. } => "scans-accepted",
            Self::DiffBounds { .. } => "diff-command-bounds",
            Self::DiffAccel { .. } => "diff-accel-bounds",
            Self::ForceWithinBound { .. } => "force-within-bound",
        }
    }
}

impl std::fmt::Display for Check {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::ReachedGoal {
                final_distance,
                tolerance,
                time_s,
                max_time_s,
            } => write!(
                f,
                "final distance {final_distance:.2e} m (tolerance {}) at t = {time_s:.3} s \
                 (max {} s)",
                Shown(*tolerance),
                Shown(*max_time_s)
            ),
            Self::NoCollision {
                min_clearance,
                margin,
            } => write!(
                f,
                "min clearance {min_clearance:.4} m to the true obstacles and boundary (margin \
                 {margin} m)"
            ),
            Self::StayedInWorkspace {
                min_boundary_distance,
            } => write!(
                f,
                "min distance to the boundary {min_boundary_distance:.4} m"
            ),
            Self::ThetaInUnitInterval { min, max } => write!(f, "Θ ∈ [{min:.3e}, {max:.6}]"),
            Self::Discoveries { discoveries } if discoveries.is_empty() => write!(f, "none"),
            Self::Discoveries { discoveries } => {
                let list: Vec<String> = discoveries
                    .iter()
                    .map(|(name, t)| format!("{name} at {t:.3} s"))
                    .collect();
                write!(f, "{}", list.join(", "))
            }
            Self::SpeedBelowBound { max_speed, bound } => {
                write!(
                    f,
                    "max speed {:.3} m/s < √(2μ/m) = {:.3} m/s",
                    Shown(*max_speed),
                    Shown(*bound)
                )
            }
            Self::EnergyNonIncreasing {
                largest_rise,
                beyond_tolerance,
            } => write!(
                f,
                "largest relative rise of V between states {largest_rise:.1e}, \
                 {beyond_tolerance:.1e} beyond the integration tolerance"
            ),
            Self::NoOvershoot { samples, .. } if *samples < 2 => {
                write!(f, "the run did not enter the critically damped goal basin")
            }
            Self::NoOvershoot {
                samples,
                largest_increase,
            } => write!(
                f,
                "{samples} samples in the last approach (Θ < 0.01, critical damping): largest \
                 increase of the distance {largest_increase:.1e} m"
            ),
            Self::StepCollapsed { time_s, position } => write!(
                f,
                "t = {time_s:.4}: the step size fell below 1e-14 s at ({:.6}, {:.6}); the closed \
                 loop is too stiff to integrate there",
                position[0], position[1]
            ),
            Self::LeftFreeSpace {
                time_s,
                position,
                reason,
            } => match reason {
                FreeSpaceLoss::Left => write!(
                    f,
                    "t = {time_s:.3}: the robot left the free space at ({:.4}, {:.4})",
                    position[0], position[1]
                ),
                FreeSpaceLoss::Discovery { obstacle, error } => write!(
                    f,
                    "t = {time_s:.4}: obstacle {obstacle} could not be added on discovery at \
                     ({:.4}, {:.4}): {error}",
                    position[0], position[1]
                ),
            },
            Self::PhysicsContacts { contacts } => write!(f, "{contacts} contact events in rapier"),
            Self::PhysicsDeviation { max_deviation } => write!(
                f,
                "largest deviation from the built-in path {max_deviation:.4} m"
            ),
            Self::PhysicsEngineEnergy { largest_rise } => write!(
                f,
                "largest relative energy rapier's corrections added to a step {largest_rise:.1e} \
                 (the integrator's, allowed by the energy monitor)"
            ),
            Self::ExpectReached { expected, got }
            | Self::ExpectDampingSwitched { expected, got } => {
                write!(f, "expected {expected}, got {got}")
            }
            Self::ExpectDiscoveryOrder { expected, got } => {
                write!(f, "expected {expected:?}, got {got:?}")
            }
            Self::ExpectMaxSpeedBelow { max_speed, limit } => {
                write!(
                    f,
                    "max speed {:.3} m/s, limit {} m/s",
                    Shown(*max_speed),
                    Shown(*limit)
                )
            }
            Self::NoCollisionWithMap {
                min_pixel_clearance,
            } => write!(
                f,
                "min clearance {min_pixel_clearance:.4} m to the map's occupied and unknown \
                 pixels"
            ),
            Self::NoCollisionWithMovers {
                contacts,
                after_certified,
                overwhelmed_commands,
                min_clearance,
                margin,
            } => write!(
                f,
                "{contacts} contact episodes with movers, {after_certified} periods with a \
                 contact under a certified command; min clearance to a mover {min_clearance:.4} \
                 m (margin {margin} m); a contact after one of the {overwhelmed_commands} \
                 uncertified commands (Overwhelmed or refused) is counted, not failed \
                 (docs/movers.md, Theorem 1)"
            ),
            Self::NoCollisionBetweenRobots {
                robots,
                contacts,
                after_certified,
                min_clearance,
                others_unsafe,
            } => write!(
                f,
                "{robots} robots: {contacts} contact episodes between two, {after_certified} \
                 periods with a contact under two certified commands; min clearance between \
                 two robots {min_clearance:.4} m; {others_unsafe} other robots lost a guarantee"
            ),
            Self::StayedInCertifiedRegion {
                min_layer_clearance,
                delta,
            } => write!(
                f,
                "min distance beyond the boundary layer {min_layer_clearance:.4} m (δ = {delta} m)"
            ),
            Self::NoCollisionBetweenStates { swept_clearance } => write!(
                f,
                "clearance ≥ {swept_clearance:.4} m along every held step (1-Lipschitz bound)"
            ),
            Self::PerceivedCoversTruth {
                seen_points,
                uncovered_points,
            } => write!(
                f,
                "{uncovered_points} of {seen_points} true boundary points seen by rays ten times \
                 denser than the beams lay outside every perceived shape"
            ),
            Self::PerceivedOnlyGrows { shrunk_points } => write!(
                f,
                "{shrunk_points} boundary points of a perceived shape outside every later one"
            ),
            Self::ScansAccepted {
                scans,
                refused_at_s: Some(t),
                error,
            } => {
                write!(
                    f,
                    "{scans} scans observed; the scan at t = {t:.3} s was refused"
                )?;
                match error {
                    Some(e) => write!(f, ": {e}"),
                    None => Ok(()),
                }
            }
            Self::ScansAccepted { scans, .. } => write!(f, "{scans} scans observed"),
            Self::DiffBounds {
                min_v,
                max_v,
                v_max,
                max_omega,
                omega_max,
            } => write!(
                f,
                "v ∈ [{min_v:.4}, {max_v:.4}] m/s (v_max {v_max}), |ω| ≤ {max_omega:.4} rad/s \
                 (ω_max {omega_max})"
            ),
            Self::DiffAccel {
                max_dv,
                a_max,
                max_domega,
                alpha_max,
            } => write!(
                f,
                "|Δv|/h ≤ {max_dv:.4} m/s² (a_max {a_max}), |Δω|/h ≤ {max_domega:.4} rad/s² \
                 (α_max {alpha_max})"
            ),
            Self::ForceWithinBound { max_force, bound } => {
                write!(f, "max |f| {max_force:.4} N ≤ F = {bound} N")
            }
        }
    }
}

/// The guarantee of a force-bounded run: every force held, the largest `max_force`, within
/// `bound` (`[robot] force_bound`).
pub(crate) fn force_within(max_force: f64, bound: f64) -> Guarantee {
    Guarantee::new(
        Check::ForceWithinBound { max_force, bound },
        max_force <= bound,
    )
}

/// A guarantee with its verdict. In JSON: `{"name", "passed", "detail", "measured"}`.
#[derive(Clone, Debug, PartialEq)]
pub struct Guarantee {
    /// What was measured.
    pub check: Check,
    /// Whether it held.
    pub passed: bool,
}

impl Guarantee {
    /// `check` with its verdict.
    pub fn new(check: Check, passed: bool) -> Self {
        Self { check, passed }
    }

    /// A guarantee lost during the run (a step-size collapse, the free space left).
    pub fn failed(check: Check) -> Self {
        Self::new(check, false)
    }

    /// The kind.
    pub fn kind(&self) -> Kind {
        self.check.kind()
    }

    /// The name (`reached-goal`, `no-collision`, …).
    pub fn name(&self) -> &'static str {
        self.check.name()
    }

    /// What was measured, as a sentence.
    pub fn detail(&self) -> String {
        self.check.to_string()
    }
}

impl Serialize for Guarantee {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("Guarantee", 4)?;
        st.serialize_field("name", self.name())?;
        st.serialize_field("passed", &self.passed)?;
        st.serialize_field("detail", &self.detail())?;
        st.serialize_field("measured", &self.check)?;
        st.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Extreme values print in scientific notation, not hundreds of digits (issue 56, D18:
    /// `sim.arrival = 1e-300` printed "tolerance 0.000…" with 300 zeros, a bound of 1.4e-9
    /// printed "0.000").
    #[test]
    fn extreme_values_print_shortly() {
        let reached = Check::ReachedGoal {
            final_distance: 0.5,
            tolerance: 1e-300,
            time_s: 1.0,
            max_time_s: 120.0,
        }
        .to_string();
        assert!(
            reached.contains("(tolerance 1e-300)") && reached.contains("(max 120 s)"),
            "{reached}"
        );
        let speed = Check::SpeedBelowBound {
            max_speed: 1e-9,
            bound: 1.4e-9,
        }
        .to_string();
        assert!(
            speed.contains("1.000e-9 m/s") && speed.contains("1.400e-9 m/s"),
            "{speed}"
        );
        assert!(reached.len() < 100 && speed.len() < 100);
    }

    #[test]
    fn json_carries_name_verdict_detail_and_measured_values() {
        let g = Guarantee::new(
            Check::SpeedBelowBound {
                max_speed: 1.5,
                bound: 4.0,
            },
            true,
        );
        let v = serde_json::to_value(&g).unwrap();
        assert_eq!(v["name"], "speed-below-bound");
        assert_eq!(v["passed"], true);
        assert_eq!(v["measured"]["max_speed"], 1.5);
        assert_eq!(v["measured"]["bound"], 4.0);
        assert_eq!(v["detail"], "max speed 1.500 m/s < √(2μ/m) = 4.000 m/s");
        assert_eq!(g.kind(), Kind::SpeedBelowBound);
    }
}
