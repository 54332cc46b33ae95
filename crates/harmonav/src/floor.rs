//! [`FloorNavigator`]: the online navigator on a floor plan (issue 25): `Θ` through
//! `Phi = S ∘ M_a ∘ H ∘ B` (harmonav-floorplan; `M_a` the identity unless the plan recentres on
//! its goal), both laws, the sampled-data hold, obstacles sensed
//! online inside the plan (no new solve of `H` when one is added).

use std::sync::Arc;

use harmonav_control::HeadingPolicy;
use harmonav_field::{FieldError, FieldEval};
use harmonav_floorplan::{FloorError, FloorField, FloorMap, NotFree};
use harmonav_perception::{LaserScan, Perceived, PerceptionError, Pose, Walls};
use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::certified::{self, Band};
use crate::error::NavError;
use crate::hold::{self, Command, Mode};
use crate::law::Law;
use crate::navigator::{
    Controller, Evaluation, controller, discovery_speed_after, event_speed, finite,
    finite_lambda_c, finite_state, moving_along, recovering,
};
use crate::options::{HoldPolicy, Options};
use crate::scan::{Observed, observe as scanned};
use crate::scanning::{ScanState, ScanUpdate};
use crate::space::Space;

/// How far below the level `phi_k(x_s)` of the point `x_s` where it began (a stall, or the
/// shortest path turning against the law) an escape takes `phi_k` before the law resumes
/// ([`Mode::Escaping`], docs/maths.md §13.7): each escape that is not blocked ends at least
/// this much lower than it began, and an escape against the law begins only this much below
/// where the last one began, so there are finitely many escapes (eq. escape-levels).
pub const ESCAPE_DROP: f64 = 0.01;

/// Within this fraction of `δ` of the edge of the certified region (`0 ≤ sd − δ < EDGE·δ`), a
/// point where the hold certifies no step is led in as out of the layer
/// ([`FloorNavigator::command`]): it lies on the edge to rounding.
const EDGE: f64 = 1e-9;

/// The hold has stalled when the robot has stayed within `δ/4` of one point (`δ` the floor's
/// [`FloorMap::delta`]) for this long, s, within `δ/2` of the edge of the certified region
/// (the layer or a sensed obstacle's band): the hold presses it against that edge at a rest
/// point of its slide. An escape follows ([`Mode::Escaping`]).
pub const ESCAPE_STALL: f64 = 2.0;

/// The share of its wanted step at or below which an escape that began against the law (the
/// shortest path's heading more than 90° from the descent direction) counts as blocked and
/// ends: creeping on with ever shorter steps would stall the robot (docs/maths.md §13.7).
/// The hold's step (`hold::held_length`) is the whole wanted step when that is certified free
/// and at most half of it otherwise, so such an escape ends as soon as its whole step is not
/// certified free (a sensed obstacle across the shortest path, or the edge turning away), or,
/// under the dynamic law, when the dynamic hold's cap `c·d(x)` leaves it half or less.
pub const ESCAPE_BLOCKED: f64 = 0.5;

/// An escape along the shortest path ([`Mode::Escaping`]): it ends when `phi_k` is
/// [`ESCAPE_DROP`] below `level`, or when blocked.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Escape {
    /// `phi_k` where it began.
    level: f64,
    /// Begun against the law (the shortest path's heading more than 90° from the descent
    /// direction), not after a stall; it also ends when blocked in the sense of
    /// [`ESCAPE_BLOCKED`].
    early: bool,
}

/// An online navigator on a floor plan: the walls are known (a [`FloorMap`], whose harmonic
/// map is solved once), star-shaped obstacles are added as perception finds them.
///
/// **Where it navigates.** Only in the certified region `W_δ = {sd ≥ δ}` ([`FloorMap::delta`],
/// `sd` the distance to the walls shrunk by `s = radius + margin − δ`: `W_δ` is the
/// configuration space with its margin), minus the sensed obstacles grown by
/// `radius + margin`. The hold ([`HoldPolicy::Auto`]) measures its clearance to the
/// boundary layer, `sd(x) − δ`, so every held step stays in `W_δ`. In the layer (`sd < δ`
/// with the robot's disc clear of the walls, reached only by a disturbance) `Θ` is not used:
/// the discrete map is not claimed a diffeomorphism there, and [`FloorNavigator::evaluate`]
/// returns [`NavError::BoundaryLayer`]. [`FloorNavigator::command`] leads the robot out
/// instead ([`Mode::Recovering`] with [`Band::Boundary`], as out of a sensed obstacle's margin
/// band): straight away from the nearest wall, by a step certified clear of the walls and of
/// the sensed obstacles (docs/maths.md §13.6).
///
/// **Escapes.** Where a hole's barrier is thinner than the layer, the hold can press the robot
/// against the edge of `W_δ` at a local minimum of `Θ` there (a rest point of its slide,
/// [`FloorField::layer_slide`]). Under the heading policy `"auto"`, a robot that has stayed
/// within `δ/4` of one point for [`ESCAPE_STALL`] s next to that edge follows the shortest path
/// ([`Mode::Escaping`], each step certified free) until `phi_k` is [`ESCAPE_DROP`] below where
/// it stalled, then the law resumes. It does so without a stall, anywhere, where the shortest
/// path's heading `g` turns more than 90° from the law's descent direction `d` (`d·g < 0`) and
/// `phi_k` is [`ESCAPE_DROP`] below where the last such escape began; such an escape also ends
/// when blocked ([`ESCAPE_BLOCKED`]; docs/maths.md §13.7, eq. escape-levels).
///
/// ```
/// use std::sync::Arc;
/// use harmonav::{FloorMap, FloorNavigator, FloorOptions, Law, Options, Vector2};
///
/// let v = Vector2::new;
/// let room = vec![v(0.0, 0.0), v(4.0, 0.0), v(4.0, 1.5), v(1.5, 1.5), v(1.5, 4.0), v(0.0, 4.0)];
/// let options = Options::default().with_robot(0.1, 0.1);
/// let floor = Arc::new(FloorMap::new(room, vec![], &FloorOptions::new(0.2, 0.2))?);
/// let goal = v(3.5, 0.75);
/// let mut nav = FloorNavigator::new(floor, goal, Law::kinematic(1.0), options)?;
/// let (mut x, h) = (v(0.75, 3.5), 0.01);
/// for _ in 0..3000 {
///     x += h * nav.command(x, Vector2::zeros())?.value;
///     assert!(nav.field().floor().wall_distance(x) > 0.2);
/// }
/// assert!((x - goal).norm() < 0.05);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct FloorNavigator {
    controller: Controller,
    options: Options,
    period: f64,
    /// `Θ` over the holes and the sensed obstacles (grown by `radius + margin`).
    field: FloorField,
    /// The sensed obstacles grown by `radius` alone (the robot's disc overlaps a true shape iff
    /// its centre is in one); empty with no margin.
    inner: Vec<StarShape>,
    speed_at_discovery: f64,
    last: Option<(Vector2<f64>, Vector2<f64>)>,
    /// The current escape ([`Mode::Escaping`]), if escaping.
    escape: Option<Escape>,
    /// `phi_k` where the last escape against the law began: another may begin only
    /// [`ESCAPE_DROP`] below it (eq. escape-levels of docs/maths.md §13.7).
    early_level: Option<f64>,
    /// Escapes begun so far.
    escapes: usize,
    /// The point the robot has stayed within `δ/4` of, and for how many periods.
    anchor: Option<(Vector2<f64>, usize)>,
    /// The scan perception inside the true walls ([`FloorNavigator::observe_scan`]).
    scan: ScanState,
    /// The true walls, as the perception holds them (one shared copy).
    walls: Arc<Walls>,
    /// The last scan was refused: commands halt the robot ([`Mode::Halted`]).
    scan_refused: bool,
}

impl FloorNavigator {
    /// A navigator on `floor` towards `goal`. `floor` must keep at least `radius + margin`
    /// from the walls (build it with `FloorOptions::new(h, radius + margin)`: then `W_δ` is the
    /// walls' erosion by `s + δ = max(radius + margin, δ)`).
    ///
    /// # Errors
    /// A law parameter or option out of range (named, as [`crate::Navigator::new`]);
    /// `radius + margin` larger than the floor's `δ` ([`NavError::InvalidOption`], `margin`);
    /// a goal not finite or not in `W_δ` ([`NavError::Floor`]).
    pub fn new(
        floor: Arc<FloorMap>,
        goal: Vector2<f64>,
        law: Law,
        options: Options,
    ) -> Result<Self, NavError> {
        finite(goal, "goal")?;
        let controller = controller(&law, &options)?;
        let inflation = options.radius + options.margin;
        // W_δ is the erosion of the walls by s + δ (FloorMap::shrink, delta).
        if inflation > (floor.shrink() + floor.delta()) * (1.0 + 1e-12) {
            return Err(NavError::InvalidOption {
                field: "margin",
                value: options.margin,
            });
        }
        // The governed pull grows with the floor's size: half the diagonal of the bounding box
        // of `W_s` (the walls shrunk, where `H` is built), as a disc navigator takes its shrunk
        // boundary's radius.
        let controller = controller.in_world(0.5 * floor.domain().diameter())?;
        let field = FloorField::new(floor, goal, options.k).map_err(NavError::Floor)?;
        // The nominal heading of the default heading policy, for either law: the shortest path
        // in the walls' W_δ (docs/maths.md §13.3–13.4).
        let heading = match &controller {
            Controller::Kinematic(law) => law.heading_policy(),
            Controller::Dynamic(law) => law.heading_policy(),
        };
        let field = if heading == HeadingPolicy::Auto {
            field.with_geodesic()
        } else {
            field
        };
        let truth = field.floor().walls();
        let walls = Walls::new(truth.outer().to_vec(), truth.holes().to_vec())
            .map_err(|e| NavError::Perception(PerceptionError::Walls(e)))?;
        let walls = Arc::new(walls);
        let scan = ScanState::in_walls(walls.clone(), &options.scan, options.rho_min, inflation)?;
        let nav = Self {
            controller,
            options,
            period: options.period_for(&law),
            field,
            inner: Vec::new(),
            speed_at_discovery: 0.0,
            last: None,
            escape: None,
            early_level: None,
            escapes: 0,
            anchor: None,
            scan,
            walls,
            scan_refused: false,
        };
        // Guard: λ_c (eq. critdamp) from the floor's goal stiffness, checked once.
        if let Controller::Dynamic(law) = &nav.controller {
            finite_lambda_c(
                law,
                law.lambda_c_for(nav.field.destination_stiffness(), 0.0),
            )?;
        }
        Ok(nav)
    }

    /// Adds a sensed obstacle (true shape, grown here by `radius + margin`): `k`, `B` and the
    /// point world update, `H` is reused (no new solve). Returns its index.
    ///
    /// # Errors
    /// The navigator is then unchanged: the shape cannot be grown ([`NavError::Shape`]); it
    /// contains the robot's last position grown by `radius` ([`NavError::ContainsRobot`]); it
    /// overlaps another, contains the goal or reaches the boundary layer ([`NavError::Floor`]).
    pub fn add_obstacle(&mut self, shape: StarShape) -> Result<usize, NavError> {
        let (grown, inner) = self.options.grow(&shape, self.last.map(|(x, _)| x))?;
        let field = self.field.with_obstacle(grown).map_err(NavError::Floor)?;
        self.field = field;
        self.inner.extend(inner);
        let index = self.field.transform().obstacles().count() - 1;
        self.scan.add_exact(shape, index);
        self.discovered();
        Ok(index)
    }

    /// The state a discovery resets: the dynamic law's `|ẋ(T_n)|` (the speed of the last
    /// commanded state) and the escapes (`phi_k` changes with `k` and the point world: the
    /// levels before and after are not comparable).
    fn discovered(&mut self) {
        self.speed_at_discovery = self.last.map_or(0.0, |(_, v)| v.norm());
        self.escape = None;
        self.early_level = None;
    }

    /// Observes one scan taken from `pose` inside the floor plan, as
    /// [`crate::Navigator::observe_scan`] does in a star world (docs/maths.md §12, §12.17):
    /// hits within `max(ε, ε_g)` of the true walls (or nearer them than `g_w − ε` under the wall
    /// prior [`crate::ScanOptions::wall_gap`]) and of the exact shapes of
    /// [`FloorNavigator::add_obstacle`] are explained; the rest are fitted to conservative
    /// stars kept out of the walls (and `g_w` from them), merged with the perceived shapes they
    /// overlap, and every new or grown shape, grown by `radius + margin`, is handed to the
    /// field as a sensed obstacle ([`FloorField::with_sensed`]: `k` and `B` update, `H` is
    /// reused). An event resets what [`FloorNavigator::add_obstacle`] resets.
    ///
    /// A sensed obstacle must lie in the certified region with its growth
    /// ([`FloorError::ObstacleNearWall`], decided by [`FloorMap::star_room`]): a fit grown by
    /// `radius + margin` that comes within `δ` of the walls shrunk by the robot cannot be taken
    /// by the harmonic map's construction, whose holes are solved once. Furniture that stands
    /// that near the walls belongs in the map; the wall prior `g_w` keeps fits from reaching
    /// towards the walls behind what the scan saw.
    ///
    /// # Errors
    /// The navigator is then unchanged: as [`crate::Navigator::observe_scan`] (a sensor outside
    /// the walls is [`NavError::Perception`]); a changed shape that reaches the boundary
    /// layer, overlaps an exact shape or contains the goal ([`NavError::Floor`]).
    pub fn observe_scan(&mut self, pose: Pose, scan: &LaserScan) -> Result<ScanUpdate, NavError> {
        let result = self.observe_once(pose, scan);
        self.scan_refused = result.is_err();
        result
    }

    /// [`FloorNavigator::observe_scan`] without the memory of a refusal.
    fn observe_once(&mut self, pose: Pose, scan: &LaserScan) -> Result<ScanUpdate, NavError> {
        let old: Vec<StarShape> = self.field.transform().obstacles().cloned().collect();
        let event = match scanned(&self.scan, &old, &self.inner, &self.options, pose, scan)? {
            Observed::Quiet(perception, update) => {
                self.scan.perception = perception;
                return Ok(update);
            }
            Observed::Event(event) => event,
        };
        let field = self
            .field
            .with_sensed(&event.obstacles)
            .map_err(NavError::Floor)?;
        self.field = field;
        self.inner = event.inner;
        self.scan = event.state;
        self.discovered();
        let clearance = event.update.event_clearance.unwrap_or(f64::INFINITY);
        self.speed_at_discovery = event_speed(
            &self.controller,
            self.speed_at_discovery,
            clearance,
            self.options.margin,
        );
        Ok(event.update)
    }

    /// The floor plan's true walls as polygon rings, against which
    /// [`FloorNavigator::observe_scan`] explains hits (and a simulator casts its lidar).
    pub fn walls(&self) -> &Arc<Walls> {
        &self.walls
    }

    /// The perceived shapes (not grown), each with its index among the sensed obstacles, in
    /// the perception's order ([`crate::Navigator::perceived`]).
    pub fn perceived(&self) -> impl Iterator<Item = (usize, &Perceived)> + '_ {
        self.scan.perceived()
    }

    /// The shapes given to [`FloorNavigator::add_obstacle`] (true, not grown), each with its
    /// index among the sensed obstacles, in the order they were added
    /// ([`crate::Navigator::added`]).
    pub fn added(&self) -> impl Iterator<Item = (usize, &StarShape)> + '_ {
        self.scan.added()
    }

    /// The command to hold for one control period at `(x, ẋ)`, as
    /// [`crate::Navigator::command`]: under [`HoldPolicy::Auto`] every held step stays in the
    /// certified clearance (to the sensed obstacles and to the boundary layer), `Θ` decreases
    /// over each kinematic step of the law (not during an escape, [`Mode::Escaping`], which ends
    /// [`ESCAPE_DROP`] below where it began, or blocked), and the dynamic law's caps hold. A
    /// recovery ([`Mode::Recovering`], out of a sensed obstacle's band or the walls' layer)
    /// lifts the dynamic law's discovery speed `|ẋ(T_n)|` to the speed `|v⁺|` it gives, as
    /// [`crate::Navigator::command`]'s does.
    ///
    /// # Errors
    /// (the navigator is then unchanged) `x` or `ẋ` not finite; the robot's disc overlapping a
    /// wall ([`NavError::OutsideBoundary`]) or a sensed obstacle ([`NavError::InObstacle`]);
    /// `x` in the boundary layer with no certified way out ([`NavError::BoundaryLayer`]); a
    /// non-finite command. After a refused [`FloorNavigator::observe_scan`] the command halts
    /// the robot ([`Mode::Halted`]) until a scan is accepted.
    pub fn command(&mut self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Command, NavError> {
        if self.scan_refused {
            return crate::navigator::halted(&self.controller, x, v, self.period, &mut self.last);
        }
        let radius = 0.25 * self.field.floor().delta();
        let anchor = match self.anchor {
            Some((a, n)) if (x - a).norm() < radius => (a, n + 1),
            _ => (x, 0),
        };
        let (command, escape) = self.held(x, v, anchor.1)?;
        if !command.value.iter().all(|c| c.is_finite()) {
            return Err(NavError::NonFiniteCommand);
        }
        self.speed_at_discovery = discovery_speed_after(
            &self.controller,
            &command,
            v,
            self.period,
            self.speed_at_discovery,
        );
        self.last = Some((x, v));
        // An escape that begins moves the robot: the watch starts again.
        let begins = escape.is_some() && escape != self.escape;
        self.anchor = Some(if begins { (x, 0) } else { anchor });
        self.escapes += usize::from(begins);
        if let Some(e) = escape.filter(|e| begins && e.early) {
            self.early_level = Some(e.level);
        }
        self.escape = escape;
        Ok(command)
    }

    /// The command and the escape after it, the robot having stayed near one point for
    /// `still` periods.
    fn held(
        &self,
        x: Vector2<f64>,
        v: Vector2<f64>,
        still: usize,
    ) -> Result<(Command, Option<Escape>), NavError> {
        let eval = match self.evaluate(x, v) {
            Ok(eval) => eval,
            Err(NavError::InObstacle { obstacle }) => {
                return self.recover(x, v, obstacle).map(|c| (c, None));
            }
            Err(NavError::BoundaryLayer) => return self.leave_layer(x, v).map(|c| (c, None)),
            Err(e) => return Err(e),
        };
        if self.options.hold == HoldPolicy::Paper {
            return Ok((
                Command {
                    value: eval.command,
                    mode: Mode::Law,
                },
                None,
            ));
        }
        // Every escape follows the shortest path's heading `g` (none without the geodesic).
        let Some(g) = self.field.geodesic().and_then(|t| t.heading_near(x)) else {
            return Ok((self.law_or_in(x, v, &eval), None));
        };
        let phi = eval.field.phi;
        if let Some(e) = self.escape.filter(|e| phi >= e.level - ESCAPE_DROP)
            && let Some(c) = self.escaping(x, v, g, e.early)
        {
            return Ok((c, Some(e)));
        }
        // Against the law: `g` more than 90° from the law's descent direction `d`, and
        // `phi_k` `Δ` below where the last such escape began.
        if self.early_level.is_none_or(|l| phi < l - ESCAPE_DROP)
            && eval.field.direction.is_some_and(|d| d.dot(&g) < 0.0)
            && let Some(c) = self.escaping(x, v, g, true)
        {
            let escape = Escape {
                level: phi,
                early: true,
            };
            return Ok((c, Some(escape)));
        }
        let delta = self.field.floor().delta();
        if still as f64 * self.period >= ESCAPE_STALL
            && self.field.clearance(x, 0.5 * delta, None) < 0.5 * delta
            && let Some(c) = self.escaping(x, v, g, false)
        {
            let escape = Escape {
                level: phi,
                early: false,
            };
            return Ok((c, Some(escape)));
        }
        Ok((self.law_or_in(x, v, &eval), None))
    }

    /// [`FloorNavigator::law_held`], or, where the hold certifies no step at all because `x`
    /// lies on the edge of the certified region (`sd − δ` below [`EDGE`]·δ, zero to rounding:
    /// no step of positive length is certified by the clearance alone), the way out of the
    /// layer ([`FloorNavigator::leave_layer`]: a step straight away from the nearest wall,
    /// certified clear of the walls and the sensed obstacles) instead of a command of zero for
    /// ever.
    fn law_or_in(&self, x: Vector2<f64>, v: Vector2<f64>, eval: &Evaluation) -> Command {
        let command = self.law_held(x, v, eval);
        let floor = self.field.floor();
        let on_edge = floor.signed_distance(x) - floor.delta() < EDGE * floor.delta();
        if command.value == Vector2::zeros() && on_edge {
            return self.leave_layer(x, v).unwrap_or(command);
        }
        command
    }

    /// The escape's command at `x` ([`Mode::Escaping`]): along `heading`, the shortest path's
    /// direction ([`FloorField::geodesic`], [`harmonav_floorplan::Geodesic::heading_near`]),
    /// slid along the edge of the certified region, for one period at the law's top speed or
    /// what the hold certifies of it (`hold::held_length`), never past the goal; `None` where
    /// it is blocked (the law then stands): nothing certified, or, for an escape against the
    /// law (`early`), [`ESCAPE_BLOCKED`] of the step or less.
    fn escaping(
        &self,
        x: Vector2<f64>,
        v: Vector2<f64>,
        heading: Vector2<f64>,
        early: bool,
    ) -> Option<Command> {
        let h = self.period;
        let speed = match &self.controller {
            Controller::Kinematic(law) => law.v_max(),
            Controller::Dynamic(law) => 0.5 * law.speed_bound(),
        };
        let want = (h * speed).min((x - self.goal()).norm());
        let slid = self.field.slide(x, heading, want);
        let norm = slid.norm();
        if !(norm > 1e-3 && want > 0.0) {
            return None;
        }
        let dir = slid / norm;
        let mut length = hold::held_length(&self.field, x, dir, want);
        // Against the law, the dynamic robot keeps the dynamic hold's invariant
        // `h|v⁺| ≤ c·d(x)` (`c` = DYNAMIC_FRACTION, docs/maths.md §10): the step is then
        // certified under the exact hold of the force too (rapier), whose displacement
        // `h(v + v⁺)/2` leaves the segment along `dir`. (A stall's escape slides along the
        // edge, where `d(x)` is about 0 and the cap would stop it: it is certified under
        // semi-implicit Euler, the built-in integrator, alone.)
        if early && matches!(self.controller, Controller::Dynamic(_)) {
            let need = 2.0 * want / hold::DYNAMIC_FRACTION;
            let d = self.field.clearance(x, need, None).max(0.0);
            length = length.min(hold::DYNAMIC_FRACTION * d);
        }
        let least = if early { ESCAPE_BLOCKED * want } else { 0.0 };
        (length > least && length > 0.0).then(|| Command {
            value: moving_along(&self.controller, dir, length, h, v),
            mode: Mode::Escaping,
        })
    }

    /// The law's command under the hold.
    fn law_held(&self, x: Vector2<f64>, v: Vector2<f64>, eval: &Evaluation) -> Command {
        let h = self.period;
        match &self.controller {
            Controller::Dynamic(law) => {
                let d = eval.damping.unwrap_or_else(|| {
                    law.damping_for(
                        (self.field.destination_stiffness(), 0.0),
                        &eval.field,
                        v,
                        self.speed_at_discovery,
                    )
                });
                hold::dynamic(law, &self.field, x, (&eval.field, v), &d, h)
            }
            Controller::Kinematic(law) => {
                hold::kinematic(law, &self.field, x, &eval.field, eval.command, h)
            }
        }
    }

    /// The way out of sensed obstacle `i`'s margin band, as [`crate::Navigator`]'s: along the
    /// ray from its centre to the grown shape's edge, plus half the edge's clearance from
    /// everything else (at most half the margin).
    fn recover(&self, x: Vector2<f64>, v: Vector2<f64>, i: usize) -> Result<Command, NavError> {
        let error = NavError::InObstacle { obstacle: i };
        let Some(inner) = self.inner.get(i) else {
            return Err(error);
        };
        if inner.contains(x) {
            return Err(error);
        }
        let grown = self
            .field
            .transform()
            .obstacles()
            .nth(i)
            .ok_or(error.clone())?;
        let (dir, rho) = certified::ray(grown, x).ok_or(error.clone())?;
        let to_edge = (grown.radius_along(dir).0 - rho).max(0.0);
        let edge = x + to_edge * dir;
        let band = Band::Obstacle(i);
        let room = self
            .field
            .clearance(edge, self.options.margin, Some(band))
            .max(0.0);
        if room <= 0.0 {
            return Err(error);
        }
        let length = to_edge + 0.5 * room;
        Ok(recovering(
            &self.controller,
            band,
            dir,
            length,
            self.period,
            v,
        ))
    }

    /// The way out of the walls' boundary layer (`sd(x) < δ`, the robot's disc clear of the
    /// walls): along `−n`, `n` the unit vector to the nearest point of `∂W_s`, for
    /// `δ − sd(x) + δ/4` (a quarter of `δ` into `W_δ`), halved until the segment is certified:
    /// `sd` grows along it and, by the 1-Lipschitz chord bound `c ≥ (c(x) + c(y) − L)/2`, it
    /// keeps the disc clear of the true walls (`c` the wall distance less the radius) and the
    /// sensed obstacles grown by `radius + margin` (their certified distances). Held for the
    /// period, the command moves along a prefix of that segment (its speed capped as a band's
    /// recovery is). [`NavError::BoundaryLayer`] if no halving certifies.
    fn leave_layer(&self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Command, NavError> {
        // Also from the edge itself (`sd = δ`, [`FloorNavigator::law_or_in`]): the step is then
        // a quarter of δ inwards.
        let floor = self.field.floor();
        let dir = -floor.toward_boundary(x).ok_or(NavError::BoundaryLayer)?;
        let (sd, delta) = (floor.signed_distance(x), floor.delta());
        let walls = |z: Vector2<f64>| floor.wall_distance(z) - self.options.radius;
        let sensed = |z: Vector2<f64>| self.field.clearance(z, f64::INFINITY, Some(Band::Boundary));
        let (w0, s0) = (walls(x), sensed(x));
        let mut length = delta - sd + 0.25 * delta;
        for _ in 0..=hold::MAX_HALVINGS {
            let y = x + length * dir;
            if floor.signed_distance(y) > sd
                && w0 + walls(y) - length > 0.0
                && s0 + sensed(y) - length > 0.0
            {
                return Ok(recovering(
                    &self.controller,
                    Band::Boundary,
                    dir,
                    length,
                    self.period,
                    v,
                ));
            }
            length *= 0.5;
        }
        Err(NavError::BoundaryLayer)
    }

    /// The continuous law at `(x, ẋ)` without the hold and without remembering the state.
    ///
    /// # Errors
    /// As [`FloorNavigator::command`], with the sensed obstacles grown by `radius + margin`.
    pub fn evaluate(&self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Evaluation, NavError> {
        finite_state(x, v)?;
        let e = self.eval(x)?;
        let (command, damping) = match &self.controller {
            Controller::Kinematic(law) => (
                law.velocity_toward(
                    &e,
                    (x - self.field.transform().goal()).norm(),
                    self.field.heading(x, &e),
                ),
                None,
            ),
            Controller::Dynamic(law) => {
                // A floor plan's Θ is free of the world's scale already: no shift.
                let s = self.field.destination_stiffness();
                let d = law.damping_for((s, 0.0), &e, v, self.speed_at_discovery);
                let nominal = self.field.heading(x, &e);
                (law.force_toward((s, 0.0), &e, v, &d, nominal), Some(d))
            }
        };
        Ok(Evaluation {
            command,
            field: e,
            damping,
        })
    }

    /// `Θ` at `x` with the navigator's errors.
    fn eval(&self, x: Vector2<f64>) -> Result<FieldEval, NavError> {
        self.field.eval(x).map_err(|e| match e {
            FieldError::InObstacle { obstacle } => NavError::InObstacle { obstacle },
            FieldError::NotFinite => NavError::NotFinite { what: "position" },
            _ => match self.field.locate(x) {
                Some(NotFree::BoundaryLayer)
                    if self.field.floor().wall_distance(x) > self.options.radius =>
                {
                    NavError::BoundaryLayer
                }
                _ => NavError::OutsideBoundary,
            },
        })
    }

    /// `Θ(x)` (for logging); errors as [`FloorNavigator::evaluate`].
    pub fn theta(&self, x: Vector2<f64>) -> Result<f64, NavError> {
        finite(x, "position")?;
        self.eval(x).map(|e| e.value)
    }

    /// The certified clearance at `x`: a lower bound on the distance to the boundary layer
    /// (`sd(x) − δ`) and to every sensed obstacle grown by `radius + margin`; `−∞` at a
    /// non-finite point.
    pub fn clearance(&self, x: Vector2<f64>) -> f64 {
        if !x.iter().all(|c| c.is_finite()) {
            return f64::NEG_INFINITY;
        }
        self.field.clearance(x, f64::INFINITY, None)
    }

    /// The goal.
    pub fn goal(&self) -> Vector2<f64> {
        self.field.transform().goal()
    }

    /// `Θ` on the floor plan (read only).
    pub fn field(&self) -> &FloorField {
        &self.field
    }

    /// `k` (holes plus sensed obstacles under the k policy).
    pub fn k(&self) -> f64 {
        self.field.k()
    }

    /// The law in use.
    pub fn controller(&self) -> &Controller {
        &self.controller
    }

    /// The speed bound `√(2μ/m)` of the dynamic law, `None` for the kinematic law.
    pub fn speed_bound(&self) -> Option<f64> {
        match &self.controller {
            Controller::Kinematic(_) => None,
            Controller::Dynamic(law) => Some(law.speed_bound()),
        }
    }

    /// The control period `h` in force, s.
    pub fn control_period(&self) -> f64 {
        self.period
    }

    /// The escapes begun so far ([`Mode::Escaping`]), back-to-back ones counted apart (an
    /// escape may end and the next begin within one period, the mode staying `Escaping`).
    pub fn escapes(&self) -> usize {
        self.escapes
    }

    /// `phi_k` where the current escape began, `None` when not escaping.
    pub fn escape_level(&self) -> Option<f64> {
        self.escape.map(|e| e.level)
    }

    /// The options in use.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// `|ẋ(T_n)|`, the speed at the latest discovery that the dynamic law's switched damping
    /// `(m/d_min)|ẋ(T_n)|` uses (eq. `dissipationfun`), lifted by a recovery
    /// ([`FloorNavigator::command`]).
    pub fn discovery_speed(&self) -> f64 {
        self.speed_at_discovery
    }
}

impl From<FloorError> for NavError {
    fn from(e: FloorError) -> Self {
        Self::Floor(e)
    }
}
