//! The one control loop both integrators share: the robot's [`Navigator`] (its belief: the
//! obstacles it has sensed) driven against the [`Truth`] (the scenario's shapes, which only the
//! sensor sees). The built-in integrator ([`crate::run`]) and the rapier harness
//! (`rapier.rs`, feature `rapier`) differ only in how they advance the state; the driver
//! (`driver.rs`) does the rest.

use harmonav::control::Branch;
use harmonav::{Controller, Evaluation, Law, NavError, Navigator, Options};
use harmonav_sensing::{axis, initially_known};
use nalgebra::Vector2;

use harmonav_scenario::{Model, Prepared, Sensor, Truth};

use crate::guarantee::{Check, FreeSpaceLoss, Guarantee};
use crate::scanner::{Scanner, Scene};
use crate::summary::RunError;
use crate::trace::{Discovery, Sample, ScanRecord, recorded_velocity};
use crate::warning::Warning;
use harmonav::perception::sim::Enclosure;

/// The closed loop of one robot model in one world.
pub(crate) struct ClosedLoop<'a> {
    pub model: Model,
    /// What the robot knows.
    pub nav: Navigator,
    /// The truth index of each obstacle the navigator knows, in the order it learnt them.
    pub known: Vec<usize>,
    pub truth: &'a Truth,
    /// The lidar, when the robot perceives by scans (`[sensor] type = "lidar"`).
    pub scanner: Option<Scanner>,
    /// The heading of the last lidar scan, rad: the next one keeps it where the sector's axis
    /// has no value (at rest at a critical point, or in a margin band, where the law has none).
    pub yaw: f64,
    /// A differential drive's heading `θ`, rad, set by the held-command loop each period: the
    /// sector's axis and the lidar's heading are then `e(θ)`, the body's (its motion's
    /// direction whenever it moves, `v ≥ 0`). `None` for a holonomic robot.
    pub heading: Option<f64>,
}

impl<'a> ClosedLoop<'a> {
    /// The loop at the start of `prepared` (`model` overrides the file's robot model), with the
    /// obstacles known at `t = 0` (assumption `localobs`: within `d_min` of the start, and
    /// those the sector sees from the start along the descent direction of the full field,
    /// then along that of the known ones) and those discoveries. `period`: the control period
    /// of a fixed-step loop, for the navigator's hold (`None`: the file's `robot.control_period`,
    /// else the law's default; the built-in integrator evaluates the continuous law and holds a
    /// command only out of a margin band).
    pub fn start(
        prepared: &'a Prepared,
        model: Option<Model>,
        period: Option<f64>,
    ) -> Result<(Self, Vec<Discovery>), RunError> {
        let sc = &prepared.scenario;
        let truth = &prepared.truth;
        let model = model.unwrap_or(sc.robot.model);
        let law = match model {
            Model::Kinematic => Law::kinematic(sc.controller.gain),
            Model::Dynamic => Law::dynamic(sc.robot.mass, sc.controller.mu),
        };
        let mut options = Options::default()
            .with_robot(truth.radius, truth.margin)
            .with_k(prepared.k_policy())
            .with_damping(prepared.damping_policy())
            .with_speed(prepared.speed_policy());
        if let Some(v) = sc.controller.v_max {
            options = options.with_v_max(v);
        }
        if let Some(h) = period.or(prepared.control_period()) {
            options = options.with_control_period(h);
        }
        // After `v_max`: a differential drive caps the law's top speed at its own.
        if let Some(base) = prepared.base() {
            options = options.with_base(base);
        }
        if let (Some(force), Model::Dynamic) = (sc.controller.force_bound, model) {
            options = options.with_force_bound(force);
        }
        options = options.with_comfort(sc.controller.comfort);
        // The lidar's fit range for this law (eq. fitnear), for the navigator and the
        // scanner's claim alike.
        let lidar = truth.sensor.lidar().map(|l| l.for_law(&law, &options));
        // Global sensing never switches λ on a discovery after t = 0: the default sensor's
        // d_min serves. Without obstacles no curvature bound is needed either.
        match (truth.sensor, &sc.sensor, &lidar) {
            (Sensor::Sector(_), Some(spec), _) => {
                options = options.with_sensor(spec.range, spec.aperture_deg);
                if truth.rho_min.is_finite() {
                    options = options.with_rho_min(truth.rho_min);
                }
            }
            (_, _, Some(lidar)) => options = lidar.options(options, truth.rho_min),
            _ => {}
        }
        let nav = Navigator::new(truth.boundary.clone(), truth.goal(), law, options)?;
        let mut lp = Self {
            model,
            nav,
            known: Vec::new(),
            truth,
            scanner: lidar.map(Scanner::new),
            yaw: 0.0,
            heading: prepared.base().map(|_| prepared.start_yaw()),
        };
        let Some(sensing) = truth.sensor.exact() else {
            // A lidar's first scan, at t = 0, is the driver's.
            return Ok((lp, Vec::new()));
        };
        let start = prepared.start();
        let global = prepared.global_field()?;
        let first_axis = global.eval(start).ok().and_then(|e| e.direction);
        let known = initially_known(&truth.workspace, start, &sensing, truth.rho_min, first_axis);
        let mut discoveries = Vec::new();
        let at_start = (start, Vector2::zeros());
        lp.discover(0.0, &known, at_start, first_axis, &mut discoveries)
            .map_err(|lost| RunError::Start(Box::new(lost)))?;
        // A discovery at t = 0 along the axis of the known set's field.
        let seen = lp.sees(start, Vector2::zeros());
        lp.discover(0.0, &seen, at_start, None, &mut discoveries)
            .map_err(|lost| RunError::Start(Box::new(lost)))?;
        Ok((lp, discoveries))
    }

    /// [`Warning::ScansTooSparse`] when the robot's top speed (the kinematic `v_max`, the
    /// dynamic bound `√(2μ/m)`) over one scan period reaches the room eq. fitnear leaves: the
    /// fit range less the robot's radius, margin and the noise bound `ε` (a fixed step longer
    /// than the scan period skips scans, and shortens that room further).
    pub fn scan_warning(&self) -> Option<Warning> {
        let lidar = self.scanner.as_ref()?.sensor();
        let speed = match self.nav.controller() {
            Controller::Kinematic(law) => law.v_max(),
            Controller::Dynamic(law) => law.speed_bound(),
        };
        let travel = speed * lidar.period();
        let near = (self.truth.radius + self.truth.margin).max(lidar.lidar.range_min);
        let room = lidar.scan.fit_range - near - lidar.scan.range_noise;
        (travel >= room).then_some(Warning::ScansTooSparse { travel, room })
    }

    /// The law at `(x, ẋ)`; `None` outside the free space of the known obstacles.
    pub fn eval(&self, x: Vector2<f64>, v: Vector2<f64>) -> Option<Evaluation> {
        self.nav.evaluate(x, v).ok()
    }

    /// How the robot moves at `(x, ẋ)`: `ẋ` (dynamic model) or the commanded velocity.
    pub fn moving(&self, v: Vector2<f64>, e: &Evaluation) -> Vector2<f64> {
        match self.model {
            Model::Kinematic => e.command,
            Model::Dynamic => v,
        }
    }

    /// The sector's axis at `(x, ẋ)` (eq. `sectoraxis`), `None` at rest at a critical point or
    /// outside the free space; a differential drive's heading `e(θ)` ([`ClosedLoop::heading`]).
    pub fn axis(&self, x: Vector2<f64>, v: Vector2<f64>) -> Option<Vector2<f64>> {
        if let Some(yaw) = self.heading {
            return Some(Vector2::new(yaw.cos(), yaw.sin()));
        }
        let e = self.eval(x, v)?;
        axis(self.moving(v, &e), e.field.direction)
    }

    /// The unknown obstacles (truth indices) the sensor sees at `(x, ẋ)`.
    pub fn sees(&self, x: Vector2<f64>, v: Vector2<f64>) -> Vec<usize> {
        match self.axis(x, v) {
            Some(a) => self.truth.sees(x, a, &self.known),
            None => Vec::new(),
        }
    }

    /// At time `t` the robot at `(x, ẋ)` learns the true obstacles `found`, sensed along
    /// `axis`: `k`, `Phi` and `|ẋ(T_n)|` update (the navigator's discovery state is the state of
    /// its last command), and each one added is appended to `log`. Stops at the first that the
    /// navigator rejects (the robot is inside it) and returns the guarantee that is lost; those
    /// before it stay known.
    pub fn discover(
        &mut self,
        t: f64,
        found: &[usize],
        (x, v): (Vector2<f64>, Vector2<f64>),
        axis: Option<Vector2<f64>>,
        log: &mut Vec<Discovery>,
    ) -> Result<(), Guarantee> {
        let a = axis.unwrap_or_default();
        for &i in found {
            // The discovery happens at this state: the navigator's last command is here.
            let added = self
                .nav
                .command(x, v)
                .and_then(|_| self.nav.add_obstacle(self.truth.obstacles[i].clone()));
            if let Err(error) = added {
                return Err(Guarantee::failed(Check::LeftFreeSpace {
                    time_s: t,
                    position: [x.x, x.y],
                    reason: FreeSpaceLoss::Discovery {
                        obstacle: self.truth.names[i].clone(),
                        error,
                    },
                }));
            }
            self.known.push(i);
            log.push(Discovery {
                obstacle: self.truth.names[i].clone(),
                index: i,
                time_s: t,
                position: [x.x, x.y],
                axis: [a.x, a.y],
            });
        }
        Ok(())
    }

    /// The lidar's scan at `t` from `(x, ẋ)`, heading along the sector's axis there (the last
    /// scan's heading when there is none, `+x` before the first), handed to the navigator (its discovery state is the state of its last
    /// command, here). `None` without a lidar; `Some(Err)`: the navigator refused the scan,
    /// and is unchanged.
    pub fn scan(
        &mut self,
        t: f64,
        x: Vector2<f64>,
        v: Vector2<f64>,
    ) -> Option<Result<ScanRecord, NavError>> {
        let yaw = self.axis(x, v).map_or(self.yaw, |a| a.y.atan2(a.x));
        self.yaw = yaw;
        let scanner = self.scanner.as_mut()?;
        if let Err(e) = self.nav.command(x, v) {
            scanner.refuse(t, e.clone());
            return Some(Err(e));
        }
        let scene = Scene {
            obstacles: &self.truth.obstacles,
            enclosure: Enclosure::Star(&self.truth.boundary),
        };
        Some(scanner.scan(&mut self.nav, scene, t, x, yaw))
    }

    /// The recorded state at `t`. `state_error`: the integrator's bound on the error of the
    /// state `(x, ẋ)` (m, m/s), from which the energy's is bounded: `V` may differ from the
    /// exact solution's by `10 · state_error · (μ_p|∇Ψ| + m|ẋ|)` (`μ_p` the law's pull), the
    /// state's error times the
    /// sensitivity of `V` to it, with a safety factor of 10 (dynamic model).
    pub fn sample(&self, t: f64, x: Vector2<f64>, v: Vector2<f64>, state_error: f64) -> Sample {
        let e = self.eval(x, v);
        let dynamic = match self.nav.controller() {
            Controller::Dynamic(law) => Some(law),
            Controller::Kinematic(_) => None,
        };
        let damping = e.and_then(|e| e.damping);
        Sample {
            t,
            x: [x.x, x.y],
            v: recorded_velocity(dynamic.is_some(), v, e.map(|e| e.command)),
            theta: e.map_or(f64::NAN, |e| e.field.value),
            energy: dynamic
                .map(|law| e.map_or(f64::NAN, |e| law.energy(self.nav.field(), &e.field, v))),
            k: self.nav.k(),
            lambda: damping.map(|d| d.lambda),
            energy_tolerance: match (dynamic, &e) {
                (Some(law), Some(e)) => {
                    let sensitivity = law.pull()
                        * law.potential(self.nav.field(), &e.field).gradient.norm()
                        + law.mass() * v.norm();
                    10.0 * state_error * sensitivity
                }
                _ => 0.0,
            },
            critical: damping.is_some_and(|d| d.branch == Branch::Critical),
            yaw: None,
        }
    }
}
