//! The online navigator: obstacles become known as the robot's own perception reports them
//! (the paper's assumptions `objknown`, `objpers`), and each call of [`Navigator::command`]
//! returns the command of the law for the current state.

use std::sync::Arc;

use harmonav_perception::Walls;
use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::braking;
use crate::controller::{
    Controller, Evaluation, controller, discovery_speed_after, finite, finite_lambda_c, halted,
};
use crate::error::NavError;
use crate::floor::{Escape, EscapeMemory, FloorWorld, FunnelRun};
use crate::hold::{self, Command};
use crate::law::Law;
use crate::movers::{self, KeepRight, Mover, MoverMemory, Verdict};
use crate::options::Options;
use crate::space::Space;
use crate::star::StarWorld;
use crate::world::{Added, Core, IntoWorld, World, evaluate};
use harmonav_floorplan::Funnels;

/// An online navigator over a world `W` ([`StarWorld`] by default; [`FloorWorld`] for a
/// floor plan, [`FloorNavigator`]): the navigation function `Θ` over the obstacles added so far,
/// and the law. See the crate documentation for a complete loop.
#[derive(Clone, Debug)]
pub struct Navigator<W = StarWorld> {
    /// What every world keeps: the law, the options, the discovery state, the perception and
    /// the movers.
    pub(crate) core: Core,
    /// The workspace: `Θ` over the known obstacles, grown by `radius + margin`, and what the
    /// world keeps of its own.
    pub(crate) world: W,
}

/// An online navigator on a floor plan: the walls are known (a [`FloorMap`](crate::FloorMap), whose harmonic
/// map is solved once), star-shaped obstacles are added as perception finds them.
///
/// **Where it navigates.** Only in the certified region `W_δ = {sd ≥ δ}` ([`FloorMap::delta`](crate::FloorMap::delta),
/// `sd` the distance to the walls shrunk by `s = radius + margin − δ`: `W_δ` is the
/// configuration space with its margin), minus the sensed obstacles grown by
/// `radius + margin`. The hold ([`HoldPolicy::Auto`](crate::HoldPolicy::Auto)) measures its clearance to the
/// boundary layer, `sd(x) − δ`, so every held step stays in `W_δ`. In the layer (`sd < δ`
/// with the robot's disc clear of the walls, reached only by a disturbance) `Θ` is not used:
/// the discrete map is not claimed a diffeomorphism there, and [`FloorNavigator::evaluate`]
/// returns [`NavError::BoundaryLayer`]. [`FloorNavigator::command`] leads the robot out
/// instead ([`Mode::Recovering`](crate::Mode::Recovering) with [`Band::Boundary`](crate::Band::Boundary), as out of a sensed obstacle's margin
/// band): straight away from the nearest wall, by a step certified clear of the walls and of
/// the sensed obstacles (docs/maths.md §13.6).
///
/// **Escapes.** Where a hole's barrier is thinner than the layer, the hold can press the robot
/// against the edge of `W_δ` at a local minimum of `Θ` there (a rest point of its slide,
/// [`FloorField::layer_slide`](harmonav_floorplan::FloorField::layer_slide)). Under the heading policy `"auto"`, a robot that has stayed
/// within `δ/4` of one point for [`ESCAPE_STALL`](crate::tuning::ESCAPE_STALL) s next to that edge follows the shortest path
/// ([`Mode::Escaping`](crate::Mode::Escaping), each step certified free) until `phi_k` is [`ESCAPE_DROP`](crate::tuning::ESCAPE_DROP) below where
/// it stalled, then the law resumes. It does so without a stall, anywhere, where the shortest
/// path's heading `g` turns more than 90° from the law's descent direction `d` (`d·g < 0`) and
/// `phi_k` is [`ESCAPE_DROP`](crate::tuning::ESCAPE_DROP) below where the last such escape began; such an escape also ends
/// when blocked ([`ESCAPE_BLOCKED`](crate::tuning::ESCAPE_BLOCKED); docs/maths.md §13.7, eq. escape-levels).
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
pub type FloorNavigator = Navigator<FloorWorld>;

impl<W: World> Navigator<W> {
    /// A navigator in `workspace` towards `goal`, with no obstacle known yet. `workspace` is
    /// the true boundary of a star world (a [`StarShape`]: a [`Navigator`]), or a floor plan's
    /// solved map (an `Arc<`[`crate::FloorMap`]`>`: a [`crate::FloorNavigator`], which must keep
    /// at least `radius + margin` from the walls: build it with
    /// `FloorOptions::new(h, radius + margin)`).
    ///
    /// Errors: a law parameter (`gain`, `mass`, `mu`) or option outside its range
    /// ([`PARAMETER_RANGE`](crate::tuning::PARAMETER_RANGE), [`Options::validate`]; the error names the field), a
    /// boundary that cannot be shrunk by `radius + margin` (a floor whose `δ` is less than
    /// `radius + margin`: [`NavError::InvalidOption`], `margin`), a goal that is not finite or
    /// not strictly inside the free space.
    pub fn new<S: IntoWorld<World = W>>(
        workspace: S,
        goal: Vector2<f64>,
        law: Law,
        options: Options,
    ) -> Result<Self, NavError> {
        finite(goal, "goal")?;
        let controller = controller(&law, &options)?;
        let (world, scan, controller) = workspace.build(goal, controller, &options)?;
        let core = Core {
            controller,
            options,
            period: options.period_for(&law),
            inner: Vec::new(),
            speed_at_discovery: 0.0,
            last: None,
            scan,
            scan_refused: false,
            movers: Vec::new(),
            rows: Vec::new(),
            along: Vec::new(),
            yielded: false,
            keep_right: KeepRight::default(),
            pose_command: (0.0, 0.0),
            brake: crate::base::Brake::Disc,
            goal_yaw: None,
            goal_tolerance: crate::base::GoalTolerance::default(),
            goal_stateful: true,
            goal_latched: false,
        };
        let nav = Self { core, world };
        // Guard: λ_c (eq. critdamp) overflowed for m = μ = 1e308; within the ranges it is
        // finite, and this checks it once rather than at every command.
        if let Controller::Dynamic(law) = &nav.core.controller {
            let c = nav.world.field().calibration(law);
            finite_lambda_c(law, law.lambda_c_for(c.stiffness, c.shift))?;
        }
        Ok(nav)
    }

    /// Adds an obstacle that the robot's perception has just found (its true shape; it is grown
    /// by `radius + margin` here). `k`, `Phi` and the dynamic law's discovery state (`|ẋ(T_n)|`,
    /// the speed of the last commanded state) update (on a floor plan `B` and the point world;
    /// `H` is reused, no new solve, unless the shape joins the walls). Returns its index.
    /// Allocates (with [`Navigator::observe_scan`], the only calls that do).
    ///
    /// A shape found late, whose margin band already holds the robot, is accepted: the next
    /// [`Navigator::command`] leads out of the band ([`Mode::Recovering`](crate::Mode::Recovering)).
    ///
    /// In a star world, a shape that reaches the boundary once grown (furniture against a
    /// wall) joins it: the field's boundary is cut around it and its shadow as seen from the
    /// boundary's centre (`docs/maths/12-range-scans.md` §12.21); on a floor plan, a shape
    /// whose band reaches the boundary layer joins the walls (`H` solved again without it and
    /// its gap, §12.22). The indices stay; [`Navigator::joined`] lists the joined ones.
    ///
    /// Errors (the navigator is then unchanged): the grown shape overlaps a known obstacle,
    /// reaches the boundary and cannot join it ([`NavError::CrossesBoundary`]; on a floor
    /// plan [`NavError::Floor`], e.g. `CutOff` when the goal or the robot would be behind it),
    /// or contains the goal; the shape grown by `radius` alone contains the robot's last
    /// commanded position; the shape cannot be grown.
    pub fn add_obstacle(&mut self, shape: StarShape) -> Result<usize, NavError> {
        let (grown, inner) = self
            .core
            .options
            .grow(&shape, self.core.last.map(|(x, _)| x))?;
        let added = Added {
            bodies: &self.core.inner,
            body: inner.as_ref(),
            robot: self.core.last.map(|(x, _)| x),
        };
        let index = self.world.admit(grown, added, &self.core.options)?;
        self.core.inner.extend(inner);
        self.core.speed_at_discovery = self.core.last.map_or(0.0, |(_, v)| v.norm());
        self.world.discovered();
        self.core.scan.add_exact(shape, index);
        Ok(index)
    }

    /// The command to hold for one control period at the state `(x, ẋ)`: the velocity `u`
    /// (kinematic law, `ẋ` unused) or the force `f` (dynamic law), with how it was formed.
    /// Does not allocate.
    ///
    /// Under [`HoldPolicy::Auto`](crate::HoldPolicy::Auto) (the default) it is safe when held for the control period
    /// `h` ([`Options::with_control_period`]; 100 Hz kinematic, 1 kHz dynamic by default), by
    /// construction (`docs/maths.md` §10):
    ///
    /// - kinematic (`x += h·u`): the step stays within half the certified distance to the
    ///   nearest known grown shape (on a floor plan: and to the boundary layer), and `Θ`
    ///   strictly decreases over it ([`Mode::Capped`](crate::Mode::Capped) when the law's step was shortened; not
    ///   during an escape, [`Mode::Escaping`](crate::Mode::Escaping), which ends [`ESCAPE_DROP`](crate::tuning::ESCAPE_DROP) below where
    ///   it began, or blocked);
    /// - dynamic (`v += h·f/m, x += h·v`, or the exact hold of `f`): the damping acts
    ///   implicitly, `h|v⁺|` stays within a quarter of the certified distance, and
    ///   `|v⁺| < √(2μ/m)`.
    ///
    /// A robot inside the margin band of a known shape (clear of the true shape by at least
    /// `radius`, after a disturbance or a late perception), or in a floor plan's boundary
    /// layer, gets a command straight out of it ([`Mode::Recovering`](crate::Mode::Recovering)), under either policy.
    /// Under [`HoldPolicy::Paper`](crate::HoldPolicy::Paper) the command is otherwise the continuous law's
    /// (`Navigator::evaluate`), unchecked.
    ///
    /// Under the dynamic law a recovery also lifts the discovery speed `|ẋ(T_n)|` of eq.
    /// `dissipationfun` to at least the speed `|v⁺|` it gives: the event's state is the one in
    /// which the robot leaves the band, where `Θ` is near 1 and the damping may switch to
    /// `(m/d_min)|ẋ(T_n)|`, and the speed recorded at the event (at rest, say) would
    /// understate it.
    ///
    /// After a refused [`Navigator::observe_scan`] the command halts the robot
    /// ([`Mode::Halted`](crate::Mode::Halted)) until a scan is accepted.
    ///
    /// Errors (the navigator is then unchanged): `x` or `ẋ` not finite, the robot's disc
    /// overlapping a known true shape or the boundary (a wall: [`NavError::OutsideBoundary`]),
    /// `x` in a floor plan's boundary layer with no certified way out
    /// ([`NavError::BoundaryLayer`]), a non-finite command (a guard).
    pub fn command(&mut self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Command, NavError> {
        if self.core.scan_refused {
            let c = halted(
                &self.core.controller,
                x,
                v,
                self.core.period,
                &mut self.core.last,
            )?;
            return self.braked(x, v, c, false).map(|(c, _)| c);
        }
        let before = self.core.speed_at_discovery;
        if self.core.yielded {
            // After a period the filter changed, the law's energy may have grown: the dynamic
            // law's switched damping takes the speed now as a discovery speed.
            self.core.speed_at_discovery = before.max(v.norm());
        }
        let result = W::held(&self.core, &self.world, x, v).and_then(|(command, step)| {
            let (command, yielded, memory) = self.filtered(x, v, command)?;
            let nominal = command.value;
            let (command, yielded) = self.braked(x, v, command, yielded)?;
            let memory = self.braked_memory(memory, (x, v), (nominal, command.value), yielded);
            if command.value.iter().all(|c| c.is_finite()) {
                Ok((command, step, yielded, memory))
            } else {
                Err(NavError::NonFiniteCommand)
            }
        });
        let (command, step, yielded, memory) = match result {
            Ok(done) => done,
            Err(e) => {
                self.core.speed_at_discovery = before;
                return Err(e);
            }
        };
        self.core.speed_at_discovery = discovery_speed_after(
            &self.core.controller,
            &command,
            v,
            self.core.period,
            self.core.speed_at_discovery,
        );
        self.core.last = Some((x, v));
        self.core.yielded = yielded;
        self.core.keep_right = memory;
        self.world.after(x, step);
        Ok(command)
    }

    /// Replaces the movers (`docs/movers.md`): every mover is reported afresh each period, so
    /// the list is not kept from one call to the next. All or nothing: a mover that is not
    /// valid is [`NavError::InvalidMover`] and the navigator keeps its movers. Allocates only
    /// when the list is longer than any before.
    ///
    /// From the next [`Navigator::command`] on, the held command is filtered last: kept when
    /// it keeps out of every place a mover can reach within the period (eq. reach), else the
    /// closest certified command ([`Mode::Yielding`](crate::Mode::Yielding)), else the least violation
    /// ([`Mode::Overwhelmed`](crate::Mode::Overwhelmed), not certified against the mover it names).
    pub fn set_movers(&mut self, movers: &[Mover]) -> Result<(), NavError> {
        for (i, m) in movers.iter().enumerate() {
            m.validate(i)?;
        }
        self.core.movers.clear();
        self.core.movers.extend_from_slice(movers);
        // Up to four rows per mover (a reciprocal one with a position error, eq. robust); the
        // rows are rebuilt at every command, so the buffer is cleared first (`reserve` counts
        // from the length).
        self.core.rows.clear();
        self.core.rows.reserve(4 * movers.len());
        Ok(())
    }

    /// The movers of the last [`Navigator::set_movers`].
    pub fn movers(&self) -> &[Mover] {
        &self.core.movers
    }

    /// What the navigator remembers of its movers between commands: KeepRight's memory
    /// (docs/movers.md §7) and whether the filter changed the last command. A copy rebuilt by
    /// replaying the calls that made this navigator (Python's pickle) takes it back with
    /// [`Navigator::set_mover_memory`], so that the commands the filter changed need not be
    /// replayed. The default (all zero, `false`) before the first command and while no mover
    /// has held the robot.
    pub fn mover_memory(&self) -> MoverMemory {
        MoverMemory {
            slow: self.core.keep_right.slow,
            turning: self.core.keep_right.turning,
            yielded: self.core.yielded,
        }
    }

    /// Takes back what [`Navigator::mover_memory`] gave (of this navigator or of one with the
    /// same obstacles, movers and last state): the next commands are then those the original
    /// would give. It changes only the nominal command (KeepRight's turn) and, under the
    /// dynamic law, the discovery speed the next command takes; every command stays certified.
    ///
    /// # Errors
    /// [`NavError::InvalidOption`] naming `mover_memory.slow` (not finite or outside
    /// `[0, 1)` s) or `mover_memory.turning` (not finite or outside `[0, 2]` s); the navigator
    /// is then unchanged.
    pub fn set_mover_memory(&mut self, memory: MoverMemory) -> Result<(), NavError> {
        let memory = memory.validate()?;
        self.core.keep_right = KeepRight {
            slow: memory.slow,
            turning: memory.turning,
        };
        self.core.yielded = memory.yielded;
        Ok(())
    }

    /// `command` filtered against the movers at `(x, ẋ)`, and whether the filter changed it.
    /// Kinematic: the rows on `u`, the static set the hold's sphere tracing (or the one ball
    /// `|u| ≤ min(v_max, β·d(x)/h)`). Dynamic: the rows on `v⁺ = ẋ + h·f/m`, each `ε_j` grown
    /// by the exact hold's deviation `(h/2)(|ẋ| + √(2μ/m))` from the straight step, the static
    /// set `|v⁺| ≤ min((1 − SPEED_SLACK)√(2μ/m), c·d(x)/h)`, and `f = m(v⁺ − ẋ)/h`.
    fn filtered(
        &mut self,
        x: Vector2<f64>,
        v: Vector2<f64>,
        command: Command,
    ) -> Result<(Command, bool, KeepRight), NavError> {
        let memory = self.core.keep_right;
        if self.core.movers.is_empty() {
            return Ok((command, false, memory));
        }
        let h = self.core.period;
        let options = &self.core.options;
        let inflation = options.inflation();
        // Under a force bound the movers are kept out of by the braking certificate
        // ([`Navigator::braked`]), not by the rows of one period; KeepRight turns the velocity
        // the nominal force leads to (the certificate then certifies whatever it becomes).
        if let (Some(_), Controller::Dynamic(law)) = (options.force_bound, &self.core.controller) {
            if matches!(command.mode, hold::Mode::Recovering(_) | hold::Mode::Halted) {
                return Ok((command, false, memory));
            }
            let m = law.mass();
            let next = v + (h / m) * command.value;
            let turn = memory.turn(&self.core.movers, x, next, inflation);
            if turn > 0.0 {
                let value = (m / h) * (movers::clockwise(next, turn) - v);
                return Ok((Command { value, ..command }, false, memory));
            }
            return Ok((command, false, memory));
        }
        let body = (x, options.radius, options.margin);
        let field = self.world.field();
        let far = (x - self.world.goal()).norm() > 2.0 * inflation;
        // KeepRight turns the nominal only (docs/movers.md §7); the filter certifies it.
        let turned = |u: Vector2<f64>, movers: &[Mover]| {
            let turn = memory.turn(movers, x, u, inflation);
            if turn > 0.0 {
                (movers::clockwise(u, turn), false)
            } else {
                (u, true)
            }
        };
        let comfort = options.comfort;
        let (value, verdict, speeds) = match &self.core.controller {
            Controller::Kinematic(law) => {
                let v_max = law.v_max();
                let nominal = turned(command.value, &self.core.movers);
                let (movers, rows) = (&self.core.movers, &mut self.core.rows);
                // The comfort stage turns the nominal first (its rows in the same scratch).
                let nominal =
                    movers::comfort(movers, body, (h, 0.0, comfort), rows, nominal, v_max)?;
                movers::rows(movers, body, h, 0.0, rows)?;
                let d = field.clearance(x, 2.0 * h * v_max / hold::KINEMATIC_FRACTION, None);
                let small = v_max.min(hold::KINEMATIC_FRACTION * d.max(0.0) / h);
                let certified = |u: Vector2<f64>| {
                    let length = h * u.norm();
                    length == 0.0 || hold::free_length(field, x, u / u.norm(), length) >= length
                };
                let (u, verdict) = movers::filter(rows, nominal, v_max, certified, small);
                (u, verdict, (u.norm(), command.value.norm()))
            }
            Controller::Dynamic(law) => {
                let (m, bound) = (law.mass(), law.speed_bound());
                let extra = 0.5 * h * (v.norm() + bound);
                let next = v + (h / m) * command.value;
                let cap = (1.0 - hold::SPEED_SLACK) * bound;
                let d = field.clearance(x, 2.0 * h * cap / hold::DYNAMIC_FRACTION, None);
                let r = cap.min(hold::DYNAMIC_FRACTION * d.max(0.0) / h);
                let nominal = turned(next, &self.core.movers);
                let (movers, rows) = (&self.core.movers, &mut self.core.rows);
                let nominal = movers::comfort(movers, body, (h, extra, comfort), rows, nominal, r)?;
                movers::rows(movers, body, h, extra, rows)?;
                let (after, verdict) = movers::filter(rows, nominal, r, |_| true, r);
                ((m / h) * (after - v), verdict, (after.norm(), next.norm()))
            }
        };
        let yielded = verdict != Verdict::Kept;
        let memory = memory.after(speeds, yielded, far, h);
        if !yielded {
            return Ok((command, false, memory));
        }
        let mode = verdict.mode_or(command.mode);
        Ok((Command { value, mode }, true, memory))
    }

    /// The dynamic law's command under a force bound `F` ([`Options::force_bound`],
    /// `crate::braking::bounded`, docs/movers.md §2): within `|f| ≤ F`, and certified to leave
    /// the robot a way to brake to rest inside the known free space and out of every mover's
    /// reach; the command itself if it is (bit for bit), else the nearest such force towards
    /// the full brake (`Mode::Bounded`, or `Mode::Yielding` where a mover binds), else the
    /// full brake (`Mode::Braking` or `Mode::Overwhelmed`, not certified). The halt after a
    /// refused scan (`Mode::Halted`) is the full brake, kept `Halted` only if its way to rest
    /// is certified; the way out of the margin band (`Mode::Recovering`) is scaled to `F` and
    /// kept while it still leads out and clear of the movers' caps, else braked (not
    /// certified). `yielded`: whether a mover changed the command (returned as is without a
    /// bound).
    fn braked(
        &self,
        x: Vector2<f64>,
        v: Vector2<f64>,
        command: Command,
        yielded: bool,
    ) -> Result<(Command, bool), NavError> {
        let (Some(force_bound), Controller::Dynamic(law)) =
            (self.core.options.force_bound, &self.core.controller)
        else {
            return Ok((command, yielded));
        };
        let options = &self.core.options;
        let (value, verdict) = braking::bounded(
            self.world.field(),
            &self.core.movers,
            (x, options.radius, options.margin),
            (v, command.value, command.mode),
            (law.mass(), self.core.period, force_bound),
        )?;
        let by_mover = matches!(
            verdict,
            braking::Verdict::Overwhelmed { .. }
                | braking::Verdict::Shortened { mover: Some(_), .. }
        );
        Ok((
            Command {
                value,
                mode: verdict.mode_or(command.mode),
            },
            yielded || by_mover,
        ))
    }

    /// KeepRight's memory after a command under a force bound among movers (docs/movers.md
    /// §7): slow while the braking certificate keeps `|v⁺|` (of the force `kept`) below ⅕ of
    /// the speed the `nominal` force (KeepRight's turn included) led to, and a mover bound it
    /// (`yielded`); `memory` as it is otherwise (without a bound [`Navigator::filtered`]
    /// updates it).
    fn braked_memory(
        &self,
        memory: KeepRight,
        (x, v): (Vector2<f64>, Vector2<f64>),
        (nominal, kept): (Vector2<f64>, Vector2<f64>),
        yielded: bool,
    ) -> KeepRight {
        let (Some(_), Controller::Dynamic(law)) =
            (self.core.options.force_bound, &self.core.controller)
        else {
            return memory;
        };
        if self.core.movers.is_empty() {
            return memory;
        }
        let (h, m) = (self.core.period, law.mass());
        let speed = |f: Vector2<f64>| (v + (h / m) * f).norm();
        let far = (x - self.world.goal()).norm() > 2.0 * self.core.options.inflation();
        memory.after((speed(kept), speed(nominal)), yielded, far, h)
    }

    /// The continuous law at the state `(x, ẋ)` with what it is made of (`Θ`, `∇Θ`, the
    /// damping), without remembering the state and without the hold: for integrators of the
    /// continuous closed loop that evaluate trial states, and for logging. Does not allocate.
    /// On a floor plan the law turns towards the shortest path's heading, if built
    /// ([`HeadingPolicy`](crate::HeadingPolicy)).
    ///
    /// Errors: `x` or `ẋ` not finite, `x` inside a known obstacle grown by `radius + margin`
    /// or outside the boundary shrunk by it (in a floor plan's boundary layer with the disc
    /// clear of the walls: [`NavError::BoundaryLayer`]).
    pub fn evaluate(&self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Evaluation, NavError> {
        evaluate(&self.core, &self.world, x, v)
    }

    /// `Θ(x)` over the known obstacles (for logging); errors as [`Navigator::evaluate`].
    pub fn theta(&self, x: Vector2<f64>) -> Result<f64, NavError> {
        finite(x, "position")?;
        self.world.eval(x, &self.core.options).map(|e| e.value)
    }

    /// The goal.
    pub fn goal(&self) -> Vector2<f64> {
        self.world.goal()
    }

    /// The law in use.
    pub fn controller(&self) -> &Controller {
        &self.core.controller
    }

    /// `Θ` over the known obstacles (read only): a [`harmonav_field::Field`] in a star world,
    /// a [`harmonav_floorplan::FloorField`] on a floor plan.
    pub fn field(&self) -> &W::Field {
        self.world.field()
    }

    /// Every known obstacle, grown by `radius + margin`, in the navigator's order (the indices
    /// of [`Navigator::add_obstacle`] and [`Navigator::perceived`]), those joined to the
    /// boundary or walls included. A star world's `obstacles` borrows the same list.
    pub fn known_obstacles(&self) -> std::borrow::Cow<'_, [StarShape]> {
        self.world.known()
    }

    /// The indices of the known obstacles (as [`Navigator::add_obstacle`] returned them, or
    /// [`Navigator::perceived`] gives them) that joined the workspace's boundary (a star world,
    /// `docs/maths/12-range-scans.md` §12.21) or a floor plan's walls (`H` solved again,
    /// §12.22): furniture against a wall, whose gap to the wall is closed. Sorted; empty while
    /// none did.
    pub fn joined(&self) -> &[usize] {
        self.world.joined()
    }

    /// `k` of `phi_k` for the known obstacles (on a floor plan: the holes and the sensed
    /// obstacles, under the k policy).
    pub fn k(&self) -> f64 {
        self.world.k()
    }

    /// The speed bound `√(2μ/m)` of the dynamic law (corollary `boundedvel`), `None` for the
    /// kinematic law.
    pub fn speed_bound(&self) -> Option<f64> {
        match &self.core.controller {
            Controller::Kinematic(_) => None,
            Controller::Dynamic(law) => Some(law.speed_bound()),
        }
    }

    /// The control period `h` in force, s ([`Options::control_period`] or the law's default).
    pub fn control_period(&self) -> f64 {
        self.core.period
    }

    /// The certified clearance at `x`: a lower bound on the distance to the nearest known grown
    /// obstacle and to the shrunk boundary (on a floor plan: to the boundary layer,
    /// `sd(x) − δ`); 0 or less outside the free space, `−∞` at a non-finite point. It is the
    /// quantity the hold of [`Navigator::command`] keeps its steps within. Within the
    /// certificate's tolerance of a shape that is not a circle (about 1e-4 of its size) it may
    /// be 0 or less at a free point.
    pub fn clearance(&self, x: Vector2<f64>) -> f64 {
        if !x.iter().all(|c| c.is_finite()) {
            return f64::NEG_INFINITY;
        }
        self.world.field().clearance(x, f64::INFINITY, None)
    }

    /// The options in use.
    pub fn options(&self) -> &Options {
        &self.core.options
    }

    /// `|ẋ(T_n)|`, the speed at the latest discovery that the dynamic law's switched damping
    /// `(m/d_min)|ẋ(T_n)|` uses (eq. `dissipationfun`), lifted by a recovery
    /// ([`Navigator::command`]).
    pub fn discovery_speed(&self) -> f64 {
        self.core.speed_at_discovery
    }
}

impl Navigator<StarWorld> {
    /// The known obstacles, grown by `radius + margin`, in the order they were added.
    pub fn obstacles(&self) -> &[StarShape] {
        self.world.obstacles()
    }
}

impl Navigator<FloorWorld> {
    /// Follows the chain of certified funnels `chain` (docs/maths.md §13.10; built by
    /// [`harmonav_floorplan::FloorField::funnels`] on this navigator's walls): from every
    /// point of their union the kinematic law's convergence to the goal is certified (the
    /// walls' `Θ`, before any obstacle is sensed, as `c_δ` and `c_s`). At each command the
    /// robot in funnel `i` moves to `i`'s parent once the parent's funnel holds it (in none,
    /// to the least funnel that holds it); in a funnel `Θ` runs towards its goal, the
    /// shortest path's heading still towards the navigator's goal, and no escape begins. An
    /// obstacle that joins the walls (a new `H`) drops the chain. Replaces a chain followed
    /// before.
    ///
    /// # Errors
    /// [`NavError::InvalidFunnels`] (the navigator unchanged) when the law is not the
    /// kinematic one (the funnels are sublevel sets of `Θ`, not of the dynamic law's energy),
    /// the chain's goal, floor or `k` policy is not this navigator's, or an obstacle has
    /// joined the walls.
    pub fn set_funnels(&mut self, chain: Arc<Funnels>) -> Result<(), NavError> {
        let bad = |reason| Err(NavError::InvalidFunnels { reason });
        let Some(root) = chain.funnels.first() else {
            return bad("is empty");
        };
        if !matches!(self.core.controller, Controller::Kinematic(_)) {
            return bad("needs the kinematic law");
        }
        if root.goal != self.goal() {
            return bad("leads to another goal");
        }
        if self.world.joined.any() || !Arc::ptr_eq(root.field.floor(), self.world.field.floor()) {
            return bad("was built on another floor plan (or an obstacle has joined the walls)");
        }
        if root.field.k_policy() != self.world.field.k_policy() {
            return bad("was built with another k policy");
        }
        self.clear_funnels()?;
        self.world.funnels = Some(FunnelRun {
            chain,
            current: None,
        });
        Ok(())
    }

    /// Stops following the chain of funnels ([`Navigator::set_funnels`]): `Θ` runs towards
    /// the goal again.
    ///
    /// # Errors
    /// As [`Navigator::add_obstacle`] if the goal's field cannot take the sensed obstacles
    /// (the navigator unchanged).
    pub fn clear_funnels(&mut self) -> Result<(), NavError> {
        let root = self.world.root_field()?;
        self.world.field = root;
        self.world.funnels = None;
        Ok(())
    }

    /// The chain of funnels followed, if any, and the funnel the robot was last in (`None`
    /// before the first command in one).
    pub fn funnels(&self) -> Option<(&Arc<Funnels>, Option<usize>)> {
        self.world
            .funnels
            .as_ref()
            .map(|run| (&run.chain, run.current))
    }

    /// The floor plan's true walls as polygon rings, against which
    /// [`Navigator::observe_scan`] explains hits (and a simulator casts its lidar).
    pub fn walls(&self) -> &Arc<Walls> {
        &self.world.walls
    }

    /// The escapes begun so far ([`Mode::Escaping`](crate::Mode::Escaping)), back-to-back ones counted apart (an
    /// escape may end and the next begin within one period, the mode staying `Escaping`).
    pub fn escapes(&self) -> usize {
        self.world.escapes
    }

    /// `phi_k` where the current escape began, `None` when not escaping.
    pub fn escape_level(&self) -> Option<f64> {
        self.world.escape.map(|e| e.level)
    }

    /// What the floor world remembers of its escapes between commands: a copy rebuilt by
    /// replaying the calls that made this navigator (Python's pickle) does not rebuild it, and
    /// takes it back with [`Navigator::set_escape_memory`].
    pub fn escape_memory(&self) -> EscapeMemory {
        let w = &self.world;
        EscapeMemory {
            escape: w.escape.map(|e| (e.level, e.early)),
            early_level: w.early_level,
            escapes: w.escapes,
            anchor: w.anchor,
        }
    }

    /// Takes back what [`Navigator::escape_memory`] gave (of this navigator or of one with the
    /// same obstacles): the next commands are then those the original would give. It changes
    /// only the nominal command (an escape's heading, when one begins or ends); every command
    /// stays certified by the hold.
    ///
    /// # Errors
    /// [`NavError::NotFinite`] (`"escape memory"`) for a level or anchor that is not finite
    /// (the navigator unchanged).
    pub fn set_escape_memory(&mut self, memory: EscapeMemory) -> Result<(), NavError> {
        let finite = memory.escape.is_none_or(|(level, _)| level.is_finite())
            && memory.early_level.is_none_or(f64::is_finite)
            && memory
                .anchor
                .is_none_or(|(a, _)| a.x.is_finite() && a.y.is_finite());
        if !finite {
            return Err(NavError::NotFinite {
                what: "escape memory",
            });
        }
        let w = &mut self.world;
        w.escape = memory.escape.map(|(level, early)| Escape { level, early });
        w.early_level = memory.early_level;
        w.escapes = memory.escapes;
        w.anchor = memory.anchor;
        Ok(())
    }
}

#[cfg(test)]
mod recovery_tests {
    use super::*;
    use crate::controller::event_speed;
    use crate::hold::Mode;

    /// Eq. eventstop: the speed handed to the switched damping makes its stopping distance the
    /// event's room `d_e` (to the grown shape, or in the band to the body) when that is below
    /// `d_min`: `(m/d_min)·s = (m/d_e)|ẋ(T_n)|`; at or beyond `d_min`, and for a room of 0 or
    /// less, NaN or the kinematic law, the speed stands.
    #[test]
    fn a_scan_event_brakes_within_its_own_room() {
        let options = Options::default().with_sensor(2.0, 360.0).with_rho_min(0.1);
        let dynamic = controller(&Law::dynamic(2.0, 1.0), &options).unwrap();
        let Controller::Dynamic(law) = &dynamic else {
            unreachable!()
        };
        let (d_min, m) = (law.d_min(), law.mass());
        assert!(d_min > 0.5, "{d_min}");
        let switched = |s: f64| m / d_min * s;
        let s = event_speed(&dynamic, 1.5, 0.1, 0.05);
        assert!((switched(s) - m / 0.1 * 1.5).abs() < 1e-9, "{s}");
        // In the margin band: the room to the body, clearance + margin.
        let s = event_speed(&dynamic, 1.5, -0.02, 0.05);
        assert!((switched(s) - m / 0.03 * 1.5).abs() < 1e-9, "{s}");
        for clearance in [d_min, 2.0 * d_min, -0.1, f64::NAN, f64::INFINITY] {
            assert_eq!(
                event_speed(&dynamic, 1.5, clearance, 0.05),
                1.5,
                "{clearance}"
            );
        }
        let kinematic = controller(&Law::kinematic(1.0), &options).unwrap();
        assert_eq!(event_speed(&kinematic, 1.5, 0.1, 0.05), 1.5);
    }

    /// A dynamic robot at rest in the margin band of a shape perceived late: its discovery
    /// speed was 0 at the event, and the recovery command lifts it to the speed `|v⁺|` that
    /// the command gives (semi-implicit Euler over the control period), which the switched
    /// damping then uses; a kinematic robot's is left alone.
    #[test]
    fn a_recovery_lifts_the_discovery_speed() {
        let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
        let rock = StarShape::circle(Vector2::zeros(), 1.0).unwrap();
        let goal = Vector2::new(3.0, 0.0);
        for law in [Law::dynamic(1.0, 10.0), Law::kinematic(1.0)] {
            let options = Options::default().with_robot(0.1, 0.2);
            let mut nav = Navigator::new(boundary.clone(), goal, law, options).unwrap();
            let x = Vector2::new(-1.2, 0.05);
            nav.command(x, Vector2::zeros()).unwrap();
            nav.add_obstacle(rock.clone()).unwrap();
            assert_eq!(nav.core.speed_at_discovery, 0.0);
            let c = nav.command(x, Vector2::zeros()).unwrap();
            assert!(matches!(c.mode, Mode::Recovering(_)), "{:?}", c.mode);
            match law {
                Law::Dynamic { mass, .. } => {
                    let v_next = (nav.core.period / mass) * c.value;
                    assert!(v_next.norm() > 0.0);
                    assert_eq!(nav.core.speed_at_discovery, v_next.norm());
                }
                Law::Kinematic { .. } => assert_eq!(nav.core.speed_at_discovery, 0.0),
            }
        }
    }
}
