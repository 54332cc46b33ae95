//! The held-command loop of a file with `[[movers]]` (issue 54, item 4; docs/movers.md §8):
//! the user's loop at the control period `h` (as [`crate::golden`] drives it), judged. At
//! every period the robot senses, the movers' reports are handed to the navigator
//! ([`harmonav::Navigator::set_movers`]), its command is held for `h` — `x += h·u`
//! (kinematic), `v += h·f/m, x += h·v` (dynamic, semi-implicit Euler) — and the movers advance
//! by their scripts; the monitor measures the exact least clearance along the period
//! ([`crate::movers`]). The built-in integrator's adaptive continuous law cannot hold a
//! command, which the mover filter certifies for exactly one period: a file with movers runs
//! here instead ([`crate::run::run`] comes here), and a file without movers never does.

use harmonav::control::{Dynamic, Potential};
use harmonav::tuning::{DEFAULT_DYNAMIC_PERIOD, DEFAULT_KINEMATIC_PERIOD};
use harmonav::{Controller, Mode, NavError};
use harmonav_scenario::{Model, Prepared, Truth};
use nalgebra::Vector2;

use crate::driver::{Driver, Warnings};
use crate::guarantee::{Check, FreeSpaceLoss, Guarantee};
use crate::monitor::End;
use crate::movers::{MoverWorld, Sweep, fleet_judged, peer_marks, peers, stop};
use crate::step::held;
use crate::summary::{Physics, Run, RunError};
use crate::trace::{Event, Sample};
use crate::trajectory::Keep;
use crate::unicycle::{Diff, pose_command};

/// The run of `prepared` (with `model`, or the file's) in the held-command loop with its
/// movers.
pub(crate) fn fly(
    prepared: &Prepared,
    model: Option<Model>,
    warnings: Warnings,
    observer: &mut dyn FnMut(Event<'_>),
) -> Result<Run, RunError> {
    fly_with(prepared, model, warnings, observer, true)
}

/// [`fly`]; `filter`: the movers are handed to the navigator (`false`: a negative control,
/// the robot blind to them, the movers still moved and judged).
pub(crate) fn fly_with(
    prepared: &Prepared,
    model: Option<Model>,
    warnings: Warnings,
    observer: &mut dyn FnMut(Event<'_>),
    filter: bool,
) -> Result<Run, RunError> {
    if !prepared.scenario.sim.robots.is_empty() {
        return fleet(prepared, model, warnings, observer, filter);
    }
    let sc = &prepared.scenario;
    let h = prepared
        .control_period()
        .unwrap_or(match model.unwrap_or(sc.robot.model) {
            Model::Kinematic => DEFAULT_KINEMATIC_PERIOD,
            Model::Dynamic => DEFAULT_DYNAMIC_PERIOD,
        });
    let mut d = Driver::start(prepared, model, Some(h), 0.0, warnings, observer)?;
    let mut world = MoverWorld::new(&sc.sim.movers, prepared.truth.radius);
    // A differential drive (`crate::unicycle`): its heading, and the monitors of its arcs.
    let mut diff = Diff::of(prepared.base(), prepared.start_yaw());
    // The last command turned a differential drive in place: not at rest.
    let mut turning = false;
    // How the last command was formed, for the movers' frames.
    let mut last_mode: Option<&'static str> = None;
    // A state recorded every `sim.dt`, to the nearest period; every other period's end judged.
    let record_every = (sc.sim.dt / h).round().max(1.0) as usize;
    let (mut x, mut v) = (prepared.start(), Vector2::zeros());
    let (mut t, mut periods) = (0.0, 0usize);
    let mut reached = false;
    // The energy error of the last period (dynamic law), carried by the state that ends it.
    let mut drift = 0.0;
    // The command of the last period was changed by the filter (or refused): `V` may rise.
    let mut acted = false;
    // The largest force held (the dynamic law), N: judged against a force bound.
    let mut max_force: f64 = 0.0;
    // A lower bound on the body's clearance along every held step ([`swept_clearance`]).
    let mut swept = f64::INFINITY;
    let mass = match d.nav().controller() {
        Controller::Dynamic(law) => law.mass(),
        Controller::Kinematic(_) => 1.0,
    };
    loop {
        if d.eval(x, v).is_none() && !d.recovering(x, v) {
            d.abort(Guarantee::failed(Check::LeftFreeSpace {
                time_s: t,
                position: [x.x, x.y],
                reason: FreeSpaceLoss::Left,
            }));
            break;
        }
        let mut s = state(&d, t, (x, v), diff.as_ref().map(|u| u.yaw));
        s.energy_tolerance = std::mem::take(&mut drift);
        reached = d.arrived(x);
        if periods % record_every == 0 || reached {
            let keep = if reached { Keep::Pinned } else { Keep::Grid };
            d.record(s, keep, acted);
        } else {
            d.judge_event(&s, acted);
        }
        if !world.is_empty() && d.movers_due(t) {
            d.movers(world.frame(t, x, last_mode, h));
        }
        if reached || t >= sc.sim.max_time {
            break;
        }
        if let Some(u) = &diff {
            d.set_heading(u.yaw);
        }
        // Sensing at the period's start: discoveries, a lidar's scans when due.
        let found = d.sees(x, v);
        let mut discovered = !found.is_empty();
        if discovered && !d.discover(t, &found, x, v) {
            break;
        }
        if d.scan_due(t) {
            match d.scan(state(&d, t, (x, v), diff.as_ref().map(|u| u.yaw)), x, v) {
                None => break,
                Some(changed) => discovered |= changed,
            }
        }
        if discovered {
            d.record(
                state(&d, t, (x, v), diff.as_ref().map(|u| u.yaw)),
                Keep::Pinned,
                true,
            );
        }
        // Waiting for a mover is not a stall, nor is turning in place.
        if d.at_rest(t, x, false, discovered || acted || turning, reached) {
            break;
        }
        if let Some(u) = diff.as_mut() {
            // The arc of `(v, ω)` held for `h`, judged along its length against the shapes
            // and, with movers, against every mover (`crate::movers::Sweep::Arc`).
            if filter && !world.is_empty() {
                d.nav_mut().set_movers(world.reports())?;
            }
            let yaw = u.yaw;
            let (c, mode) = pose_command(d.nav_mut(), x, yaw, !world.is_empty())?;
            turning = c.v == 0.0 && c.omega != 0.0;
            let x1;
            (x1, v) = u.period(&prepared.truth, x, &c, h);
            if !world.is_empty() {
                let certified = mode.is_some_and(|m| m.certified());
                world.count(mode.as_ref());
                last_mode = Some(mode.as_ref().map_or("refused", Mode::as_str));
                acted = !certified
                    || matches!(mode, Some(Mode::Yielding { .. } | Mode::Bounded { .. }));
                let arc = Sweep::Arc {
                    x,
                    yaw,
                    v: c.v,
                    omega: c.omega,
                };
                world.period_along(&arc, h, certified);
            }
            x = x1;
            periods += 1;
            t = periods as f64 * h;
            continue;
        }
        if filter {
            d.nav_mut().set_movers(world.reports())?;
        }
        let bound = d.nav().options().force_bound;
        let (command, mode) = match d.nav_mut().command(x, v) {
            Ok(c) => (c.value, Some(c.mode)),
            // The reported bodies overlap: no certified command; the robot stops (as hard as
            // its force bound lets it).
            Err(NavError::InMover { .. }) => (stop(mass, v, h, bound), None),
            Err(e) => return Err(e.into()),
        };
        if matches!(d.nav().controller(), Controller::Dynamic(_)) {
            max_force = max_force.max(command.norm());
        }
        let certified = mode.as_ref().is_some_and(|m| m.certified());
        world.count(mode.as_ref());
        last_mode = Some(mode.as_ref().map_or("refused", Mode::as_str));
        acted = !certified || matches!(mode, Some(Mode::Yielding { .. } | Mode::Bounded { .. }));
        let before = potential(&d, x, v);
        let (x1, v1) = match mode {
            Some(_) => held(d.nav().controller(), h, x, v, command),
            None => (x, Vector2::zeros()),
        };
        if let (Controller::Dynamic(law), Some(p0), Some(p1)) =
            (d.nav().controller(), before, potential(&d, x1, v1))
        {
            drift = euler_energy_error(law, h, (&p0, p1.value), (x, x1), (v, v1), command);
        }
        world.period(x, x1, h, certified);
        swept = swept.min(swept_clearance(&prepared.truth, x, x1));
        (x, v) = (x1, v1);
        periods += 1;
        t = periods as f64 * h;
    }
    if d.last_recorded() != Some(t) {
        d.record(
            state(&d, t, (x, v), diff.as_ref().map(|u| u.yaw)),
            Keep::Pinned,
            acted,
        );
    }
    let margin = prepared.margin();
    let mut more: Vec<Guarantee> = (!world.is_empty())
        .then(|| world.guarantee(margin))
        .into_iter()
        .collect();
    if let Some(u) = &diff {
        more.extend(u.guarantees(margin));
    }
    if let (Some(bound), Controller::Dynamic(_)) =
        (d.nav().options().force_bound, d.nav().controller())
    {
        more.push(crate::guarantee::force_within(max_force, bound));
    }
    // The straight held steps of a holonomic robot (a differential drive's arcs are judged by
    // its own monitors).
    if diff.is_none() {
        more.push(Guarantee::new(
            Check::NoCollisionBetweenStates {
                swept_clearance: swept,
            },
            swept > 0.0,
        ));
    }
    let mut run = d.finish_with(
        End {
            reached,
            time: t,
            final_distance: (x - prepared.truth.goal()).norm(),
            steps: periods,
            rejected: 0,
            physics: Physics::Builtin,
        },
        more,
    );
    if !world.is_empty() {
        run.summary.movers = Some(world.report);
    }
    run.summary.diff = diff.map(|u| u.report);
    Ok(run)
}

/// The state recorded at `t` at `(x, ẋ)`: [`Driver::sample`], and for a differential drive
/// (its heading `yaw` given) that heading and its velocity `ẋ = v·e(θ)` (the law's `u` is not
/// its motion).
pub(crate) fn state(
    d: &Driver,
    t: f64,
    (x, v): (Vector2<f64>, Vector2<f64>),
    yaw: Option<f64>,
) -> Sample {
    let mut s = d.sample(t, x, v);
    if yaw.is_some() {
        s.v = [v.x, v.y];
        s.yaw = yaw;
    }
    s
}

/// One robot of a fleet in flight.
struct Flying<'a, 'o> {
    d: Driver<'a, 'o>,
    world: MoverWorld,
    x: Vector2<f64>,
    v: Vector2<f64>,
    drift: f64,
    acted: bool,
    /// Arrived, stopped or lost: it holds still from here.
    done: bool,
    reached: bool,
    time: f64,
    speed: f64,
    mass: f64,
    /// How its last command was formed (the movers' frames).
    mode: Option<&'static str>,
    /// A differential drive: its heading and the monitors of its arcs (`None`: holonomic).
    diff: Option<Diff>,
    /// Its last command turned it in place (a differential drive): not at rest.
    turning: bool,
}

/// The scenario of robot `i` of a fleet (0: `[robot]`, then the `[[robots]]`): the file with
/// that start, goal and (a differential drive) start heading, no other robots, and its own
/// movers.
fn member(prepared: &Prepared, i: usize) -> Result<Prepared, RunError> {
    let mut sc = prepared.scenario.clone();
    if i > 0 {
        let r = &sc.sim.robots[i - 1];
        (sc.robot.start, sc.robot.goal) = (r.start, r.goal);
        if let Some(yaw) = r.yaw {
            sc.controller.yaw = Some(yaw);
        }
        // `[expect]` speaks of the first robot.
        sc.expect = None;
    }
    sc.sim.robots.clear();
    let path = std::path::PathBuf::from(&sc.name);
    sc.prepare(&path).map_err(|e| RunError::Robot {
        robot: i,
        problem: e.to_string(),
    })
}

/// A file with `[[robots]]`: every robot runs its own navigator in lockstep at the control
/// period, each given the scripted movers and the other robots (reciprocal, share ½, exact
/// positions; a robot that has arrived or stopped as a non-cooperative mover at rest). The
/// summary is the first robot's, with the others and the clearances between all of them in
/// its `fleet`, and the guarantee `no-collision-between-robots`. `filter: false` (a negative
/// control): no robot is given the movers or the other robots.
fn fleet(
    prepared: &Prepared,
    model: Option<Model>,
    warnings: Warnings,
    observer: &mut dyn FnMut(Event<'_>),
    filter: bool,
) -> Result<Run, RunError> {
    let sc = &prepared.scenario;
    let n = sc.sim.robots.len() + 1;
    let members: Vec<Prepared> = (0..n)
        .map(|i| member(prepared, i))
        .collect::<Result<_, _>>()?;
    let h = prepared
        .control_period()
        .unwrap_or(match model.unwrap_or(sc.robot.model) {
            Model::Kinematic => DEFAULT_KINEMATIC_PERIOD,
            Model::Dynamic => DEFAULT_DYNAMIC_PERIOD,
        });
    let record_every = (sc.sim.dt / h).round().max(1.0) as usize;
    let radius = prepared.truth.radius;
    let mut quiet: Vec<fn(Event<'_>)> = vec![|_| {}; n - 1];
    let mut observers: Vec<&mut dyn FnMut(Event<'_>)> = vec![observer];
    observers.extend(quiet.iter_mut().map(|f| f as &mut dyn FnMut(Event<'_>)));
    let mut robots = Vec::with_capacity(n);
    for (i, (p, o)) in members.iter().zip(observers).enumerate() {
        let d = Driver::start(
            p,
            model,
            Some(h),
            0.0,
            if i == 0 { warnings } else { Warnings::Skip },
            o,
        )?;
        let (speed, mass) = match d.nav().controller() {
            Controller::Dynamic(law) => (law.speed_bound(), law.mass()),
            Controller::Kinematic(law) => (law.v_max(), 1.0),
        };
        robots.push(Flying {
            d,
            world: MoverWorld::new(&sc.sim.movers, radius),
            x: p.start(),
            v: Vector2::zeros(),
            drift: 0.0,
            acted: false,
            done: false,
            reached: false,
            time: 0.0,
            speed,
            mass,
            mode: None,
            diff: Diff::of(p.base(), p.start_yaw()),
            turning: false,
        });
    }
    let mut report = crate::movers::FleetReport {
        min_robot_clearance: f64::INFINITY,
        ..Default::default()
    };
    let mut touching = vec![false; n * n];
    let mut periods = 0usize;
    let mut t = 0.0;
    loop {
        // Each robot's state judged and recorded; arrival and the end of time.
        for r in robots.iter_mut().filter(|r| !r.done) {
            let (x, v) = (r.x, r.v);
            if r.d.eval(x, v).is_none() && !r.d.recovering(x, v) {
                r.d.abort(Guarantee::failed(Check::LeftFreeSpace {
                    time_s: t,
                    position: [x.x, x.y],
                    reason: FreeSpaceLoss::Left,
                }));
                (r.done, r.time) = (true, t);
                continue;
            }
            let mut s = state(&r.d, t, (x, v), r.diff.as_ref().map(|u| u.yaw));
            s.energy_tolerance = std::mem::take(&mut r.drift);
            r.reached = r.d.arrived(x);
            if periods.is_multiple_of(record_every) || r.reached {
                let keep = if r.reached { Keep::Pinned } else { Keep::Grid };
                r.d.record(s, keep, r.acted);
            } else {
                r.d.judge_event(&s, r.acted);
            }
            if r.reached || t >= sc.sim.max_time {
                (r.done, r.time) = (true, t);
            }
        }
        let at: Vec<(Vector2<f64>, f64, bool)> =
            robots.iter().map(|r| (r.x, r.speed, r.done)).collect();
        // The first robot's frame, after its state: the scripted movers and the other robots
        // (reciprocal while they fly).
        if robots[0].d.movers_due(t) {
            let first = &mut robots[0];
            let mut frame = first.world.frame(t, first.x, first.mode, h);
            frame.movers.extend(peer_marks(&at[1..], radius, h));
            first.d.movers(frame);
        }
        if robots.iter().all(|r| r.done) {
            break;
        }
        // How each robot moves over the period, and whether its command was certified.
        let mut next: Vec<(Sweep, bool)> = Vec::with_capacity(n);
        for (i, r) in robots.iter_mut().enumerate() {
            let still = Sweep::Straight(r.x, r.x);
            if r.done {
                next.push((still, true));
                continue;
            }
            let (x, v) = (r.x, r.v);
            let yaw = r.diff.as_ref().map(|u| u.yaw);
            if let Some(yaw) = yaw {
                r.d.set_heading(yaw);
            }
            let found = r.d.sees(x, v);
            let mut discovered = !found.is_empty();
            if discovered && !r.d.discover(t, &found, x, v) {
                (r.done, r.time) = (true, t);
                next.push((still, true));
                continue;
            }
            if r.d.scan_due(t) {
                match r.d.scan(state(&r.d, t, (x, v), yaw), x, v) {
                    None => {
                        (r.done, r.time) = (true, t);
                        next.push((still, true));
                        continue;
                    }
                    Some(changed) => discovered |= changed,
                }
            }
            if discovered {
                r.d.record(state(&r.d, t, (x, v), yaw), Keep::Pinned, true);
            }
            if r.d
                .at_rest(t, x, false, discovered || r.acted || r.turning, false)
            {
                (r.done, r.time) = (true, t);
                next.push((still, true));
                continue;
            }
            if filter {
                let movers = r.world.reports_with(peers(&at, i, radius));
                r.d.nav_mut().set_movers(movers)?;
            }
            if let Some(u) = r.diff.as_mut() {
                // A differential drive: the arc of its `(v, ω)`, judged along its length.
                let yaw = u.yaw;
                let (c, mode) = pose_command(r.d.nav_mut(), x, yaw, true)?;
                let certified = mode.is_some_and(|m| m.certified());
                r.turning = c.v == 0.0 && c.omega != 0.0;
                r.world.count(mode.as_ref());
                r.mode = Some(mode.as_ref().map_or("refused", Mode::as_str));
                r.acted = !certified
                    || matches!(mode, Some(Mode::Yielding { .. } | Mode::Bounded { .. }));
                let (x1, v1) = u.period(&prepared.truth, x, &c, h);
                let arc = Sweep::Arc {
                    x,
                    yaw,
                    v: c.v,
                    omega: c.omega,
                };
                r.world.period_along(&arc, h, certified);
                (r.x, r.v) = (x1, v1);
                next.push((arc, certified));
                continue;
            }
            let (command, mode) = match r.d.nav_mut().command(x, v) {
                Ok(c) => (c.value, Some(c.mode)),
                Err(NavError::InMover { .. }) => {
                    let bound = r.d.nav().options().force_bound;
                    (stop(r.mass, v, h, bound), None)
                }
                Err(e) => return Err(e.into()),
            };
            let certified = mode.as_ref().is_some_and(|m| m.certified());
            r.world.count(mode.as_ref());
            r.mode = Some(mode.as_ref().map_or("refused", Mode::as_str));
            r.acted =
                !certified || matches!(mode, Some(Mode::Yielding { .. } | Mode::Bounded { .. }));
            let before = potential(&r.d, x, v);
            let (x1, v1) = match mode {
                Some(_) => held(r.d.nav().controller(), h, x, v, command),
                None => (x, Vector2::zeros()),
            };
            if let (Controller::Dynamic(law), Some(p0), Some(p1)) =
                (r.d.nav().controller(), before, potential(&r.d, x1, v1))
            {
                r.drift = euler_energy_error(law, h, (&p0, p1.value), (x, x1), (v, v1), command);
            }
            r.world.period(x, x1, h, certified);
            (r.x, r.v) = (x1, v1);
            next.push((Sweep::Straight(x, x1), certified));
        }
        // Every two robots along the period (exact for straight steps, within
        // `ARC_TOLERANCE` below the truth along arcs).
        report.period(&next, &mut touching, radius, h);
        periods += 1;
        t = periods as f64 * h;
    }
    let margin = prepared.margin();
    // The others first (the first robot's guarantee counts those that lost one of theirs),
    // with their recorded states.
    let mut others: Vec<(crate::summary::Summary, Vec<Sample>)> = Vec::with_capacity(n - 1);
    let mut first = None;
    for (i, r) in robots.into_iter().enumerate().rev() {
        let Flying {
            mut d,
            world,
            x,
            v,
            acted,
            reached,
            time,
            diff,
            ..
        } = r;
        if d.last_recorded() != Some(time) {
            let yaw = diff.as_ref().map(|u| u.yaw);
            d.record(state(&d, time, (x, v), yaw), Keep::Pinned, acted);
        }
        let mut extra: Vec<Guarantee> = Vec::new();
        if !world.is_empty() {
            extra.push(world.guarantee(margin));
        }
        if let Some(u) = &diff {
            extra.extend(u.guarantees(margin));
        }
        if i == 0 {
            let others_unsafe = others.iter().filter(|(s, _)| !s.safe()).count();
            extra.push(fleet_judged(&report, n, others_unsafe));
        }
        let goal = d.nav().goal();
        let mut run = d.finish_with(
            End {
                reached,
                time,
                final_distance: (x - goal).norm(),
                steps: periods,
                rejected: 0,
                physics: Physics::Builtin,
            },
            extra,
        );
        run.summary.movers = (!world.is_empty()).then(|| world.report.clone());
        run.summary.diff = diff.map(|u| u.report);
        if i == 0 {
            first = Some(run);
        } else {
            others.push((run.summary, run.samples));
        }
    }
    let mut first = first.ok_or(RunError::StartNotFree)?;
    report.others = others
        .into_iter()
        .rev()
        .zip(&sc.sim.robots)
        .map(|((s, samples), r)| crate::movers::FleetRobot {
            start: r.start,
            goal: r.goal,
            reached: s.reached,
            time_s: s.time_s,
            final_distance: s.final_distance,
            safe: s.safe(),
            movers: s.movers,
            samples,
        })
        .collect();
    first.summary.fleet = Some(report);
    Ok(first)
}

/// The most halvings of a held step [`swept_clearance`] makes where its bound is not positive.
const SWEPT_HALVINGS: u32 = 20;

/// A lower bound on the robot disc's clearance from the true obstacles and boundary along the
/// straight step from `a` to `b` (`no-collision-between-states`, as a floor plan's): the
/// clearance `c` (a signed distance less the radius) is 1-Lipschitz, so a segment of length
/// `L` from `c₀` to `c₁` keeps at least `(c₀ + c₁ − L)/2`. Where that is not positive the step
/// is halved (up to [`SWEPT_HALVINGS`] times) and each half bounded alike: the bound tightens
/// to the true least clearance, so a step that is clear is found clear unless it grazes a
/// shape within `2⁻²⁰` of its length.
pub(crate) fn swept_clearance(truth: &Truth, a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    let c = |x: Vector2<f64>| {
        let (obstacle, boundary) = truth.clearances(x);
        obstacle.min(boundary)
    };
    fn bound(
        c: &dyn Fn(Vector2<f64>) -> f64,
        (a, ca): (Vector2<f64>, f64),
        (b, cb): (Vector2<f64>, f64),
        halvings: u32,
    ) -> f64 {
        let lower = 0.5 * (ca + cb - (b - a).norm());
        if lower > 0.0 || halvings == 0 {
            return lower;
        }
        let m = 0.5 * (a + b);
        let cm = c(m);
        bound(c, (a, ca), (m, cm), halvings - 1).min(bound(c, (m, cm), (b, cb), halvings - 1))
    }
    bound(&c, (a, c(a)), (b, c(b)), SWEPT_HALVINGS)
}

/// `Ψ` and `∇Ψ` of the dynamic law at `(x, ẋ)` (`None` for the kinematic law or outside the
/// free space).
pub(crate) fn potential(d: &Driver, x: Vector2<f64>, v: Vector2<f64>) -> Option<Potential> {
    let Controller::Dynamic(law) = d.nav().controller() else {
        return None;
    };
    let e = d.eval(x, v)?;
    Some(law.potential(d.nav().field(), &e.field))
}

/// **rapier's error model**: how much one semi-implicit Euler step of length `h` changes
/// `V = μΨ + ½m|ẋ|²` (`μ` standing for the law's pull `μ_p`, `Dynamic::pull`) beyond the
/// work of the non-conservative force, from `(x, v)` to
/// `(x', v')` under the force `f` held over the step (`v' = v + h f/m`, `x' = x + h v'`,
/// rapier's integration of a free body). Exactly, by algebra,
///
/// ```text
/// V' − V = h v'·(f + μ∇Ψ(x))                       (the work of f + μ∇Ψ: ≤ 0 for the law)
///        − h²|f|²/(2m)                             (the step's kinetic error)
///        + μ(Ψ(x') − Ψ(x) − ∇Ψ(x)·(x' − x))          (the potential's second-order remainder)
/// ```
///
/// The first term is the law's: the navigator's hold damps implicitly, `f + μ∇Ψ = −λv'`
/// (and a cap only shortens `v'`, `m|v'|²(1 − a/s) ≤ 0` with `a ≥ 1 ≥ s`), so it is never
/// positive. The other two are the integrator's, `O(h²)` per step, and large where `Ψ` curves
/// hard: a robot passing 1 mm from a disc (`scenarios/shapes/grid-12-dynamic.toml`) rose by
/// 1.2e-5·V per recorded state against the former flat allowance of 5e-7·V. Returned: their
/// positive part, plus the rounding of the `f64` terms (`16ε` of their sizes). The monitor
/// then judges the law's term on the states rapier made; a controller that pumps energy in
/// (`f = −μ∇Ψ + c·ẋ`, `c > 0`) still fails it.
pub(crate) fn euler_energy_error(
    law: &Dynamic,
    h: f64,
    (p0, psi1): (&Potential, f64),
    (x0, x1): (Vector2<f64>, Vector2<f64>),
    (v0, v1): (Vector2<f64>, Vector2<f64>),
    f: Vector2<f64>,
) -> f64 {
    let (m, mu) = (law.mass(), law.pull());
    let kinetic = -0.5 * h * h / m * f.norm_squared();
    let remainder = mu * (psi1 - p0.value - p0.gradient.dot(&(x1 - x0)));
    let size = mu * (p0.value.abs() + psi1.abs())
        + m * (v0.norm_squared() + v1.norm_squared())
        + h * h / m * f.norm_squared()
        + mu * (p0.gradient.norm() * (x1 - x0).norm());
    (kinetic + remainder).max(0.0) + 16.0 * f64::EPSILON * size
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use harmonav::transform::random::Rng;
    use harmonav_scenario::Scenario;

    use super::*;

    /// `no-collision-between-states` in a star world (issue 51, item 2): against the body's
    /// clearance at 201 points of each of 800 seeded steps past a tilted ellipse and the
    /// boundary, the bound never exceeds the least sampled clearance, and where that is above
    /// 1 mm it is positive (the halving finds the step clear). Negative control: a step whose
    /// ends are both 0.25 m clear but which passes through the ellipse (what the monitors at
    /// the states alone miss) is bounded below 0.
    #[test]
    fn the_swept_clearance_bounds_the_step_and_catches_one_through_a_shape() {
        let text = r#"
name = "swept"
[workspace]
type = "circle"
center = [0.0, 0.0]
radius = 3.0
[[obstacles]]
type = "ellipse"
center = [0.0, 0.0]
semi_axes = [1.0, 0.4]
angle_deg = 20.0
[robot]
model = "kinematic"
start = [-2.0, 0.0]
goal = [2.0, 0.0]
radius = 0.2
margin = 0.05
"#;
        let path = Path::new("swept.toml");
        let p = Scenario::parse(path, text).unwrap().prepare(path).unwrap();
        let truth = &p.truth;
        let c = |x: Vector2<f64>| {
            let (o, b) = truth.clearances(x);
            o.min(b)
        };
        let mut rng = Rng::new(11);
        let (mut clear, mut found) = (0, 0);
        for _ in 0..800 {
            let a = Vector2::new(rng.uniform(-2.5, 2.5), rng.uniform(-2.0, 2.0));
            let turn = rng.uniform(0.0, std::f64::consts::TAU);
            let b = a + rng.uniform(0.01, 0.6) * Vector2::new(turn.cos(), turn.sin());
            if c(a) <= 0.0 || c(b) <= 0.0 {
                continue;
            }
            let least = (0..=200)
                .map(|i| c(a + (f64::from(i) / 200.0) * (b - a)))
                .fold(f64::INFINITY, f64::min);
            let bound = swept_clearance(truth, a, b);
            assert!(bound <= least + 1e-12, "{a:?} → {b:?}: {bound} > {least}");
            if least > 1e-3 {
                clear += 1;
                found += usize::from(bound > 0.0);
            }
        }
        assert!(clear > 300 && found == clear, "{found} of {clear}");
        let (a, b) = (Vector2::new(0.0, 0.9), Vector2::new(0.0, -0.9));
        assert!(c(a) > 0.2 && c(b) > 0.2, "{} {}", c(a), c(b));
        assert!(swept_clearance(truth, a, b) < 0.0);
    }
}
