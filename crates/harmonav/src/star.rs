//! [`StarWorld`]: a star world (`Φ = T`, the paper's navigation transformation): the
//! workspace's boundary and the known obstacles as star shapes, grown by `radius + margin`.

use std::borrow::Cow;
use std::sync::Arc;

use harmonav_field::{Field, FieldError, FieldEval};
use harmonav_transform::{StarShape, Workspace, WorldError};
use nalgebra::Vector2;

use crate::certified::Band;
use crate::controller::{Controller, recovering};
use crate::error::NavError;
use crate::event::ScanEvent;
use crate::hold::{self, Command};
use crate::options::{HoldPolicy, Options};
use crate::scanning::ScanState;
use crate::world::{Build, Core, Rules, World, evaluate, law_held};

/// A star world: `Θ` over the obstacles known so far, grown by `radius + margin` (in the order
/// they were added), in the boundary shrunk by `radius + margin`; and the boundary shrunk by
/// `radius` alone, inside which the robot's disc is clear of the true boundary.
#[derive(Clone, Debug)]
pub struct StarWorld {
    pub(crate) field: Field,
    /// The boundary shrunk by `radius` (with a margin): the margin band of the boundary is
    /// inside it and outside the field's.
    pub(crate) inner_boundary: Option<StarShape>,
}

/// A field error at a point, as the navigator reports it.
fn not_free(e: FieldError) -> NavError {
    match e {
        FieldError::InObstacle { obstacle } => NavError::InObstacle { obstacle },
        _ => NavError::OutsideBoundary,
    }
}

impl Build for StarShape {
    type World = StarWorld;

    /// The boundary shrunk by `radius + margin` (and by `radius` alone under a margin), `Θ`
    /// with no obstacle known yet, the perception in the true boundary, and the dynamic law's
    /// governed pull grown with the largest radius of the shrunk boundary (as its scale shift
    /// does).
    fn build(
        self,
        goal: Vector2<f64>,
        controller: Controller,
        options: &Options,
    ) -> Result<(StarWorld, ScanState, Controller), NavError> {
        let inflation = options.inflation();
        let shrunk = self.offset(-inflation).map_err(NavError::Shape)?;
        let inner_boundary = if options.margin > 0.0 {
            Some(self.offset(-options.radius).map_err(NavError::Shape)?)
        } else {
            None
        };
        let scan = ScanState::new(self, &options.scan, options.rho_min, inflation)?;
        let ws = Workspace::new(shrunk, Vec::new(), goal).map_err(|_| NavError::GoalNotFree)?;
        let field = Field::all_known_with(Arc::new(ws), options.k).map_err(NavError::Field)?;
        let controller = controller.in_world(field.workspace().boundary().radius_bounds().1)?;
        let world = StarWorld {
            field,
            inner_boundary,
        };
        Ok((world, scan, controller))
    }
}

impl World for StarWorld {}

impl Rules for StarWorld {
    type Field = Field;
    type Step = ();

    fn field(&self) -> &Field {
        &self.field
    }

    fn eval(&self, x: Vector2<f64>, _: &Options) -> Result<FieldEval, NavError> {
        self.field.eval(x).map_err(not_free)
    }

    fn known(&self) -> Cow<'_, [StarShape]> {
        Cow::Borrowed(self.field.workspace().obstacles())
    }

    fn k(&self) -> f64 {
        self.field.k()
    }

    /// In place, validated before anything changes (`Field::push_obstacle`).
    fn admit(&mut self, grown: StarShape) -> Result<usize, NavError> {
        self.field.push_obstacle(grown).map_err(|e| match e {
            FieldError::World(WorldError::Overlap { first, .. }) => {
                NavError::Overlap { obstacle: first }
            }
            FieldError::World(WorldError::InObstacle { .. }) => NavError::ContainsGoal,
            FieldError::World(WorldError::OutsideBoundary { .. }) => NavError::CrossesBoundary,
            e => NavError::Field(e),
        })
    }

    fn sensed(&mut self, event: &ScanEvent, options: &Options) -> Result<(), NavError> {
        let boundary = self.field.workspace().boundary().clone();
        let before = |j: usize| event.keep.get(j).copied();
        let goal = self.field.workspace().destination();
        let ws = Workspace::new(boundary, event.obstacles.clone(), goal).map_err(|e| match e {
            WorldError::Overlap { first, second } => NavError::NotStarWorld {
                obstacle: before(first).or(before(second)),
            },
            WorldError::InObstacle { .. } => NavError::ContainsGoal,
            _ => NavError::CrossesBoundary,
        })?;
        self.field = self
            .field
            .all_known_after(Arc::new(ws), options.k)
            .map_err(NavError::Field)?;
        Ok(())
    }

    /// The law under the hold; a kinematic command far below the law's speed (a rest point of
    /// the hold, not of `Θ`) is replaced by a certified step off it ([`crate::Mode::FromRest`]).
    fn held(
        core: &Core,
        world: &Self,
        x: Vector2<f64>,
        v: Vector2<f64>,
    ) -> Result<(Command, ()), NavError> {
        let eval = match evaluate(core, world, x, v) {
            Ok(eval) => eval,
            Err(e) => return recover(core, world, x, v, e).map(|c| (c, ())),
        };
        let law = law_held(core, world, x, v, &eval);
        if core.options.hold == HoldPolicy::Paper {
            return Ok((law, ()));
        }
        let field = &world.field;
        Ok(match &core.controller {
            Controller::Kinematic(k) => {
                let speed = k.speed(&eval.field, (x - field.workspace().destination()).norm());
                if law.value.norm() < hold::REST_SCALE * speed {
                    let rest =
                        hold::kinematic_from_rest(field, x, &eval.field, speed, &law, core.period);
                    (rest.unwrap_or(law), ())
                } else {
                    (law, ())
                }
            }
            Controller::Dynamic(_) => (law, ()),
        })
    }

    fn after(&mut self, _: Vector2<f64>, (): ()) {}
}

/// The command out of the margin band, if `x` (not in the free space: `error`) is in it;
/// otherwise `error`, with the obstacle or boundary that the robot's disc overlaps.
fn recover(
    core: &Core,
    world: &StarWorld,
    x: Vector2<f64>,
    v: Vector2<f64>,
    error: NavError,
) -> Result<Command, NavError> {
    let band = match error {
        NavError::InObstacle { obstacle } => match core.inner.get(obstacle) {
            Some(inner) if !inner.contains(x) => Band::Obstacle(obstacle),
            _ => return Err(error),
        },
        NavError::OutsideBoundary => match &world.inner_boundary {
            Some(inner) if inner.contains(x) => Band::Boundary,
            _ => return Err(error),
        },
        _ => return Err(error),
    };
    let ws = world.field.workspace();
    let Some((dir, length)) = hold::way_out(ws, band, x, core.options.margin) else {
        return Err(error);
    };
    Ok(recovering(
        &core.controller,
        band,
        dir,
        length,
        core.period,
        v,
    ))
}
