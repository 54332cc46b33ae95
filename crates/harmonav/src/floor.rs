//! [`FloorWorld`]: a floor plan (issue 25): `Θ` through `Phi = S ∘ M_a ∘ H ∘ B`
//! (harmonav-floorplan; `M_a` the identity unless the plan recentres on its goal), obstacles
//! sensed online inside the plan (no new solve of `H` when one is added), and its rest policy,
//! the escapes along the shortest path. [`FloorNavigator`] is the navigator over it.

use std::borrow::Cow;
use std::sync::Arc;

use harmonav_control::HeadingPolicy;
use harmonav_field::{FieldError, FieldEval};
use harmonav_floorplan::{FloorError, FloorField, FloorMap, Funnels, NotFree};
use harmonav_perception::{PerceptionError, Walls};
use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::certified::{self, Band};
use crate::controller::{Controller, Evaluation, moving_along, recovering};
use crate::error::NavError;
use crate::event::ScanEvent;
use crate::floor_joined::FloorJoined;
use crate::hold::{self, Command, Mode};
use crate::joined::Known;
use crate::options::{HoldPolicy, Options};
use crate::scanning::ScanState;
use crate::space::Space;
use crate::world::{Added, Build, Core, Rules, World, evaluate, law_held};

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
pub(crate) struct Escape {
    /// `phi_k` where it began.
    pub(crate) level: f64,
    /// Begun against the law (the shortest path's heading more than 90° from the descent
    /// direction), not after a stall; it also ends when blocked in the sense of
    /// [`ESCAPE_BLOCKED`].
    pub(crate) early: bool,
}

/// What a floor navigator remembers of its escapes ([`Mode::Escaping`], docs/maths.md §13.7)
/// between commands, as [`crate::FloorNavigator::escape_memory`] gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EscapeMemory {
    /// The escape under way: `phi_k` where it began, and whether it began against the law.
    pub escape: Option<(f64, bool)>,
    /// `phi_k` where the last escape against the law began (eq. escape-levels).
    pub early_level: Option<f64>,
    /// Escapes begun so far.
    pub escapes: usize,
    /// The point the robot has stayed within `δ/4` of, and for how many periods.
    pub anchor: Option<(Vector2<f64>, usize)>,
}

/// A floor plan as a navigator's world: `Θ` over the holes and the sensed obstacles (grown by
/// `radius + margin`), the true walls, and the escapes ([`Mode::Escaping`]).
#[derive(Clone, Debug)]
pub struct FloorWorld {
    /// `Θ` over the holes and the sensed obstacles (grown by `radius + margin`).
    pub(crate) field: FloorField,
    /// The true walls, as the perception holds them (one shared copy).
    pub(crate) walls: Arc<Walls>,
    /// The current escape ([`Mode::Escaping`]), if escaping.
    pub(crate) escape: Option<Escape>,
    /// `phi_k` where the last escape against the law began: another may begin only
    /// [`ESCAPE_DROP`] below it (eq. escape-levels of docs/maths.md §13.7).
    pub(crate) early_level: Option<f64>,
    /// Escapes begun so far.
    pub(crate) escapes: usize,
    /// The point the robot has stayed within `δ/4` of, and for how many periods.
    pub(crate) anchor: Option<(Vector2<f64>, usize)>,
    /// The obstacles that joined the walls, and the floor before they did
    /// ([`crate::floor_joined`]).
    pub(crate) joined: FloorJoined,
    /// The chain of certified funnels followed, if any ([`crate::FloorNavigator::set_funnels`]).
    pub(crate) funnels: Option<FunnelRun>,
}

/// The chain of certified funnels a floor navigator follows (docs/maths.md §13.10): while the
/// robot is in funnel `i`, `field` is `Θ_i` (towards the funnel's goal, with the sensed
/// obstacles and the shortest path to the navigator's goal); the navigator moves to `i`'s
/// parent once the robot lies in the parent's funnel ([`harmonav_floorplan::Funnel::holds`]),
/// never back.
#[derive(Clone, Debug)]
pub(crate) struct FunnelRun {
    pub(crate) chain: Arc<Funnels>,
    /// The funnel whose goal `field` runs towards; `None` while the robot has been in none
    /// (`field` then runs towards the navigator's goal, as without a chain).
    pub(crate) current: Option<usize>,
}

/// A floor navigator's step: the escape after the command and the point the robot stays near.
pub struct FloorStep {
    escape: Option<Escape>,
    anchor: (Vector2<f64>, usize),
    /// The funnel entered at this command, and its field.
    funnel: Option<(usize, FloorField)>,
}

impl Build for Arc<FloorMap> {
    type World = FloorWorld;

    /// `floor` must keep at least `radius + margin` from the walls (build it with
    /// `FloorOptions::new(h, radius + margin)`: then `W_δ` is the walls' erosion by
    /// `s + δ = max(radius + margin, δ)`); `radius + margin` larger than the floor's `δ` is
    /// [`NavError::InvalidOption`] (`margin`), a goal not in `W_δ` [`NavError::Floor`].
    fn build(
        self,
        goal: Vector2<f64>,
        controller: Controller,
        options: &Options,
    ) -> Result<(FloorWorld, ScanState, Controller), NavError> {
        let floor = self;
        let inflation = options.inflation();
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
        let joined = FloorJoined::new(field.floor().clone());
        let world = FloorWorld {
            field,
            joined,
            walls,
            escape: None,
            early_level: None,
            escapes: 0,
            anchor: None,
            funnels: None,
        };
        Ok((world, scan, controller))
    }
}

impl World for FloorWorld {}

impl Rules for FloorWorld {
    type Field = FloorField;
    type Step = FloorStep;

    fn field(&self) -> &FloorField {
        &self.field
    }

    fn goal(&self) -> Vector2<f64> {
        self.funnels.as_ref().map_or_else(
            || self.field.transform().goal(),
            |run| run.chain.funnels[0].goal,
        )
    }

    /// `Θ` at `x` with the navigator's errors: in the boundary layer with the robot's disc clear
    /// of the walls, [`NavError::BoundaryLayer`].
    fn eval(&self, x: Vector2<f64>, options: &Options) -> Result<FieldEval, NavError> {
        self.field.eval(x).map_err(|e| match e {
            FieldError::InObstacle { obstacle } => NavError::InObstacle {
                obstacle: self.joined.navigator_index(obstacle),
            },
            FieldError::NotFinite => NavError::NotFinite { what: "position" },
            _ => match self.field.locate(x) {
                Some(NotFree::BoundaryLayer)
                    if self.field.floor().wall_distance(x) > options.radius =>
                {
                    NavError::BoundaryLayer
                }
                // In a joined obstacle's cut (outside the carved `W_s`, inside the floor's own),
                // the disc clear of the walls and of every joined body: led out as from the
                // layer (`leave_layer`).
                Some(NotFree::Outside)
                    if self.joined.any()
                        && self.joined.base_signed_distance(x) > 0.0
                        && self.field.floor().wall_distance(x) > options.radius
                        && self.joined.body_clearance(x) > 0.0 =>
                {
                    NavError::BoundaryLayer
                }
                _ => NavError::OutsideBoundary,
            },
        })
    }

    fn known(&self) -> Cow<'_, [StarShape]> {
        match self.joined.all() {
            Some(all) => Cow::Borrowed(all),
            None => Cow::Owned(self.field.transform().obstacles().cloned().collect()),
        }
    }

    fn k(&self) -> f64 {
        self.field.k()
    }

    fn joined(&self) -> &[usize] {
        &self.joined.indices
    }

    /// `k`, `B` and the point world update, `H` is reused (no new solve); an obstacle that
    /// reaches the boundary layer joins the walls ([`crate::floor_joined`]: `H` is solved
    /// again).
    fn admit(
        &mut self,
        grown: StarShape,
        added: Added<'_>,
        options: &Options,
    ) -> Result<usize, NavError> {
        let mut all = self.known().into_owned();
        let index = all.len();
        if !self.joined.any() {
            match self.field.with_obstacle(grown.clone()) {
                Ok(field) => {
                    self.field = field;
                    return Ok(index);
                }
                Err(FloorError::ObstacleNearWall { .. }) => {}
                Err(e) => return Err(NavError::Floor(e)),
            }
        }
        all.push(grown);
        let mut bodies = added.bodies.to_vec();
        bodies.extend(added.body.cloned());
        let known = Known {
            grown: &all,
            bodies: &bodies,
            joined: self.joined.indices.clone(),
            robot: added.robot,
        };
        self.rebuild(known, options)?;
        Ok(index)
    }

    /// Every new or grown shape is handed to the field as a sensed obstacle
    /// ([`FloorField::with_sensed`]: `k` and `B` update, `H` is reused); one that reaches the
    /// boundary layer joins the walls ([`crate::floor_joined`]: `H` is solved again).
    fn sensed(&mut self, event: &ScanEvent, options: &Options) -> Result<(), NavError> {
        // The obstacles that joined before and are kept, in the event's order.
        let joined = (0..event.keep.len())
            .filter(|&j| self.joined.indices.binary_search(&event.keep[j]).is_ok())
            .collect();
        let known = Known {
            grown: &event.obstacles,
            bodies: &event.inner,
            joined,
            robot: Some(event.robot),
        };
        self.rebuild(known, options)
    }

    /// The escapes (`phi_k` changes with `k` and the point world: the levels before and after
    /// are not comparable).
    fn discovered(&mut self) {
        self.escape = None;
        self.early_level = None;
    }

    /// The command, the robot having stayed near one point for some periods, and the escape
    /// after it.
    fn held(
        core: &Core,
        world: &Self,
        x: Vector2<f64>,
        v: Vector2<f64>,
    ) -> Result<(Command, FloorStep), NavError> {
        let radius = 0.25 * world.field.floor().delta();
        let anchor = match world.anchor {
            Some((a, n)) if (x - a).norm() < radius => (a, n.saturating_add(1)),
            _ => (x, 0),
        };
        // Entering a funnel (or its parent): the command is that of its field.
        let funnel = world.funnel_switch(x);
        let view;
        let world = match &funnel {
            Some((j, field)) => {
                view = world.entering(*j, field.clone());
                &view
            }
            None => world,
        };
        let (mut command, escape) = Floor { core, world }.held(x, v, anchor.1)?;
        // The mode names the navigator's obstacle (the field's index differs after a join).
        if let Mode::Recovering(Band::Obstacle(i)) = command.mode {
            command.mode = Mode::Recovering(Band::Obstacle(world.joined.navigator_index(i)));
        }
        Ok((
            command,
            FloorStep {
                escape,
                anchor,
                funnel,
            },
        ))
    }

    fn after(&mut self, x: Vector2<f64>, step: FloorStep) {
        let world = self;
        let FloorStep {
            escape,
            anchor,
            funnel,
        } = step;
        if let Some((j, field)) = funnel {
            *world = world.entering(j, field);
        }
        // An escape that begins moves the robot: the watch starts again.
        let begins = escape.is_some() && escape != world.escape;
        world.anchor = Some(if begins { (x, 0) } else { anchor });
        world.escapes = world.escapes.saturating_add(usize::from(begins));
        if let Some(e) = escape.filter(|e| begins && e.early) {
            world.early_level = Some(e.level);
        }
        world.escape = escape;
    }
}

impl FloorWorld {
    /// Takes the field `known` gives, with the obstacles that reach the boundary layer joined
    /// to the walls ([`FloorJoined::rebuild`]); unchanged on error. In a funnel the field stays
    /// that funnel's (or, if its goal cannot take the obstacles, the goal's, and the robot in no
    /// funnel); an obstacle that joins the walls solves `H` again, and the chain, certified
    /// over the old `H`, is dropped.
    fn rebuild(&mut self, known: Known<'_>, options: &Options) -> Result<(), NavError> {
        let overlap = |first, second| NavError::Floor(FloorError::Overlap { first, second });
        let root = self.root_field()?;
        let (field, joined) = self.joined.rebuild(&root, known, options, overlap)?;
        let run = self.funnels.take().filter(|_| !joined.any());
        self.field = field;
        self.joined = joined;
        if let Some(mut run) = run {
            let inside = run.current.filter(|&j| j != 0);
            match inside.and_then(|j| self.funnel_field(&run.chain, j).map(|f| (j, f))) {
                Some((_, f)) => self.field = f,
                None if inside.is_some() => run.current = None,
                None => {}
            }
            self.funnels = Some(run);
        }
        Ok(())
    }

    /// The field towards the navigator's goal with the sensed obstacles: `field` itself
    /// outside the funnels or in the goal's own.
    pub(crate) fn root_field(&self) -> Result<FloorField, NavError> {
        match &self.funnels {
            Some(run) if run.current.is_some_and(|j| j != 0) => {
                let root = run.chain.funnels[0].field.with_sensed(&self.sensed())?;
                Ok(root.with_geodesic_of(&self.field))
            }
            _ => Ok(self.field.clone()),
        }
    }

    /// Funnel `j`'s field with the sensed obstacles and the shortest path of `field`; `None`
    /// if its goal cannot take them (an obstacle over it).
    fn funnel_field(&self, chain: &Funnels, j: usize) -> Option<FloorField> {
        let field = chain
            .funnels
            .get(j)?
            .field
            .with_sensed(&self.sensed())
            .ok()?;
        Some(field.with_geodesic_of(&self.field))
    }

    /// The funnel the robot at `x` enters, and its field: in funnel `i`, its parent (or the
    /// parent's, on up) once that holds `x` ([`harmonav_floorplan::Funnel::holds`]); in none,
    /// the least funnel that holds `x`. `None` when it stays where it is (or the funnel's
    /// field cannot be built, [`FloorWorld::funnel_field`]).
    fn funnel_switch(&self, x: Vector2<f64>) -> Option<(usize, FloorField)> {
        let run = self.funnels.as_ref()?;
        let chain = &run.chain;
        let target = match run.current {
            Some(i) => {
                let mut j = i;
                while let Some(p) = chain.funnels[j].parent
                    && chain.funnels[p].holds(x)
                {
                    j = p;
                }
                (j != i).then_some(j)
            }
            None => chain.entry(x),
        }?;
        Some((target, self.funnel_field(chain, target)?))
    }

    /// This world in funnel `j` with its field `field`: the escapes forgotten (the levels of
    /// `phi_k` change with the goal).
    fn entering(&self, j: usize, field: FloorField) -> Self {
        let mut world = Self {
            field,
            escape: None,
            early_level: None,
            ..self.clone()
        };
        if let Some(run) = &mut world.funnels {
            run.current = Some(j);
        }
        world
    }

    /// The sensed obstacles in the field (grown), which a funnel's field takes too.
    fn sensed(&self) -> Vec<StarShape> {
        self.field.transform().obstacles().cloned().collect()
    }

    /// In a funnel of the chain: the law converges without an escape (and an escape along the
    /// shortest path could leave the funnel).
    fn in_funnel(&self) -> bool {
        self.funnels.as_ref().is_some_and(|r| r.current.is_some())
    }
}

/// A floor navigator's view while it forms a command: what every world keeps and the floor.
struct Floor<'a> {
    core: &'a Core,
    world: &'a FloorWorld,
}

impl Floor<'_> {
    /// The command and the escape after it, the robot having stayed near one point for
    /// `still` periods.
    fn held(
        &self,
        x: Vector2<f64>,
        v: Vector2<f64>,
        still: usize,
    ) -> Result<(Command, Option<Escape>), NavError> {
        let eval = match evaluate(self.core, self.world, x, v) {
            Ok(eval) => eval,
            Err(NavError::InObstacle { obstacle }) => {
                return self.recover(x, v, obstacle).map(|c| (c, None));
            }
            Err(NavError::BoundaryLayer) => return self.leave_layer(x, v).map(|c| (c, None)),
            Err(e) => return Err(e),
        };
        if self.core.options.hold == HoldPolicy::Paper {
            return Ok((law_held(self.core, self.world, x, v, &eval), None));
        }
        if self.world.in_funnel() {
            return Ok((self.law_or_in(x, v, &eval), None));
        }
        let field = &self.world.field;
        // Every escape follows the shortest path's heading `g` (none without the geodesic).
        let Some(g) = field.geodesic().and_then(|t| t.heading_near(x)) else {
            return Ok((self.law_or_in(x, v, &eval), None));
        };
        let phi = eval.field.phi;
        if let Some(e) = self.world.escape.filter(|e| phi >= e.level - ESCAPE_DROP)
            && let Some(c) = self.escaping(x, v, g, e.early)
        {
            return Ok((c, Some(e)));
        }
        // Against the law: `g` more than 90° from the law's descent direction `d`, and
        // `phi_k` `Δ` below where the last such escape began.
        if self.world.early_level.is_none_or(|l| phi < l - ESCAPE_DROP)
            && eval.field.direction.is_some_and(|d| d.dot(&g) < 0.0)
            && let Some(c) = self.escaping(x, v, g, true)
        {
            let escape = Escape {
                level: phi,
                early: true,
            };
            return Ok((c, Some(escape)));
        }
        let delta = field.floor().delta();
        if still as f64 * self.core.period >= ESCAPE_STALL
            && field.clearance(x, 0.5 * delta, None) < 0.5 * delta
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

    /// The law under the hold (`law_held`), or, where the hold certifies no step at all because `x`
    /// lies on the edge of the certified region (`sd − δ` below [`EDGE`]·δ, zero to rounding:
    /// no step of positive length is certified by the clearance alone), the way out of the
    /// layer (`leave_layer`: a step straight away from the nearest wall,
    /// certified clear of the walls and the sensed obstacles) instead of a command of zero for
    /// ever.
    fn law_or_in(&self, x: Vector2<f64>, v: Vector2<f64>, eval: &Evaluation) -> Command {
        let command = law_held(self.core, self.world, x, v, eval);
        let floor = self.world.field.floor();
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
        let h = self.core.period;
        let speed = match &self.core.controller {
            Controller::Kinematic(law) => law.v_max(),
            Controller::Dynamic(law) => 0.5 * law.speed_bound(),
        };
        let want = (h * speed).min((x - self.world.field.transform().goal()).norm());
        let slid = self.world.field.slide(x, heading, want);
        let norm = slid.norm();
        if !(norm > 1e-3 && want > 0.0) {
            return None;
        }
        let dir = slid / norm;
        let mut length = hold::held_length(&self.world.field, x, dir, want);
        // Against the law, the dynamic robot keeps the dynamic hold's invariant
        // `h|v⁺| ≤ c·d(x)` (`c` = DYNAMIC_FRACTION, docs/maths.md §10): the step is then
        // certified under the exact hold of the force too (rapier), whose displacement
        // `h(v + v⁺)/2` leaves the segment along `dir`. (A stall's escape slides along the
        // edge, where `d(x)` is about 0 and the cap would stop it: it is certified under
        // semi-implicit Euler, the built-in integrator, alone.)
        if early && matches!(self.core.controller, Controller::Dynamic(_)) {
            let need = 2.0 * want / hold::DYNAMIC_FRACTION;
            let d = self.world.field.clearance(x, need, None).max(0.0);
            length = length.min(hold::DYNAMIC_FRACTION * d);
        }
        let least = if early { ESCAPE_BLOCKED * want } else { 0.0 };
        (length > least && length > 0.0).then(|| Command {
            value: moving_along(&self.core.controller, dir, length, h, v),
            mode: Mode::Escaping,
        })
    }

    /// The way out of the margin band of the navigator's obstacle `j` (the field's `i`), as
    /// [`crate::Navigator`]'s: along the ray from its centre to the grown shape's edge, plus
    /// half the edge's clearance from everything else (at most half the margin).
    fn recover(&self, x: Vector2<f64>, v: Vector2<f64>, j: usize) -> Result<Command, NavError> {
        let error = NavError::InObstacle { obstacle: j };
        let (Some(inner), Some(i)) = (self.core.inner.get(j), self.world.joined.field_index(j))
        else {
            return Err(error);
        };
        if inner.contains(x) {
            return Err(error);
        }
        let grown = self
            .world
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
            .world
            .field
            .clearance(edge, self.core.options.margin, Some(band))
            .max(0.0);
        if room <= 0.0 {
            return Err(error);
        }
        let length = to_edge + 0.5 * room;
        Ok(recovering(
            &self.core.controller,
            band,
            dir,
            length,
            self.core.period,
            v,
        ))
    }

    /// The way out of the walls' boundary layer (`sd(x) < δ`, the robot's disc clear of the
    /// walls): along `−n`, `n` the unit vector to the nearest point of `∂W_s` (along `n` from
    /// inside a joined obstacle's cut, `sd(x) < 0`), for `δ − sd(x) + δ/4` (a quarter of `δ`
    /// into `W_δ`), halved until the segment is certified:
    /// `sd` grows along it and, by the 1-Lipschitz chord bound `c ≥ (c(x) + c(y) − L)/2`, it
    /// keeps the disc clear of the true walls (`c` the wall distance less the radius), the
    /// sensed obstacles grown by `radius + margin` (their certified distances) and the bodies
    /// of the obstacles joined to the walls ([`FloorJoined::body_clearance`]). Held for the
    /// period, the command moves along a prefix of that segment (its speed capped as a band's
    /// recovery is). [`NavError::BoundaryLayer`] if no halving certifies.
    fn leave_layer(&self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Command, NavError> {
        // Also from the edge itself (`sd = δ`, `law_or_in`): the step is then
        // a quarter of δ inwards.
        let floor = self.world.field.floor();
        let (sd, delta) = (floor.signed_distance(x), floor.delta());
        // Away from the nearest point of `∂W_s`, or towards it from inside a joined
        // obstacle's cut (`sd < 0`, [`Rules::eval`]).
        let toward = floor.toward_boundary(x).ok_or(NavError::BoundaryLayer)?;
        let dir = if sd < 0.0 { toward } else { -toward };
        let walls = |z: Vector2<f64>| floor.wall_distance(z) - self.core.options.radius;
        let sensed = |z: Vector2<f64>| {
            self.world
                .field
                .clearance(z, f64::INFINITY, Some(Band::Boundary))
        };
        let joined = |z: Vector2<f64>| self.world.joined.body_clearance(z);
        let (w0, s0, j0) = (walls(x), sensed(x), joined(x));
        let mut length = delta - sd + 0.25 * delta;
        for _ in 0..=hold::MAX_HALVINGS {
            let y = x + length * dir;
            if floor.signed_distance(y) > sd
                && w0 + walls(y) - length > 0.0
                && s0 + sensed(y) - length > 0.0
                && j0 + joined(y) - length > 0.0
            {
                return Ok(recovering(
                    &self.core.controller,
                    Band::Boundary,
                    dir,
                    length,
                    self.core.period,
                    v,
                ));
            }
            length *= 0.5;
        }
        Err(NavError::BoundaryLayer)
    }
}

impl From<FloorError> for NavError {
    fn from(e: FloorError) -> Self {
        Self::Floor(e)
    }
}
