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
use harmonav::{Controller, DEFAULT_DYNAMIC_PERIOD, DEFAULT_KINEMATIC_PERIOD, Mode, NavError};
use harmonav_scenario::{Model, Prepared};
use nalgebra::Vector2;

use crate::driver::{Driver, Warnings};
use crate::golden::held;
use crate::guarantee::{Check, FreeSpaceLoss, Guarantee};
use crate::monitor::End;
use crate::movers::MoverWorld;
use crate::summary::{Physics, Run, RunError};
use crate::trace::Event;
use crate::trajectory::Keep;

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
    let sc = &prepared.scenario;
    let h = prepared
        .control_period()
        .unwrap_or(match model.unwrap_or(sc.robot.model) {
            Model::Kinematic => DEFAULT_KINEMATIC_PERIOD,
            Model::Dynamic => DEFAULT_DYNAMIC_PERIOD,
        });
    let mut d = Driver::start(prepared, model, Some(h), 0.0, warnings, observer)?;
    let mut world = MoverWorld::new(&sc.sim.movers, prepared.truth.radius);
    // A state recorded every `sim.dt`, to the nearest period; every other period's end judged.
    let record_every = (sc.sim.dt / h).round().max(1.0) as usize;
    let (mut x, mut v) = (prepared.start(), Vector2::zeros());
    let (mut t, mut periods) = (0.0, 0usize);
    let mut reached = false;
    // The energy error of the last period (dynamic law), carried by the state that ends it.
    let mut drift = 0.0;
    // The command of the last period was changed by the filter (or refused): `V` may rise.
    let mut acted = false;
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
        let mut s = d.sample(t, x, v);
        s.energy_tolerance = std::mem::take(&mut drift);
        reached = d.arrived(x);
        if periods % record_every == 0 || reached {
            let keep = if reached { Keep::Pinned } else { Keep::Grid };
            d.record(s, keep, acted);
        } else {
            d.judge_event(&s, acted);
        }
        if reached || t >= sc.sim.max_time {
            break;
        }
        // Sensing at the period's start: discoveries, a lidar's scans when due.
        let found = d.sees(x, v);
        let mut discovered = !found.is_empty();
        if discovered && !d.discover(t, &found, x, v) {
            break;
        }
        if d.scan_due(t) {
            match d.scan(d.sample(t, x, v), x, v) {
                None => break,
                Some(changed) => discovered |= changed,
            }
        }
        if discovered {
            d.record(d.sample(t, x, v), Keep::Pinned, true);
        }
        // Waiting for a mover is not a stall.
        if d.at_rest(t, x, false, discovered || acted, reached) {
            break;
        }
        if filter {
            d.nav_mut().set_movers(world.reports())?;
        }
        let (command, mode) = match d.nav_mut().command(x, v) {
            Ok(c) => (c.value, Some(c.mode)),
            // The reported bodies overlap: no certified command; the robot stops.
            Err(NavError::InMover { .. }) => (-mass * v / h, None),
            Err(e) => return Err(e.into()),
        };
        let certified = mode
            .as_ref()
            .is_some_and(|m| !matches!(m, Mode::Overwhelmed { .. }));
        world.count(mode.as_ref());
        acted = !certified || matches!(mode, Some(Mode::Yielding { .. }));
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
        (x, v) = (x1, v1);
        periods += 1;
        t = periods as f64 * h;
    }
    if d.last_recorded() != Some(t) {
        d.record(d.sample(t, x, v), Keep::Pinned, acted);
    }
    let margin = prepared.margin();
    let movers = (!world.is_empty()).then(|| world.guarantee(margin));
    let mut run = d.finish_with(
        End {
            reached,
            time: t,
            final_distance: (x - prepared.truth.goal()).norm(),
            steps: periods,
            rejected: 0,
            physics: Physics::Builtin,
        },
        movers.into_iter().collect(),
    );
    if !world.is_empty() {
        run.summary.movers = Some(world.report);
    }
    Ok(run)
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
