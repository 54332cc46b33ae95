//! Running a scenario: the integrator with discovery events, and the guarantee monitors.
//!
//! Both robot models are integrated with the Bogacki–Shampine 3(2) pair and step-size
//! control (`sim.dt` is the largest step and the recording interval). The dynamic law is stiff
//! near walls (`|∇Θ|` grows without bound, maths.md §4 pitfall B), so a step any of whose stages
//! leaves the free space is rejected and retried smaller. After each accepted step the sector
//! is checked against the unknown obstacles; a discovery is located within the step by
//! bisection on the cubic Hermite interpolant of the step, the state is cut there, and only
//! then do `Θ`, `k` and `λ` change (Carathéodory solutions). Runs are deterministic.

use harmonav::{Controller, Evaluation};
use nalgebra::Vector2;
use serde::Serialize;

use crate::closed_loop::ClosedLoop;
pub use crate::guarantee::Guarantee;
use crate::guarantee::{Check, FreeSpaceLoss};
use crate::monitor::Recorder;
use crate::outcome::{Outcome, STALL_WINDOW};
use crate::scenario::{Model, Prepared};
use crate::trajectory::Keep;
pub use crate::trajectory::MAX_KEPT_STATES;
use crate::truth::Truth;

/// One recorded state.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sample {
    /// Time, s.
    pub t: f64,
    /// Position.
    pub x: [f64; 2],
    /// Velocity.
    pub v: [f64; 2],
    /// `Θ(x)`.
    pub theta: f64,
    /// `V = μΘ + ½m|ẋ|²` (dynamic model).
    pub energy: Option<f64>,
    /// `k = n + 1`.
    pub k: f64,
    /// Damping `λ` in force (dynamic model).
    pub lambda: Option<f64>,
    /// How much `V` may differ from the exact solution's at this state through integration
    /// error alone (dynamic model): the local error bound [`step_tolerance`] times the
    /// sensitivity `μ|∇Ψ| + m|ẋ|` of `V` to the state, times a safety factor of 10.
    #[serde(skip)]
    pub energy_tolerance: f64,
    /// Whether the damping is in its `V < μ` branch, critical at the goal (`λ_c` under the
    /// `"paper"` policy, `λ(x)` under `"auto"`), rather than switched (dynamic model).
    pub critical: bool,
}

/// A discovery event.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Discovery {
    /// Obstacle name.
    pub obstacle: String,
    /// Obstacle index in the scenario.
    #[serde(skip)]
    pub index: usize,
    /// Time, s.
    pub time_s: f64,
    /// Robot position at discovery.
    #[serde(skip)]
    pub position: [f64; 2],
    /// Sector axis at discovery.
    #[serde(skip)]
    pub axis: [f64; 2],
}

/// The summary of a run (`summary.json`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Scenario name.
    pub name: String,
    /// `kinematic` or `dynamic`.
    pub model: Model,
    /// `builtin` (or `rapier`).
    pub physics: String,
    /// The `k` policy (`"paper"` or `"auto"`).
    pub k_policy: &'static str,
    /// The damping policy of the dynamic law (`None` for the kinematic model).
    pub damping: Option<&'static str>,
    /// Goal reached within tolerance and time.
    pub reached: bool,
    /// Time at the end of the run, s.
    pub time_s: f64,
    /// Distance to the goal at the end, m.
    pub final_distance: f64,
    /// Smallest clearance to the true obstacles and boundary (minus the robot radius), m.
    pub min_clearance: f64,
    /// The length of the recorded path (every state on the `sim.dt` grid and at the events),
    /// m.
    pub path_length: f64,
    /// Largest speed, m/s.
    pub max_speed: f64,
    /// `√(2μ/m)` for the dynamic model.
    pub speed_bound: Option<f64>,
    /// Recorded states in collision (clearance ≤ 0).
    pub collisions: usize,
    /// Contact events reported by the physics engine (rapier runs only).
    pub physics_contacts: Option<usize>,
    /// Discoveries in order.
    pub discoveries: Vec<Discovery>,
    /// The guarantee monitors.
    pub guarantees: Vec<Guarantee>,
    /// How the run ended.
    pub outcome: Outcome,
    /// What the verdict alone would not explain (a start on a symmetry axis, …): filled by
    /// [`crate::physics::simulate`], empty from [`run`] alone (a sweep's many runs skip them).
    pub warnings: Vec<crate::warning::Warning>,
    /// States recorded (on the `sim.dt` grid and at the events), all of them judged and handed
    /// to the observer; [`Run::samples`] keeps at most [`MAX_KEPT_STATES`] of the grid ones.
    pub recorded_states: usize,
    /// Accepted integration steps.
    pub steps: usize,
    /// Rejected integration steps.
    pub rejected_steps: usize,
}

impl Summary {
    /// Whether every guarantee held.
    pub fn all_passed(&self) -> bool {
        self.guarantees.iter().all(|g| g.passed)
    }
}

/// What a run hands its observer as it goes, in time order ([`run_observed`]).
#[derive(Clone, Copy, Debug)]
pub enum Event<'a> {
    /// A warning about the scenario, before the run starts
    /// ([`crate::physics::simulate_observed`]).
    Warning(&'a crate::warning::Warning),
    /// An obstacle became known (those known at the start come before the first state).
    Discovery(&'a Discovery),
    /// A recorded state (a discovery's first side comes before its [`Event::Discovery`], the
    /// second after).
    State(&'a Sample),
}

/// A run: the summary and the recorded trajectory.
#[derive(Clone, Debug)]
pub struct Run {
    /// The summary.
    pub summary: Summary,
    /// Recorded states (every `sim.dt`, and at discoveries and the end), kept in bounded
    /// memory: a run longer than [`MAX_KEPT_STATES`] grid states keeps one in a power of two
    /// of them ([`crate::trajectory`]). The monitors judged every state, and
    /// [`run_observed`] hands every one to its observer.
    pub samples: Vec<Sample>,
}

/// Why a run could not start.
#[derive(Clone, Debug, PartialEq)]
pub struct RunError(pub String);

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for RunError {}

type State = [f64; 4];

/// Accepted steps at rest after which a kinematic run is stopped as stalled (see `run`).
pub const STALL_STEPS: usize = 10_000;

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
fn rhs(lp: &ClosedLoop, y: &State) -> Option<(State, Evaluation)> {
    let (x, v) = (pos(y), vel(y));
    let e = lp.eval(x, v)?;
    let dy = match lp.nav.controller() {
        Controller::Kinematic(_) => [e.command.x, e.command.y, 0.0, 0.0],
        Controller::Dynamic(law) => {
            let a = e.command / law.mass();
            [v.x, v.y, a.x, a.y]
        }
    };
    Some((dy, e))
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
    let sc = &prepared.scenario;
    let truth = &prepared.truth;
    let (mut lp, mut discoveries) = ClosedLoop::start(prepared, model, None)?;
    let start = Vector2::new(sc.robot.start[0], sc.robot.start[1]);
    let goal = truth.goal();
    let mut y: State = [start.x, start.y, 0.0, 0.0];

    let (dt, max_time, tol) = (sc.sim.dt, sc.sim.max_time, sc.sim.goal_tolerance);
    let step_tol = step_tolerance(truth);
    let mut t = 0.0;
    let mut h = dt.min(1e-3);
    let (mut steps, mut rejected) = (0usize, 0usize);
    let sample = |lp: &ClosedLoop, t: f64, y: &State| lp.sample(t, pos(y), vel(y));
    let mut rec = Recorder::new(goal, tol, observer);
    rec.discovered(&discoveries);
    rec.record(sample(&lp, t, &y), Keep::Pinned, false, truth);
    let mut next_record = dt;
    let (mut k1, _) =
        rhs(&lp, &y).ok_or_else(|| RunError("the start is not in the free space".into()))?;
    let mut reached = (pos(&y) - goal).norm() < tol;
    let mut aborted: Option<Guarantee> = None;
    // Stall detection (kinematic law): the robot has stayed within tol/2 of `anchor` since
    // `rest_from`, for `rest_steps` steps. At a saddle the normalised law chatters at ever
    // smaller steps (1.5 million per simulated second were seen, for minutes to max_time), so
    // the run stops once the rest has lasted the window of `Outcome::Stalled`,
    // max(STALL_WINDOW·t, 1 s), or STALL_STEPS chattering steps, those the error control cut
    // below dt/2: a robot moving at all covers tol/2 in far fewer (at 1 m/s and 1e-5 s steps,
    // 10⁴ steps are 0.1 m). Steps of a full dt are not counted: at a tiny sim.dt (5e-6 s)
    // 10⁴ of them are 0.05 s, in which a robot slowing near its goal moves less than tol/2.
    // The dynamic law is smooth there and creeps: it is left to run.
    let kinematic = lp.model == Model::Kinematic;
    let (mut anchor, mut rest_from, mut rest_steps) = (start, 0.0, 0usize);
    while !reached && t < max_time {
        h = h.min(dt).min(max_time - t);
        if h < 1e-14 {
            if max_time - t >= 1e-14 {
                // Step-size collapse: the run cannot go on, and must not pass as a mere
                // "not reached".
                aborted = Some(Guarantee::failed(Check::StepCollapsed {
                    time_s: t,
                    position: [y[0], y[1]],
                }));
            }
            break;
        }
        let stages = (|| {
            let (k2, _) = rhs(&lp, &axpy(&y, h, &[(0.5, &k1)]))?;
            let (k3, _) = rhs(&lp, &axpy(&y, h, &[(0.75, &k2)]))?;
            let y1 = axpy(
                &y,
                h,
                &[(2.0 / 9.0, &k1), (1.0 / 3.0, &k2), (4.0 / 9.0, &k3)],
            );
            let (k4, _) = rhs(&lp, &y1)?;
            let e = axpy(
                &[0.0; 4],
                h,
                &[
                    (-5.0 / 72.0, &k1),
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
        let sees = |y: &State| lp.sees(pos(y), vel(y));
        let (mut s_end, mut found) = (1.0, sees(&y1));
        if !found.is_empty() {
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if sees(&hermite(&y, &k1, &y1, &k4, h, mid)).is_empty() {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            s_end = hi;
            found = sees(&hermite(&y, &k1, &y1, &k4, h, hi));
        }
        // Record on the dt grid inside the accepted part of the step (cubic Hermite).
        let t_end = t + s_end * h;
        let chattering = s_end * h < 0.5 * dt;
        while next_record <= t_end + 1e-12 && next_record > t {
            let yr = hermite(&y, &k1, &y1, &k4, h, (next_record - t) / h);
            rec.record(sample(&lp, next_record, &yr), Keep::Grid, false, truth);
            next_record += dt;
        }
        y = if s_end < 1.0 {
            hermite(&y, &k1, &y1, &k4, h, s_end)
        } else {
            y1
        };
        t = t_end;
        steps += 1;
        let discovered = !found.is_empty();
        if discovered {
            let ax = lp.axis(pos(&y), vel(&y));
            rec.record(sample(&lp, t, &y), Keep::Pinned, false, truth);
            let before = discoveries.len();
            let added = lp.discover(t, &found, (pos(&y), vel(&y)), ax, &mut discoveries);
            rec.discovered(&discoveries[before..]);
            if let Err(lost) = added {
                aborted = Some(lost);
                break;
            }
        }
        // Θ, k and λ change here; the next step starts from the new right-hand side.
        let Some((k_next, _)) = rhs(&lp, &y) else {
            aborted = Some(Guarantee::failed(Check::LeftFreeSpace {
                time_s: t,
                position: [y[0], y[1]],
                reason: FreeSpaceLoss::Left,
            }));
            break;
        };
        k1 = k_next;
        h *= (0.9 * (step_tol / err.max(1e-300)).cbrt()).clamp(0.2, 5.0);
        reached = (pos(&y) - goal).norm() < tol;
        let s = sample(&lp, t, &y);
        // A discovery is recorded on both sides (Θ, k and λ jump at the same t), so that the
        // recording shows the switch of eq. `dissipationfun` when the jump lifts V to μ.
        if reached || discovered {
            rec.record(s, Keep::Pinned, discovered, truth);
        } else {
            rec.step(&s, false, truth);
        }
        if (pos(&y) - anchor).norm() > 0.5 * tol || discovered {
            (anchor, rest_from, rest_steps) = (pos(&y), t, 0);
        } else {
            rest_steps += usize::from(chattering);
            if kinematic
                && !reached
                && (t - rest_from >= (STALL_WINDOW * t).max(1.0) || rest_steps >= STALL_STEPS)
            {
                rec.monitor.stalled(rest_from);
                break;
            }
        }
    }
    if rec.last_time() != Some(t) {
        rec.record(sample(&lp, t, &y), Keep::Pinned, false, truth);
    }
    let final_distance = (pos(&y) - goal).norm();
    let (monitor, samples) = rec.into_parts();
    let summary = monitor.finish(
        prepared,
        &lp,
        reached,
        t,
        final_distance,
        discoveries,
        steps,
        rejected,
        aborted,
    );
    Ok(Run { summary, samples })
}

pub use crate::monitor::MARGIN_TOLERANCE;

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
