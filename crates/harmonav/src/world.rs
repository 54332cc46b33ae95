//! [`World`]: what a navigator needs of its workspace, so that one navigator serves the two
//! navigation transformations of `Θ = σ∘φ_k∘Φ` (`docs/maths.md` §10, §13): a star world
//! (`StarWorld`, `Φ = T` the star bands of the workspace's boundary and obstacles) and a floor
//! plan (`FloorWorld`, `Φ = S∘M_a∘H∘B` through the harmonic map of its walls).
//!
//! A world gives `Θ` and `∇Θ`, the certified clearance `d(x)`, admits an obstacle, takes a
//! scan's event, leads the robot out of a margin band or boundary layer, and has its own rest
//! policy (a star world steps off a rest point of the hold, [`Mode::FromRest`]; a floor plan
//! follows its shortest path out of a stall, [`Mode::Escaping`]). The trait is sealed: its
//! methods are the navigator's, and a new world is a change to this crate. The navigator's
//! `command` is monomorphised over it: no `dyn` in the control path.
//!
//! What every world shares is [`Core`] (the law, the options, the discovery state, the scan
//! perception, the movers) and the continuous law through the world's `Θ` ([`evaluate`],
//! [`law_held`]); the navigator is a `Core` and a world.

use std::borrow::Cow;
use std::fmt;

use harmonav_field::FieldEval;
use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::controller::{Controller, Evaluation, finite_state};
use crate::error::NavError;
use crate::event::ScanEvent;
use crate::hold::{self, Command, Mode};
use crate::movers::program::Row;
use crate::movers::{KeepRight, Mover};
use crate::options::{HoldPolicy, Options};
use crate::scanning::ScanState;
use crate::space::Space;

/// A workspace a navigator navigates: a star world (`StarWorld`) or a floor plan
/// (`FloorWorld`). Sealed. Its `Θ`, read through `Navigator::field`, is a
/// [`harmonav_field::Field`] or a [`harmonav_floorplan::FloorField`].
pub trait World: Rules + Clone + fmt::Debug {}

/// What a navigator is built on (`Navigator::new`): the workspace's true boundary (a
/// [`StarShape`], giving a star world) or a floor plan's solved map
/// (`Arc<`[`harmonav_floorplan::FloorMap`]`>`, giving a floor world). Sealed.
pub trait IntoWorld: Build {}

impl<T: Build> IntoWorld for T {}

/// The sealed half of [`IntoWorld`]: builds the world.
pub trait Build {
    /// The world it builds.
    type World: World;
    /// The world towards `goal` (finite) for `controller` under `options` (validated), with its
    /// empty scan perception and the controller in a world of its size
    /// (`Controller::in_world`).
    ///
    /// # Errors
    /// As `Navigator::new`.
    fn build(
        self,
        goal: Vector2<f64>,
        controller: Controller,
        options: &Options,
    ) -> Result<(Self::World, ScanState, Controller), NavError>;
}

/// What a navigator keeps whatever its world: the law and its options, the discovery state,
/// the scan perception and the movers.
#[derive(Clone, Debug)]
pub struct Core {
    pub(crate) controller: Controller,
    pub(crate) options: Options,
    /// The control period `h` in force (s).
    pub(crate) period: f64,
    /// The known shapes grown by `radius` alone: the robot's disc overlaps a true shape iff
    /// its centre is in one of these. Empty with no margin.
    pub(crate) inner: Vec<StarShape>,
    /// `|ẋ(T_n)|` at the latest discovery (eq. `dissipationfun`).
    pub(crate) speed_at_discovery: f64,
    /// The last state passed to a successful `command`.
    pub(crate) last: Option<(Vector2<f64>, Vector2<f64>)>,
    /// The scan perception: the true boundary or walls, the exact shapes of `add_obstacle`,
    /// the perceived shapes and where each sits among the obstacles (`observe_scan`).
    pub(crate) scan: ScanState,
    /// The last scan was refused: commands halt the robot ([`Mode::Halted`]) until one is
    /// accepted.
    pub(crate) scan_refused: bool,
    /// The movers of the last `set_movers`.
    pub(crate) movers: Vec<Mover>,
    /// The filter's rows, rebuilt at each command (their capacity kept: no allocation).
    pub(crate) rows: Vec<Row>,
    /// A differential drive's `m_j` of each row along its arc (`command_pose`), rebuilt with
    /// the rows (their capacity kept).
    pub(crate) along: Vec<f64>,
    /// The last command was changed by the mover filter.
    pub(crate) yielded: bool,
    /// The deadlock rule's memory (it turns the nominal command only).
    pub(crate) keep_right: KeepRight,
    /// The `(v, ω)` of the last successful `command_pose` (`(0, 0)` before the first: the
    /// base starts at rest), from which a base's acceleration limits count
    /// ([`crate::Accel`]).
    pub(crate) pose_command: (f64, f64),
    /// How the last `command_pose`'s braking was certified, under acceleration limits.
    pub(crate) brake: crate::base::Brake,
    /// The goal yaw of a differential-drive base, rad (`Navigator::set_goal_heading`; `None`:
    /// none, the default).
    pub(crate) goal_yaw: Option<f64>,
    /// Where a goal with a yaw has arrived (`Navigator::set_goal_tolerance`).
    pub(crate) goal_tolerance: crate::base::GoalTolerance,
    /// Whether the position tolerance latches (`Navigator::set_goal_stateful`; Nav2's
    /// `stateful`, default true).
    pub(crate) goal_stateful: bool,
    /// A pose within `goal_tolerance.xy` of the goal has been commanded since the goal yaw,
    /// the tolerance or `goal_stateful` last changed (`Navigator::goal_latched`).
    pub(crate) goal_latched: bool,
}

/// What [`Rules::admit`] may need besides the grown shape: the known shapes grown by `radius`
/// alone (the navigator's `inner`), the new one's, and the robot's last position (a star world
/// whose boundary takes the shape in keeps the robot inside, [`crate::joined`]).
pub struct Added<'a> {
    /// The known obstacles grown by `radius` alone (empty without a margin).
    pub(crate) bodies: &'a [StarShape],
    /// The new obstacle grown by `radius` alone (`None` without a margin).
    pub(crate) body: Option<&'a StarShape>,
    /// The robot's last commanded position.
    pub(crate) robot: Option<Vector2<f64>>,
}

/// The sealed half of [`World`]: the navigator's steps that differ between the worlds. The
/// steps both share are the navigator's own, and [`evaluate`] and [`law_held`].
pub trait Rules: Sized {
    /// `Θ` over this world's known obstacles, with its free space as the hold sees it.
    type Field: Space + fmt::Debug;
    /// What a successful command leaves for [`Rules::after`] (a floor plan's escape).
    type Step;
    /// `Θ` (read only).
    fn field(&self) -> &Self::Field;
    /// The navigator's goal (a floor plan's chain of funnels runs `Θ` towards intermediate
    /// goals, [`crate::FloorNavigator::set_funnels`]).
    fn goal(&self) -> Vector2<f64> {
        self.field().goal()
    }
    /// `Θ`, `∇Θ` and the direction at `x` with the navigator's errors (`options`: the robot's
    /// size, to tell a boundary layer from a collision).
    fn eval(&self, x: Vector2<f64>, options: &Options) -> Result<FieldEval, NavError>;
    /// The known obstacles, grown by `radius + margin`, in the navigator's order.
    fn known(&self) -> Cow<'_, [StarShape]>;
    /// `k` of `phi_k`.
    fn k(&self) -> f64;
    /// The navigator's indices of the known obstacles that joined the boundary or the walls
    /// (furniture against a wall), sorted.
    fn joined(&self) -> &[usize];
    /// Admits the grown obstacle `grown` (validated before anything changes); its index.
    ///
    /// # Errors
    /// The world is then unchanged: the shape overlaps another, crosses the boundary (or
    /// reaches a floor plan's boundary layer), or contains the goal.
    fn admit(
        &mut self,
        grown: StarShape,
        added: Added<'_>,
        options: &Options,
    ) -> Result<usize, NavError>;
    /// Takes a scan's event: the obstacles become `event.obstacles`.
    ///
    /// # Errors
    /// As [`Rules::admit`], the world unchanged.
    fn sensed(&mut self, event: &ScanEvent, options: &Options) -> Result<(), NavError>;
    /// A discovery (an obstacle admitted or a scan's event) resets the world's own state.
    fn discovered(&mut self) {}
    /// The command to hold at `(x, ẋ)` and what it leaves for [`Rules::after`].
    ///
    /// # Errors
    /// As `Navigator::command`.
    fn held(
        core: &Core,
        world: &Self,
        x: Vector2<f64>,
        v: Vector2<f64>,
    ) -> Result<(Command, Self::Step), NavError>;
    /// After a successful command at `x`.
    fn after(&mut self, x: Vector2<f64>, step: Self::Step);
}

/// The continuous law at the state `(x, ẋ)` over `world`'s `Θ`, with what it is made of: the
/// kinematic law `u = s(x)·d` (turned towards the world's nominal heading, if any) or the
/// dynamic law `f = −μ_p∇Ψ − λẋ` (with the heading force) on the world's [`Space::calibration`].
///
/// # Errors
/// `x` or `ẋ` not finite, `x` not in the free space ([`Rules::eval`]).
pub(crate) fn evaluate<W: Rules>(
    core: &Core,
    world: &W,
    x: Vector2<f64>,
    v: Vector2<f64>,
) -> Result<Evaluation, NavError> {
    finite_state(x, v)?;
    let e = world.eval(x, &core.options)?;
    let field = world.field();
    let nominal = field.heading(x, &e);
    let (command, damping) = match &core.controller {
        Controller::Kinematic(law) => (
            law.velocity_toward(&e, (x - field.goal()).norm(), nominal),
            None,
        ),
        Controller::Dynamic(law) => {
            let calibration = field.calibration(law);
            let d = law.damping_for(calibration, &e, v, core.speed_at_discovery);
            (law.force_toward(calibration, &e, v, &d, nominal), Some(d))
        }
    };
    Ok(Evaluation {
        command,
        field: e,
        damping,
    })
}

/// The law's command under the hold at `(x, ẋ)` evaluated as `eval` (the continuous law's
/// command under [`HoldPolicy::Paper`]): for the dynamic law, `hold::dynamic` with the damping
/// of `eval`; for the kinematic law, `hold::kinematic`.
pub(crate) fn law_held<W: Rules>(
    core: &Core,
    world: &W,
    x: Vector2<f64>,
    v: Vector2<f64>,
    eval: &Evaluation,
) -> Command {
    if core.options.hold == HoldPolicy::Paper {
        return Command {
            value: eval.command,
            mode: Mode::Law,
        };
    }
    let (h, field) = (core.period, world.field());
    match &core.controller {
        Controller::Dynamic(law) => {
            // `evaluate` gives the dynamic law's damping; computed again only if it did not.
            let d = eval.damping.unwrap_or_else(|| {
                law.damping_for(
                    field.calibration(law),
                    &eval.field,
                    v,
                    core.speed_at_discovery,
                )
            });
            hold::dynamic(law, field, x, (&eval.field, v), &d, h)
        }
        Controller::Kinematic(law) => hold::kinematic(law, field, x, &eval.field, eval.command, h),
    }
}
