//! The rapier2d cross-check: the same scenario as a rapier world. Static colliders for the
//! obstacles and the boundary (a ball for circles, closed polylines through the true
//! boundary otherwise), the robot a dynamic ball (zero gravity, no rapier damping) driven by
//! the control law — its velocity for the kinematic model, a force for the dynamic one. It
//! reports the contact events and the largest deviation from the built-in trajectory. A
//! file's `[[movers]]` are reported to the navigator at every control period's start and
//! judged along every rapier step (they are not rapier bodies); `[[robots]]` are refused.

use harmonav::control::Potential;
use harmonav::{Controller, Mode, NavError, PoseCommand};
use harmonav_field::{Field, FieldEval};
use harmonav_scenario::{Model, Prepared};
use nalgebra::Vector2;

use crate::driver::{Driver, Warnings};
use crate::guarantee::{Check, FreeSpaceLoss, Guarantee};
use crate::held::{euler_energy_error, potential, state};
use crate::monitor::End;
use crate::movers::{MoverWorld, stop};
use crate::summary::{Physics, Run, RunError};
use crate::trace::{Event, Sample};
use crate::trajectory::Keep;
use crate::unicycle::{Diff, pose_command};

mod engine;
pub mod floor;

use engine::{Engine, star};
pub(crate) use floor::rapier_floor_observed;
pub use floor::{FloorLaw, run_floor_rapier};

/// A controller other than the law: `(field, eval, x, ẋ) → command`.
pub type CustomLaw<'a> = &'a dyn Fn(&Field, &FieldEval, Vector2<f64>, Vector2<f64>) -> Vector2<f64>;

/// A command source for the rapier robot: the velocity (kinematic) or force (dynamic) to apply.
/// [`Drive::Law`] is the paper's law; tests use [`Drive::Custom`] to drive a deliberately
/// broken controller: a [`CustomLaw`] in a star world, a [`FloorLaw`] on a floor plan.
pub enum Drive<C> {
    /// The kinematic or dynamic law of the scenario.
    Law,
    /// Any other controller.
    Custom(C),
}

/// What the rapier run adds to the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct RapierReport {
    /// Contact events between the robot and any obstacle or the boundary.
    pub contacts: usize,
    /// Largest distance between the rapier and the built-in positions at equal times, m.
    pub max_deviation: f64,
}

/// Runs the scenario in rapier with `drive`; `builtin` (a built-in run of the same model) is
/// the reference for the deviation.
pub fn run_rapier(
    prepared: &Prepared,
    model: Option<Model>,
    drive: Drive<CustomLaw<'_>>,
    builtin: Option<&Run>,
) -> Result<(Run, RapierReport), RunError> {
    rapier_observed(prepared, model, drive, builtin, Warnings::Skip, &mut |_| {})
}

/// [`run_rapier`], with the scenario's warnings or without ([`Warnings`]), handing every
/// recorded state to `observer`.
pub(crate) fn rapier_observed(
    prepared: &Prepared,
    model: Option<Model>,
    drive: Drive<CustomLaw<'_>>,
    builtin: Option<&Run>,
    warnings: Warnings,
    observer: &mut dyn FnMut(Event<'_>),
) -> Result<(Run, RapierReport), RunError> {
    if !prepared.scenario.sim.robots.is_empty() {
        return Err(RunError::RobotsInRapier);
    }
    let sc = &prepared.scenario;
    let truth = &prepared.truth;
    // rapier's fixed step `h`, at most 1 ms, and the control period: `robot.control_period`
    // cut into `hold` steps, over which the navigator holds each command; without it, one
    // step of `sim.dt` cut into steps of at most 1 ms, each with its own command.
    let cut = |span: f64| (span / 1e-3).ceil().max(1.0) as usize;
    let (h, hold, period) = match prepared.control_period() {
        Some(period) => (period / cut(period) as f64, cut(period), period),
        None => {
            let h = sc.sim.dt / cut(sc.sim.dt) as f64;
            (h, 1, h)
        }
    };
    // A state recorded every `sim.dt`, to the nearest step (exactly without a control period,
    // where `h` divides it).
    let record_every = (sc.sim.dt / h).round().max(1.0) as usize;
    // Semi-implicit Euler at a fixed step has no error estimate: the energy's allowance is
    // relative (`sample` below), not from a state error.
    let mut d = Driver::start(prepared, model, Some(period), 0.0, warnings, observer)?;
    let model = d.model();
    let start = prepared.start();

    // The walls: the obstacles, then the boundary; the exact gap from `x` to each.
    let gap_to = |i: usize, x: Vector2<f64>| match truth.obstacles.get(i) {
        Some(o) => o.signed_distance(x),
        None => -truth.boundary.signed_distance(x),
    };
    let walls = truth
        .obstacles
        .iter()
        .map(|o| star(o, true))
        .chain([star(&truth.boundary, false)]);
    let mut engine = Engine::new(h, walls, (start, sc.robot.radius, sc.robot.mass), &gap_to);
    // A differential drive: its body turns; each period's `(v, ω)` is judged as in the
    // built-in loop (`crate::unicycle`), on the arc commanded from rapier's pose.
    let mut diff = Diff::of(prepared.base(), prepared.start_yaw());
    if diff.is_some() {
        engine.set_yaw(prepared.start_yaw());
    }
    // The differential drive's command held over the current control period.
    let mut pose: Option<PoseCommand> = None;
    let mut t = 0.0;
    let mut steps = 0;
    let mut reached = false;
    // The energy error of the steps since the last recorded state (dynamic law), which the
    // state recorded next carries as its tolerance ([`euler_energy_error`]).
    let mut drift = 0.0;
    // The largest energy rapier's corrections added to a step, relative to V.
    let mut engine_rise: f64 = 0.0;
    // The command held over the current control period.
    let mut command = Vector2::zeros();
    // The file's movers (docs/movers.md §8): reported to the navigator at every period's start,
    // moved by their scripts and judged along every rapier step; `certified`: the command in
    // force was certified, `acted`: the filter changed it (or refused), so `V` may rise.
    let mut world = MoverWorld::new(&sc.sim.movers, truth.radius);
    let (mut last_mode, mut certified, mut acted): (Option<&'static str>, bool, bool) =
        (None, true, false);
    let sample = |d: &Driver, t: f64, x, vel, drift: &mut f64, yaw: Option<f64>| {
        let mut s = state(d, t, (x, vel), yaw);
        s.energy_tolerance = std::mem::take(drift);
        s
    };
    loop {
        let (x, vel) = engine.state();
        // Outside the known free space: the law's held command leads out of a margin band (a
        // scan event grew a shape over the robot's margin); anything else, or a controller
        // other than the law, records and stops.
        if d.eval(x, vel).is_none() && !(matches!(drive, Drive::Law) && d.recovering(x, vel)) {
            d.abort(Guarantee::failed(Check::LeftFreeSpace {
                time_s: t,
                position: [x.x, x.y],
                reason: FreeSpaceLoss::Left,
            }));
            break;
        }
        if steps % record_every == 0 || reached {
            // A discovery's second side is recorded where it happens (below), flagged there so
            // that the energy monitor does not count V's jump as a rise.
            let keep = if reached { Keep::Pinned } else { Keep::Grid };
            let yaw = diff.as_ref().map(|_| engine.yaw());
            d.record(sample(&d, t, x, vel, &mut drift, yaw), keep, acted);
        }
        if !world.is_empty() && d.movers_due(t) {
            d.movers(world.frame(t, x, last_mode, period));
        }
        reached = d.arrived(x);
        if reached || t >= sc.sim.max_time {
            break;
        }
        // The loop's work at the start of each control period: sensing, then a new command,
        // held until the next.
        if steps % hold == 0 {
            if let Some(u) = diff.as_mut() {
                u.yaw = engine.yaw();
                d.set_heading(u.yaw);
            }
            // Sensing: discoveries at period granularity, a lidar's scans at the first period
            // at or after each scan time.
            let found = d.sees(x, vel);
            let mut discovered = !found.is_empty();
            if discovered && !d.discover(t, &found, x, vel) {
                break;
            }
            if d.scan_due(t) {
                // The side before an event carries the drift since the last recorded state.
                let mut pre = state(&d, t, (x, vel), diff.as_ref().map(|u| u.yaw));
                pre.energy_tolerance = drift;
                match d.scan(pre, x, vel) {
                    None => break,
                    Some(false) => {}
                    Some(true) => {
                        drift = 0.0;
                        discovered = true;
                    }
                }
            }
            if discovered {
                // The state right after a discovery, with the new Θ, k and λ: the switch of
                // eq. `dissipationfun` may last only a few milliseconds.
                let yaw = diff.as_ref().map(|u| u.yaw);
                d.record(sample(&d, t, x, vel, &mut drift, yaw), Keep::Pinned, true);
            }
            let turning = pose.is_some_and(|c| c.v == 0.0 && c.omega != 0.0);
            if d.at_rest(t, x, false, discovered || turning, reached) {
                break;
            }
            if !world.is_empty() {
                d.nav_mut().set_movers(world.reports())?;
            }
            // How the command was formed (`None`: refused, the reported bodies overlap).
            let mut mode = None;
            if let Some(u) = diff.as_mut() {
                // The law's `(v, ω)` (a custom controller is not taken for a differential
                // drive), judged on its arc from rapier's pose.
                let (c, formed) = pose_command(d.nav_mut(), x, u.yaw, !world.is_empty())?;
                u.period(truth, x, &c, period);
                (pose, mode) = (Some(c), formed);
            }
            command = match &drive {
                _ if diff.is_some() => Vector2::zeros(),
                Drive::Law => match d.nav_mut().command(x, vel) {
                    Ok(c) => {
                        mode = Some(c.mode);
                        c.value
                    }
                    // The reported bodies overlap: no certified command; the robot stops (as
                    // hard as its force bound lets it), as in the built-in loop.
                    Err(NavError::InMover { .. }) if !world.is_empty() => {
                        match d.nav().controller() {
                            Controller::Kinematic(_) => Vector2::zeros(),
                            Controller::Dynamic(law) => {
                                let bound = d.nav().options().force_bound;
                                stop(law.mass(), vel, period, bound)
                            }
                        }
                    }
                    Err(e) => return Err(e.into()),
                },
                Drive::Custom(f) => {
                    let e = d.nav().field().eval(x)?;
                    f(d.nav().field(), &e, x, vel)
                }
            };
            if !world.is_empty() {
                certified = mode.as_ref().is_some_and(|m| m.certified());
                world.count(mode.as_ref());
                last_mode = Some(mode.as_ref().map_or("refused", Mode::as_str));
                acted = !certified
                    || matches!(mode, Some(Mode::Yielding { .. } | Mode::Bounded { .. }));
            }
        }
        match pose {
            Some(c) => engine.drive_unicycle(c.v, c.omega),
            None => engine.drive(model, command),
        }
        // Ψ and ∇Ψ at the step's start, under the field the command was made with.
        let before = potential(&d, x, vel);
        engine.step(&gap_to);
        steps += 1;
        t = steps as f64 * h;
        if !world.is_empty() {
            // One rapier step of `h` ≤ 1 ms: its chord against where every mover went.
            world.period(x, engine.state().0, h, certified);
        }
        if let (Controller::Dynamic(law), Some(p0)) = (d.nav().controller(), before) {
            // The law's semi-implicit Euler step, and the step rapier made.
            let ve = vel + h * command / law.mass();
            let xe = x + h * ve;
            let (x1, v1) = engine.state();
            if let (Some(pe), Some(p1)) = (potential(&d, xe, ve), potential(&d, x1, v1)) {
                drift += euler_energy_error(law, h, (&p0, pe.value), (x, xe), (vel, ve), command);
                let energy = |p: &Potential, v: Vector2<f64>| {
                    law.pull() * p.value + 0.5 * law.mass() * v.norm_squared()
                };
                let rise = energy(&p1, v1) - energy(&pe, ve);
                drift += rise.max(0.0);
                engine_rise = engine_rise.max(rise / energy(&p0, vel).max(1e-300));
            }
        }
    }
    let (x, _) = engine.state();
    let contacts = engine.contacts();
    let mut more = diff
        .as_ref()
        .map_or_else(Vec::new, |u| u.guarantees(prepared.margin()));
    if !world.is_empty() {
        more.push(world.guarantee(prepared.margin()));
    }
    let Run {
        mut summary,
        samples,
        scan_events,
        mover_frames,
    } = d.finish_with(
        End {
            reached,
            time: t,
            final_distance: (x - prepared.truth.goal()).norm(),
            steps,
            rejected: 0,
            physics: Physics::Rapier,
        },
        more,
    );
    summary.diff = diff.map(|mut u| {
        u.report.final_yaw = engine.yaw();
        u.report
    });
    summary.physics_contacts = Some(contacts);
    if !world.is_empty() {
        summary.movers = Some(world.report);
    }
    summary.guarantees.push(Guarantee::new(
        Check::PhysicsContacts { contacts },
        contacts == 0,
    ));
    if model == Model::Dynamic {
        summary.guarantees.push(Guarantee::new(
            Check::PhysicsEngineEnergy {
                largest_rise: engine_rise,
            },
            true,
        ));
    }
    let max_deviation = builtin.map_or(0.0, |b| deviation(&samples, &b.samples));
    if builtin.is_some() {
        summary.guarantees.push(Guarantee::new(
            Check::PhysicsDeviation { max_deviation },
            true,
        ));
    }
    Ok((
        Run {
            summary,
            samples,
            scan_events,
            mover_frames,
        },
        RapierReport {
            contacts,
            max_deviation,
        },
    ))
}

/// Largest distance between two trajectories at the times of `a` (`b` linearly interpolated,
/// compared while both exist).
fn deviation(a: &[Sample], b: &[Sample]) -> f64 {
    let mut worst = 0.0f64;
    let mut j = 0;
    for s in a {
        while j + 1 < b.len() && b[j + 1].t < s.t {
            j += 1;
        }
        if j + 1 >= b.len() {
            break;
        }
        let (p, q) = (&b[j], &b[j + 1]);
        let w = ((s.t - p.t) / (q.t - p.t)).clamp(0.0, 1.0);
        let bx = Vector2::new(
            p.x[0] + w * (q.x[0] - p.x[0]),
            p.x[1] + w * (q.x[1] - p.x[1]),
        );
        worst = worst.max((Vector2::new(s.x[0], s.x[1]) - bx).norm());
    }
    worst
}
