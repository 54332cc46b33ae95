//! The one driver of every integrator: it starts the closed loop, senses, records, decides
//! when a run stops (arrival, a lost guarantee, a stall), and hands the monitors' judgement
//! back as a [`Run`]. An integrator ([`crate::run`], the built-in Bogacki–Shampine one, and
//! `rapier.rs`, rapier's fixed step) only advances the state between the driver's
//! calls.

use harmonav::{Evaluation, Navigator};
use harmonav_scenario::{Model, Prepared};
use nalgebra::Vector2;

use crate::closed_loop::ClosedLoop;
use crate::guarantee::Guarantee;
use crate::monitor::{End, EnergyError, Recorder};
use crate::outcome::rested_too_long;
use crate::summary::{Run, RunError};
use crate::trace::{Discovery, Event, MoverFrame, Sample, ScanRecord, frame_due};
use crate::trajectory::Keep;
use crate::warning::Warning;

/// Accepted steps at rest, each cut by the error control below half of `sim.dt`, after which
/// a kinematic run is stopped as stalled (the stall rule of `driver.rs`, for every
/// integrator).
pub const STALL_STEPS: usize = 10_000;

/// The stall rule's state (kinematic law): the robot has stayed within half the goal
/// tolerance of `anchor` since `since`, for `chattering` steps that the error control cut.
struct Rest {
    anchor: Vector2<f64>,
    since: f64,
    chattering: usize,
}

/// Whether a run looks for the scenario's [`Warning`]s before its first state
/// ([`crate::preflight::check`]): [`crate::physics::simulate`] does; [`crate::run::run`] alone
/// (a sweep's many runs, the benchmark's) and the reference run of a rapier cross-check skip
/// them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Warnings {
    /// Look for them, hand them to the observer first and put them in the summary.
    Find,
    /// Skip them.
    Skip,
}

/// A run in progress: the closed loop, the monitors and the kept trajectory, and what ended
/// it so far. The integrators reach the closed loop only through it.
pub(crate) struct Driver<'a, 'o> {
    /// The robot's navigator against the truth.
    lp: ClosedLoop<'a>,
    rec: Recorder<'o>,
    prepared: &'a Prepared,
    discoveries: Vec<Discovery>,
    aborted: Option<Guarantee>,
    rest: Rest,
    /// The integrator's bound on the state error of one recorded state (m), from which
    /// [`Driver::sample`] bounds the energy's ([`ClosedLoop::sample`]).
    state_error: f64,
    /// The scenario's warnings (empty under [`Warnings::Skip`]).
    warnings: Vec<Warning>,
    /// A lidar's scans that changed the obstacles.
    scan_events: Vec<ScanRecord>,
    /// The movers' frames so far ([`Driver::movers`]).
    mover_frames: Vec<MoverFrame>,
}

impl<'a, 'o> Driver<'a, 'o> {
    /// The run of `prepared` with `model` (or the file's) at the start: the scenario's
    /// warnings (under [`Warnings::Find`]), then the obstacles known at `t = 0`, handed to
    /// `observer`. `period`: the control period of a fixed-step integrator (the navigator
    /// holds each command for it). `state_error`: see [`Driver::sample`].
    pub fn start(
        prepared: &'a Prepared,
        model: Option<Model>,
        period: Option<f64>,
        state_error: f64,
        warnings: Warnings,
        observer: &'o mut dyn FnMut(Event<'_>),
    ) -> Result<Self, RunError> {
        let (lp, discoveries) = ClosedLoop::start(prepared, model, period)?;
        let warnings = match warnings {
            Warnings::Find => {
                let mut found = crate::preflight::check(prepared, lp.nav.field());
                found.extend(lp.scan_warning());
                found
            }
            Warnings::Skip => Vec::new(),
        };
        for w in &warnings {
            observer(Event::Warning(w));
        }
        let sim = &prepared.scenario.sim;
        // A fixed-step integrator (a control period) carries the drift of each interval on the
        // state that ends it; the built-in one bounds the error of each state.
        let energy_error = match period {
            Some(_) => EnergyError::PerInterval,
            None => EnergyError::PerState,
        };
        let mut rec = Recorder::new(
            prepared.truth.goal(),
            sim.goal_tolerance,
            energy_error,
            observer,
        );
        rec.discovered(&discoveries);
        Ok(Self {
            lp,
            rec,
            prepared,
            discoveries,
            aborted: None,
            rest: Rest {
                anchor: prepared.start(),
                since: 0.0,
                chattering: 0,
            },
            state_error,
            warnings,
            scan_events: Vec::new(),
            mover_frames: Vec::new(),
        })
    }

    /// The robot model that runs.
    #[cfg_attr(not(feature = "rapier"), allow(dead_code))]
    pub fn model(&self) -> Model {
        self.lp.model
    }

    /// The robot's navigator (what it knows).
    pub fn nav(&self) -> &Navigator {
        &self.lp.nav
    }

    /// The robot's navigator, to ask a held command of (`Navigator::command` keeps its
    /// sampled-data state).
    pub fn nav_mut(&mut self) -> &mut Navigator {
        &mut self.lp.nav
    }

    /// Whether the robot at `(x, ẋ)` is in a known obstacle's margin band (or the boundary's),
    /// where the law has no value and the navigator's held command leads out
    /// ([`harmonav::Mode::Recovering`]): a scan event or a discovery grew a shape over the
    /// robot's margin. Asks the navigator for that command (its last commanded state is then
    /// `(x, ẋ)`, as at a discovery).
    pub fn recovering(&mut self, x: Vector2<f64>, v: Vector2<f64>) -> bool {
        self.lp
            .nav
            .command(x, v)
            .is_ok_and(|c| matches!(c.mode, harmonav::Mode::Recovering(_)))
    }

    /// The law's continuous evaluation at `(x, ẋ)` ([`ClosedLoop::eval`]); `None` outside the
    /// free space of the known obstacles.
    pub fn eval(&self, x: Vector2<f64>, v: Vector2<f64>) -> Option<Evaluation> {
        self.lp.eval(x, v)
    }

    /// A differential drive's heading `θ`, rad, for the sensing from here on
    /// ([`ClosedLoop::heading`]).
    pub fn set_heading(&mut self, yaw: f64) {
        self.lp.heading = Some(yaw);
    }

    /// Whether the robot at `x` is within the goal tolerance.
    pub fn arrived(&self, x: Vector2<f64>) -> bool {
        (x - self.prepared.truth.goal()).norm() < self.prepared.scenario.sim.goal_tolerance
    }

    /// The state at `t`, as recorded ([`ClosedLoop::sample`] with the integrator's state error).
    pub fn sample(&self, t: f64, x: Vector2<f64>, v: Vector2<f64>) -> Sample {
        self.lp.sample(t, x, v, self.state_error)
    }

    /// A recorded state: judged, handed to the observer and kept as `keep` says;
    /// `discovered`: it is a discovery's second side.
    pub fn record(&mut self, s: Sample, keep: Keep, discovered: bool) {
        self.rec.record(s, keep, discovered, &self.prepared.truth);
    }

    /// A state the monitors judge but the recording leaves out (an integration step's end).
    pub fn judge(&mut self, s: &Sample) {
        self.rec.step(s, false, &self.prepared.truth);
    }

    /// [`Driver::judge`], `event`: the state ends a period whose command the mover filter
    /// changed, where `V` may rise (judged as a discovery's second side).
    pub fn judge_event(&mut self, s: &Sample, event: bool) {
        self.rec.step(s, event, &self.prepared.truth);
    }

    /// The time of the last recorded state.
    pub fn last_recorded(&self) -> Option<f64> {
        self.rec.last_time()
    }

    /// The unknown obstacles the sensor sees at `(x, ẋ)`.
    pub fn sees(&self, x: Vector2<f64>, v: Vector2<f64>) -> Vec<usize> {
        self.lp.sees(x, v)
    }

    /// At `t` the robot at `(x, ẋ)` learns the obstacles `found`, sensed along the sector's
    /// axis there. `false`: the navigator refused one (the robot is inside it), the guarantee
    /// is lost and the run must stop.
    pub fn discover(&mut self, t: f64, found: &[usize], x: Vector2<f64>, v: Vector2<f64>) -> bool {
        let axis = self.lp.axis(x, v);
        let before = self.discoveries.len();
        let added = self
            .lp
            .discover(t, found, (x, v), axis, &mut self.discoveries);
        self.rec.discovered(&self.discoveries[before..]);
        match added {
            Ok(()) => true,
            Err(lost) => {
                self.aborted = Some(lost);
                false
            }
        }
    }

    /// The time of the lidar's next scan, s (`None` without a lidar): a fixed-step integrator
    /// scans at the first step at or after it ([`Driver::scan_due`]), the built-in one lands on
    /// it.
    pub fn next_scan(&self) -> Option<f64> {
        self.lp.scanner.as_ref().map(|s| s.next())
    }

    /// Whether a lidar scan is due at `t`.
    pub fn scan_due(&self, t: f64) -> bool {
        self.lp.scanner.as_ref().is_some_and(|s| s.due(t))
    }

    /// The lidar's scan at `pre.t` from `(x, ẋ)`, observed by the navigator and handed to the
    /// observer. `Some(true)`: it changed the obstacles (an event: `Θ`, `k` and the damping
    /// state changed, as at a discovery; `pre`, the state just before as the integrator
    /// samples it, with its own energy tolerance, is recorded first as a discovery's first
    /// side, unless a state was recorded at `t` already); `Some(false)`: nothing changed, or no
    /// lidar; `None`: the navigator refused it, and the run must stop (the guarantee
    /// `scans-accepted` is lost).
    pub fn scan(&mut self, pre: Sample, x: Vector2<f64>, v: Vector2<f64>) -> Option<bool> {
        let t = pre.t;
        let record = match self.lp.scan(t, x, v)? {
            Ok(record) => record,
            Err(_) => return None,
        };
        let changed = record.perceived.is_some();
        if changed && self.rec.last_time() != Some(t) {
            self.record(pre, Keep::Pinned, false);
        }
        self.rec.scanned(&record);
        if changed {
            self.scan_events.push(record);
        }
        Some(changed)
    }

    /// Whether a movers' frame at `t` is due ([`MOVER_FRAME_PERIOD`] since the last kept), so
    /// that a loop builds one only then.
    pub fn movers_due(&self, t: f64) -> bool {
        frame_due(&self.mover_frames, t)
    }

    /// The movers at a recorded state (after it), handed to the observer and kept (a loop asks
    /// [`Driver::movers_due`] first).
    pub fn movers(&mut self, frame: MoverFrame) {
        self.rec.observe(Event::Movers(&frame));
        self.mover_frames.push(frame);
    }

    /// A guarantee lost on the way (a step-size collapse, the free space left): the run stops.
    pub fn abort(&mut self, lost: Guarantee) {
        self.aborted = Some(lost);
    }

    /// **The stall rule**, for every integrator. The robot is at `x` at time `t` after a step;
    /// `chattering`: the error control cut that step below half of `sim.dt` (a fixed-step
    /// integrator never does). At a saddle the normalised kinematic law chatters in place at
    /// ever smaller steps (1.5 million per simulated second were seen, for minutes up to
    /// `sim.max_time`), so a kinematic run that has rested within half the goal tolerance of
    /// one point stops once the rest has lasted the window of
    /// [`crate::outcome::Outcome::Stalled`] (`max(STALL_SHARE·t, 1 s)`), or for [`STALL_STEPS`]
    /// chattering steps: a robot moving at all covers that distance in far fewer (at 1 m/s and
    /// 1e-5 s steps, 10⁴ steps are 0.1 m). Steps of a full `sim.dt` are not counted: at a tiny
    /// `sim.dt` (5e-6 s) 10⁴ of them are 0.05 s, in which a robot slowing near its goal moves
    /// less than half the tolerance. The dynamic law is smooth there and creeps: it is left to
    /// run. `true`: stop the run (the monitors record the stall).
    pub fn at_rest(
        &mut self,
        t: f64,
        x: Vector2<f64>,
        chattering: bool,
        discovered: bool,
        reached: bool,
    ) -> bool {
        let tol = self.prepared.scenario.sim.goal_tolerance;
        let rest = &mut self.rest;
        if (x - rest.anchor).norm() > 0.5 * tol || discovered {
            *rest = Rest {
                anchor: x,
                since: t,
                chattering: 0,
            };
            return false;
        }
        rest.chattering += usize::from(chattering);
        let stop = self.lp.model == Model::Kinematic
            && !reached
            && (rested_too_long(rest.since, t) || rest.chattering >= STALL_STEPS);
        if stop {
            self.rec.monitor.stalled(rest.since);
        }
        stop
    }

    /// The judgement of the run that ended at `end`: the summary of the monitors and the
    /// kept states. `physics` names the integrator in the summary.
    pub fn finish(self, end: End) -> Run {
        self.finish_with(end, Vec::new())
    }

    /// [`Driver::finish`] with `more` guarantees judged by the integrator (the movers'),
    /// appended after a lidar's and before one lost on the way.
    pub fn finish_with(self, end: End, more: Vec<Guarantee>) -> Run {
        let (monitor, samples) = self.rec.into_parts();
        let (perception, mut later) = match &self.lp.scanner {
            Some(s) => {
                let (report, checks) = s.judge(&self.lp.nav, &self.prepared.truth.obstacles);
                (Some(report), checks)
            }
            None => (None, Vec::new()),
        };
        later.extend(more);
        later.extend(self.aborted);
        let mut summary = monitor.finish(
            self.prepared,
            self.lp.model,
            &self.lp.nav,
            end,
            self.discoveries,
            later,
        );
        summary.warnings = self.warnings;
        summary.perception = perception;
        Run {
            summary,
            samples,
            scan_events: self.scan_events,
            mover_frames: self.mover_frames,
        }
    }
}
