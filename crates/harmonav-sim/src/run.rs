//! The built-in integrator: it advances the state between the driver's calls
//! (`driver.rs`: sensing, recording, stopping, the monitors).
//!
//! Both robot models are integrated with the Bogacki–Shampine 3(2) pair and step-size
//! control (`sim.dt` is the largest step and the recording interval). The dynamic law is stiff
//! near walls (`|∇Ψ|` grows without bound, maths.md §4 pitfall B), so a step any of whose stages
//! leaves the free space is rejected and retried smaller. After each accepted step the sector
//! is checked against the unknown obstacles; a discovery is located within the step by
//! bisection on the cubic Hermite interpolant of the step, the state is cut there, and only
//! then do `Θ`, `k` and `λ` change (Carathéodory solutions). Runs are deterministic.

use harmonav::{Controller, Evaluation};
use harmonav_scenario::{Model, Prepared, Truth};
use nalgebra::Vector2;

use crate::driver::{Driver, Warnings};
use crate::guarantee::{Check, FreeSpaceLoss, Guarantee};
use crate::monitor::End;
use crate::summary::{Physics, Run, RunError};
use crate::trace::Event;
use crate::trajectory::Keep;

type State = [f64; 4];

fn pos(y: &State) -> Vector2<f64> {
    Vector2::new(y[0], y[1])
}

fn vel(y: &State) -> Vector2<f64> {
    Vector2::new(y[2], y[3])
}

fn axpy(y: &State, h: f64, ks: &[(f64, &State)]) -> State {
    let mut out = *y;
    for (c, k) in ks {
        for i in 0..4 {
            out[i] += h * c * k[i];
        }
    }
    out
}

/// Cubic Hermite interpolation of the step `y0 → y1` (derivatives `d0`, `d1`) at `s ∈ [0, 1]`.
fn hermite(y0: &State, d0: &State, y1: &State, d1: &State, h: f64, s: f64) -> State {
    let (s2, s3) = (s * s, s * s * s);
    let (h00, h10, h01, h11) = (
        2.0 * s3 - 3.0 * s2 + 1.0,
        s3 - 2.0 * s2 + s,
        -2.0 * s3 + 3.0 * s2,
        s3 - s2,
    );
    let mut out = [0.0; 4];
    for i in 0..4 {
        out[i] = h00 * y0[i] + h10 * h * d0[i] + h01 * y1[i] + h11 * h * d1[i];
    }
    out
}

/// `ẏ` of the closed loop at `y` with the law's evaluation; `None` outside the free space of
/// the known obstacles.
fn rhs(d: &Driver, y: &State) -> Option<(State, Evaluation)> {
    let (x, v) = (pos(y), vel(y));
    let e = d.eval(x, v)?;
    let dy = match d.nav().controller() {
        Controller::Kinematic(_) => [e.command.x, e.command.y, 0.0, 0.0],
        Controller::Dynamic(law) => {
            let a = e.command / law.mass();
            [v.x, v.y, a.x, a.y]
        }
    };
    Some((dy, e))
}

/// `ẏ` at `y` after `Θ`, `k` and `λ` may have changed (a step's end, a discovery, a scan
/// event): `Some(Some(ẏ))`; `Some(None)` when `y` is in a known obstacle's margin band, where
/// the law has no value and the navigator's held command leads out ([`band_step`]); `None`
/// when `y` is outside the known free space and not in a band, and the guarantee
/// `stayed-in-free-space` is lost (the run must stop).
fn rhs_after_event(d: &mut Driver, t: f64, y: &State) -> Option<Option<State>> {
    if let Some((dy, _)) = rhs(d, y) {
        return Some(Some(dy));
    }
    if d.recovering(pos(y), vel(y)) {
        return Some(None);
    }
    d.abort(Guarantee::failed(Check::LeftFreeSpace {
        time_s: t,
        position: [y[0], y[1]],
        reason: FreeSpaceLoss::Left,
    }));
    None
}

/// One step of the sampled-data loop out of a margin band (a scan event that grew a shape over
/// the robot's margin, docs/maths.md §12.12): the navigator's held command for its control
/// period `h` ([`harmonav::Mode::Recovering`], along the ray from the shape's centre), the
/// kinematic robot moved by `h·u`, the dynamic one by semi-implicit Euler (`v⁺ = v + h f/m`,
/// the command's own model: `v⁺` lies along the way out). The continuous law has no value in
/// the band, so the error-controlled integrator cannot take these steps. `None` when the
/// navigator gives no command there.
fn band_step(d: &mut Driver, y: &State) -> Option<(f64, State)> {
    let (x, v) = (pos(y), vel(y));
    let h = d.nav().control_period();
    let f = d.nav_mut().command(x, v).ok()?.value;
    Some(match d.nav().controller() {
        Controller::Kinematic(_) => {
            let x1 = x + h * f;
            (h, [x1.x, x1.y, 0.0, 0.0])
        }
        Controller::Dynamic(law) => {
            let v1 = v + (h / law.mass()) * f;
            let x1 = x + h * v1;
            (h, [x1.x, x1.y, v1.x, v1.y])
        }
    })
}

/// The most steps [`barrier_layer`] takes to cross one barrier layer (a crossing takes a few
/// hundred; the cap stops a map that does not come out, which then fails as a step collapse).
const LAYER_MAX_STEPS: usize = 100_000;

/// How far out [`barrier_layer`] leaves the robot: `LAYER_EXIT·r₀`, `r₀` the distance at which
/// the steps collapsed (about 1e-12 m: 2¹⁰ times that is a thousand times the spacing of `f64`
/// positions in a 100 m world, where the steps of the ordinary integration go on).
const LAYER_EXIT: f64 = 1024.0;

/// How closely the field must scale like `1/r` for [`barrier_layer`] to apply: `|∇Θ|` at
/// `r₀` over `|∇Θ|` at `2r₀` within this of 2.
const LAYER_SCALING: f64 = 0.02;

/// The robot's state after it crossed a barrier layer: `(x, ẋ)` at `LAYER_EXIT·r₀` on the way
/// out, and the duration of the crossing.
struct Crossing {
    y: State,
    duration: f64,
}

/// The distance `r₀` from `x` to the barrier whose gradient `|∇Θ|` grows like `1/r` along `n`:
/// from `|∇Θ(x)|/|∇Θ(x − δn)| = (r₀ + δ)/r₀` with `δ` grown until the ratio is at least 2;
/// `None` where `|∇Θ|` does not scale like `1/r` within [`LAYER_SCALING`].
fn layer_depth(d: &Driver, x: Vector2<f64>, v: Vector2<f64>, n: Vector2<f64>) -> Option<f64> {
    let grad = |p: Vector2<f64>| Some(d.eval(p, v)?.field.gradient.norm());
    let g0 = grad(x)?;
    let mut delta = 1e-13 * x.norm().max(1.0);
    for _ in 0..12 {
        let p = x - delta * n;
        // The step actually taken along n, after rounding.
        let step = (x - p).dot(&n);
        let ratio = g0 / grad(p)?;
        if ratio >= 2.0 {
            let r0 = step / (ratio - 1.0);
            // The check: at twice r₀, half the gradient.
            let p2 = x - r0 * n;
            let check = g0 / grad(p2)? * r0 / (x - p2).dot(&n).max(f64::MIN_POSITIVE);
            return (r0 > 0.0 && (check - 2.0).abs() < 2.0 * LAYER_SCALING).then_some(r0);
        }
        delta *= 4.0;
    }
    None
}

/// The dynamic robot's crossing of an obstacle's barrier layer that it entered at `y`, where
/// the step size collapsed (climbing `Θ`, or sliding along the shape too slowly outwards for
/// steps of `x` to resolve); `None` where the crossing does not apply (a kinematic robot, a
/// field that does not scale like `1/r` there, or a crossing that does not come out in
/// [`LAYER_MAX_STEPS`]): the run then fails as before.
///
/// Why (issue 51, "a valid run that cannot be judged"): `phi_k` rises by `(2/k)·ln(1/r)` at a
/// distance `r` from a known grown shape, so with `k = 6(n + 1)` = 6 006 for 1 000 known
/// obstacles `Θ` barely changes near a shape (`phi` 7.6307 → 7.6363 from `r` = 1e-4 to
/// 1e-11 m) and every term of the dynamic law (the pull `μ_p∇Ψ`, `λ(x)`, the uphill brake,
/// the governor) grows like `1/r`: measured, `λ·r` = 9.45e-4 kg·m/s within 0.3 % from
/// `r` = 1e-3 to 1e-11 m. The brake then takes off a fixed speed per e-fold of `r` (0.07 m/s
/// there), and a robot that enters at 2.5 m/s turns round about 1e-19 m from the grown shape,
/// far below the spacing of `f64` positions (7e-15 m at 37 m from the origin). No method that
/// steps `x` can follow that solution; Bogacki–Shampine's steps fell below 1e-14 s at
/// `r` ≈ 1e-12 m.
///
/// Where `f(x, ẋ) = (r₀/r)·f(x₀, ẋ)` (checked: [`layer_depth`]), the stretched time
/// `dt = (r/r₀) ds` (Sundman's) takes the singularity out:
///
/// ```text
/// m dẋ/ds = f(x₀, ẋ),   dD/ds = ẋ·n,   r = r₀·e^{−D/r₀},   dt/ds = e^{−D/r₀},
/// dx/ds = ẋ·e^{−D/r₀}
/// ```
///
/// (`n = ∇Θ/|∇Θ|` at `x₀`, towards the shape): the velocity follows the law's force at the
/// frozen point `x₀` and the depth is `ln(r₀/r) = D/r₀`. It is integrated by the same
/// Bogacki–Shampine pair and tolerance until the robot is back out at `LAYER_EXIT·r₀`, where
/// positions are resolved again. The pull's work is `−μ_p|∇Ψ|r·∫dD/r₀`, zero in and out at
/// the same depth, and the damping's is negative, so `V = μ_pΨ + ½m|ẋ|²` does not grow: the
/// guarantees are judged on the states as before. What the crossing leaves out is the drift of
/// `r·f` with the depth (`phi` grows by `2/k` per e-fold: 0.3 % over the decades measured). It
/// is tried only where the step size collapsed, so it changes no run that was integrated
/// before.
fn barrier_layer(d: &Driver, y: &State, h0: f64, tol: f64) -> Option<Crossing> {
    let Controller::Dynamic(_) = d.nav().controller() else {
        return None;
    };
    let (x, v0) = (pos(y), vel(y));
    let n = -d.eval(x, v0)?.field.direction?;
    let r0 = layer_depth(d, x, v0, n)?;
    let exit = -LAYER_EXIT.ln() * r0;
    // z = (ẋ, D, t, x − x₀).
    let g = |z: &[f64; 6]| -> Option<[f64; 6]> {
        let (dy, _) = rhs(d, &[x.x, x.y, z[0], z[1]])?;
        let stretch = (-z[2] / r0).exp();
        Some([
            dy[2],
            dy[3],
            z[0] * n.x + z[1] * n.y,
            stretch,
            z[0] * stretch,
            z[1] * stretch,
        ])
    };
    let step = |z: &[f64; 6], c: &[(f64, &[f64; 6])], h: f64| {
        let mut out = *z;
        for (ci, ki) in c {
            for i in 0..6 {
                out[i] += h * ci * ki[i];
            }
        }
        out
    };
    let (mut z, mut h) = ([v0.x, v0.y, 0.0, 0.0, 0.0, 0.0], h0);
    let mut k1 = g(&z)?;
    for _ in 0..LAYER_MAX_STEPS {
        let k2 = g(&step(&z, &[(0.5, &k1)], h))?;
        let k3 = g(&step(&z, &[(0.75, &k2)], h))?;
        let z1 = step(
            &z,
            &[(2.0 / 9.0, &k1), (1.0 / 3.0, &k2), (4.0 / 9.0, &k3)],
            h,
        );
        let k4 = g(&z1)?;
        let e = step(
            &[0.0; 6],
            &[
                (-5.0 / 72.0, &k1),
                (1.0 / 12.0, &k2),
                (1.0 / 9.0, &k3),
                (-1.0 / 8.0, &k4),
            ],
            h,
        );
        // The state's error, as in the ordinary steps, and the depth's relative to r₀.
        let err = (e[0] * e[0] + e[1] * e[1] + e[4] * e[4] + e[5] * e[5]).sqrt()
            + (e[2] / r0).abs() * tol;
        if err > tol {
            h *= (0.9 * (tol / err).cbrt()).clamp(0.1, 0.9);
            continue;
        }
        if z1[2] <= exit {
            // Out at LAYER_EXIT·r₀: the crossing of D = exit within the step, linearly.
            let a = (z[2] - exit) / (z[2] - z1[2]);
            let w = |i: usize| z[i] + a * (z1[i] - z[i]);
            return Some(Crossing {
                y: [x.x + w(4), x.y + w(5), w(0), w(1)],
                duration: w(3),
            });
        }
        (z, k1) = (z1, k4);
        h *= (0.9 * (tol / err.max(1e-300)).cbrt()).clamp(0.2, 5.0);
    }
    None
}

/// Runs a prepared scenario with the built-in integrator; `model` overrides the file's robot
/// model.
pub fn run(prepared: &Prepared, model: Option<Model>) -> Result<Run, RunError> {
    run_observed(prepared, model, &mut |_| {})
}

/// [`run`], handing every recorded state and every discovery to `observer` as they are made
/// (to stream a recording of a run of any length; [`Run::samples`] keeps a bounded subset).
pub fn run_observed(
    prepared: &Prepared,
    model: Option<Model>,
    observer: &mut dyn FnMut(Event<'_>),
) -> Result<Run, RunError> {
    integrate(prepared, model, Warnings::Skip, observer)
}

/// A file with `[[movers]]` run with the robot blind to them: its navigator is never given the
/// movers ([`harmonav::Navigator::set_movers`]), while they still move and every contact is
/// judged; in a file with `[[robots]]`, every robot blind to the movers and to the others. The
/// negative control of the mover filter: such a run records contacts that the filtered run
/// ([`run`]) does not.
pub fn run_without_filter(prepared: &Prepared, model: Option<Model>) -> Result<Run, RunError> {
    crate::held::fly_with(prepared, model, Warnings::Skip, &mut |_| {}, false)
}

/// The built-in run, with the scenario's warnings or without ([`Warnings`]); a file with
/// `[[movers]]` or a differential-drive base runs in the held-command loop (`held.rs`).
pub(crate) fn integrate(
    prepared: &Prepared,
    model: Option<Model>,
    warnings: Warnings,
    observer: &mut dyn FnMut(Event<'_>),
) -> Result<Run, RunError> {
    if !(prepared.scenario.sim.movers.is_empty() && prepared.scenario.sim.robots.is_empty())
        || prepared.base().is_some()
        || prepared.scenario.controller.force_bound.is_some()
    {
        // Movers need the command held for the period their filter certifies; a differential
        // drive's `(v, ω)` is certified on the arc it sweeps in one period; a force bound's
        // braking certificate is the held command's.
        return crate::held::fly(prepared, model, warnings, observer);
    }
    let sc = &prepared.scenario;
    let step_tol = step_tolerance(&prepared.truth);
    let mut d = Driver::start(prepared, model, None, step_tol, warnings, observer)?;
    let start = prepared.start();
    let mut y: State = [start.x, start.y, 0.0, 0.0];

    let (dt, max_time) = (sc.sim.dt, sc.sim.max_time);
    let mut t = 0.0;
    let mut h = dt.min(1e-3);
    let (mut steps, mut rejected) = (0usize, 0usize);
    // A barrier layer was crossed ([`barrier_layer`]) and no step accepted since: a second
    // collapse there fails the run.
    let mut layered = false;
    d.record(d.sample(t, pos(&y), vel(&y)), Keep::Pinned, false);
    let mut next_record = dt;
    let (k0, _) = rhs(&d, &y).ok_or(RunError::StartNotFree)?;
    // `ẏ` at `y`; `None` while the robot is in a margin band ([`rhs_after_event`]).
    let mut k1 = Some(k0);
    let mut reached = d.arrived(pos(&y));
    while !reached && t < max_time {
        // A lidar scans at t = n / rate_hz; the steps land on those times.
        if d.scan_due(t) {
            let pre = d.sample(t, pos(&y), vel(&y));
            match d.scan(pre, pos(&y), vel(&y)) {
                None => break,
                Some(false) => {}
                Some(true) => {
                    let Some(k_next) = rhs_after_event(&mut d, t, &y) else {
                        break;
                    };
                    k1 = k_next;
                    d.record(d.sample(t, pos(&y), vel(&y)), Keep::Pinned, true);
                    d.at_rest(t, pos(&y), false, true, false);
                }
            }
        }
        let Some(k1_law) = k1 else {
            // In a margin band: the held command's step of the control period (a scan that
            // falls due within it is taken at its end).
            let Some((h_band, y_band)) = band_step(&mut d, &y) else {
                rhs_after_event(&mut d, t, &y);
                break;
            };
            (y, t) = (y_band, t + h_band);
            steps += 1;
            // The `dt` grid resumes after the way out (its states are recorded below).
            while next_record <= t + 1e-12 {
                next_record += dt;
            }
            let Some(k_next) = rhs_after_event(&mut d, t, &y) else {
                break;
            };
            k1 = k_next;
            // Each state of the way out is recorded on the grid (a band may last many periods;
            // pinned states are bounded per event) and judged as a discovery's second side:
            // `Θ` and `V` have no value in the band, and take a new one where it ends. The
            // stall rule sees these steps: a way out that makes no progress (a recovery of
            // length 0 at the band's edge) stops a kinematic run instead of spinning on.
            d.record(d.sample(t, pos(&y), vel(&y)), Keep::Grid, true);
            reached = d.arrived(pos(&y));
            if d.at_rest(t, pos(&y), false, false, reached) {
                break;
            }
            continue;
        };
        h = h.min(dt).min(max_time - t);
        if let Some(next) = d.next_scan() {
            h = h.min(next - t);
        }
        if h < 1e-14 && max_time - t >= 1e-14 && !layered {
            // The robot may be in an obstacle's barrier layer thinner than `f64` resolves:
            // cross it in the stretched time ([`barrier_layer`]), once per collapse.
            if let Some(c) = barrier_layer(&d, &y, h.max(1e-14), step_tol) {
                d.record(d.sample(t, pos(&y), vel(&y)), Keep::Pinned, false);
                (y, t) = (c.y, t + c.duration);
                while next_record <= t + 1e-12 {
                    next_record += dt;
                }
                let Some(k_next) = rhs_after_event(&mut d, t, &y) else {
                    break;
                };
                k1 = k_next;
                d.record(d.sample(t, pos(&y), vel(&y)), Keep::Pinned, false);
                (h, layered) = (c.duration.max(1e-14), true);
                continue;
            }
        }
        if h < 1e-14 {
            if max_time - t >= 1e-14 {
                // Step-size collapse: the run cannot go on, and must not pass as a mere
                // "not reached".
                d.abort(Guarantee::failed(Check::StepCollapsed {
                    time_s: t,
                    position: [y[0], y[1]],
                }));
            }
            break;
        }
        let dr = &d;
        let stages = (|| {
            let (k2, _) = rhs(dr, &axpy(&y, h, &[(0.5, &k1_law)]))?;
            let (k3, _) = rhs(dr, &axpy(&y, h, &[(0.75, &k2)]))?;
            let y1 = axpy(
                &y,
                h,
                &[(2.0 / 9.0, &k1_law), (1.0 / 3.0, &k2), (4.0 / 9.0, &k3)],
            );
            let (k4, _) = rhs(dr, &y1)?;
            let e = axpy(
                &[0.0; 4],
                h,
                &[
                    (-5.0 / 72.0, &k1_law),
                    (1.0 / 12.0, &k2),
                    (1.0 / 9.0, &k3),
                    (-1.0 / 8.0, &k4),
                ],
            );
            let err = e.iter().map(|v| v * v).sum::<f64>().sqrt();
            Some((y1, k4, err))
        })();
        let Some((y1, k4, err)) = stages.filter(|s| s.2 <= step_tol) else {
            rejected += 1;
            h *= match stages {
                Some((_, _, err)) => (0.9 * (step_tol / err).cbrt()).clamp(0.1, 0.9),
                None => 0.25,
            };
            continue;
        };
        // Discovery within the step: the earliest s ∈ (0, 1] where the sector sees a new obstacle.
        let sees = |y: &State| d.sees(pos(y), vel(y));
        let (mut s_end, mut found) = (1.0, sees(&y1));
        if !found.is_empty() {
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if sees(&hermite(&y, &k1_law, &y1, &k4, h, mid)).is_empty() {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            s_end = hi;
            found = sees(&hermite(&y, &k1_law, &y1, &k4, h, hi));
        }
        // Record on the dt grid inside the accepted part of the step (cubic Hermite).
        let t_end = t + s_end * h;
        let chattering = s_end * h < 0.5 * dt;
        while next_record <= t_end + 1e-12 && next_record > t {
            let yr = hermite(&y, &k1_law, &y1, &k4, h, (next_record - t) / h);
            d.record(d.sample(next_record, pos(&yr), vel(&yr)), Keep::Grid, false);
            next_record += dt;
        }
        y = if s_end < 1.0 {
            hermite(&y, &k1_law, &y1, &k4, h, s_end)
        } else {
            y1
        };
        t = t_end;
        steps += 1;
        layered = false;
        let discovered = !found.is_empty();
        if discovered {
            // A discovery is recorded on both sides (Θ, k and λ jump at the same t), so that
            // the recording shows the switch of eq. `dissipationfun` when the jump lifts V to μ.
            d.record(d.sample(t, pos(&y), vel(&y)), Keep::Pinned, false);
            if !d.discover(t, &found, pos(&y), vel(&y)) {
                break;
            }
        }
        // Θ, k and λ change here; the next step starts from the new right-hand side.
        let Some(k_next) = rhs_after_event(&mut d, t, &y) else {
            break;
        };
        let in_band = k_next.is_none();
        k1 = k_next;
        h *= (0.9 * (step_tol / err.max(1e-300)).cbrt()).clamp(0.2, 5.0);
        reached = d.arrived(pos(&y));
        let s = d.sample(t, pos(&y), vel(&y));
        if reached || discovered || in_band {
            d.record(s, Keep::Pinned, discovered || in_band);
        } else {
            d.judge(&s);
        }
        if d.at_rest(t, pos(&y), chattering, discovered, reached) {
            break;
        }
    }
    if d.last_recorded() != Some(t) {
        d.record(d.sample(t, pos(&y), vel(&y)), Keep::Pinned, false);
    }
    Ok(d.finish(End {
        reached,
        time: t,
        final_distance: (pos(&y) - prepared.truth.goal()).norm(),
        steps,
        rejected,
        physics: Physics::Builtin,
    }))
}

/// The local error bound of the Bogacki–Shampine step control (norm of the state error per
/// step) in a world of [`STEP_TOLERANCE_SCALE`] or more; a smaller world scales it
/// ([`step_tolerance`]).
pub const STEP_TOLERANCE: f64 = 1e-7;

/// The workspace size (m, the boundary's smallest radius) below which [`STEP_TOLERANCE`]
/// shrinks in proportion to the world.
pub const STEP_TOLERANCE_SCALE: f64 = 1.0;

/// The local error bound of the step control in the world of `truth`:
/// `STEP_TOLERANCE·min(1, R/STEP_TOLERANCE_SCALE)`, `R` the boundary's smallest radius. An
/// absolute 1e-7 m is a tenth of a 1 µm world: the integrator then accepted steps that crossed
/// the goal and back, and a law that is not linear at the goal (the finite-time speed,
/// `docs/maths.md` §6) chattered 1e-7 m around it, ten times the goal tolerance of 1e-8 m
/// (`scenarios/adversarial/tiny-world.toml`). Scaled, the tiny world is integrated as the same
/// world at 1 m; a world of 1 m or more is integrated exactly as before.
#[must_use]
pub fn step_tolerance(truth: &Truth) -> f64 {
    let size = truth.boundary.radius_bounds().0;
    STEP_TOLERANCE * (size / STEP_TOLERANCE_SCALE).min(1.0)
}
