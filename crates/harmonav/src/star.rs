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
use crate::joined::{Joined, Known};
use crate::options::{HoldPolicy, Options};
use crate::scanning::ScanState;
use crate::world::{Added, Build, Core, Rules, World, evaluate, law_held};

/// A star world: `Θ` over the obstacles known so far, grown by `radius + margin` (in the order
/// they were added), in the boundary shrunk by `radius + margin`; and the boundary shrunk by
/// `radius` alone, inside which the robot's disc is clear of the true boundary.
///
/// An obstacle that reaches the boundary joins it (`docs/maths/12-range-scans.md` §12.21):
/// the field's boundary is then the boundary with that obstacle and its shadow cut out, and the
/// field's obstacles are the others; the navigator's indices stay as they were.
#[derive(Clone, Debug)]
pub struct StarWorld {
    pub(crate) field: Field,
    /// The boundary shrunk by `radius` (with a margin): the margin band of the boundary is
    /// inside it and outside the field's.
    pub(crate) inner_boundary: Option<StarShape>,
    /// The obstacles that joined the boundary, and the boundaries before they did.
    pub(crate) joined: Joined,
}

impl StarWorld {
    /// A field error at a point, as the navigator reports it (the navigator's obstacle index).
    fn not_free(&self, e: FieldError) -> NavError {
        match e {
            FieldError::InObstacle { obstacle } => NavError::InObstacle {
                obstacle: self.joined.navigator_index(obstacle),
            },
            _ => NavError::OutsideBoundary,
        }
    }

    /// Every known obstacle, grown, in the navigator's order.
    pub(crate) fn obstacles(&self) -> &[StarShape] {
        self.joined
            .all()
            .unwrap_or_else(|| self.field.workspace().obstacles())
    }

    /// Takes the world `known` gives ([`Joined::rebuild`]).
    fn rebuild(
        &mut self,
        known: Known<'_>,
        options: &Options,
        overlap: impl Fn(usize, usize) -> NavError,
    ) -> Result<(), NavError> {
        let goal = self.field.workspace().destination();
        let rebuilt = self
            .joined
            .rebuild(&self.field, known, goal, options, overlap)?;
        self.field = rebuilt.field;
        self.inner_boundary = rebuilt.inner;
        self.joined = rebuilt.joined;
        Ok(())
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
        let joined = Joined::new(field.workspace().boundary().clone(), inner_boundary.clone());
        let world = StarWorld {
            field,
            inner_boundary,
            joined,
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
        self.field.eval(x).map_err(|e| self.not_free(e))
    }

    fn known(&self) -> Cow<'_, [StarShape]> {
        Cow::Borrowed(self.obstacles())
    }

    fn k(&self) -> f64 {
        self.field.k()
    }

    fn joined(&self) -> &[usize] {
        &self.joined.indices
    }

    /// In place, validated before anything changes (`Field::push_obstacle`); an obstacle that
    /// reaches the boundary joins it ([`Joined::rebuild`]).
    fn admit(
        &mut self,
        grown: StarShape,
        added: Added<'_>,
        options: &Options,
    ) -> Result<usize, NavError> {
        let index = self.obstacles().len();
        let joined = &self.joined;
        match self.field.push_obstacle(grown.clone()) {
            Ok(_) => {
                if self.joined.any() {
                    self.joined.push(grown);
                }
                Ok(index)
            }
            Err(FieldError::World(WorldError::OutsideBoundary { .. })) => {
                let mut all = self.obstacles().to_vec();
                all.push(grown);
                let mut bodies = added.bodies.to_vec();
                bodies.extend(added.body.cloned());
                let known = Known {
                    grown: &all,
                    bodies: &bodies,
                    joined: self.joined.indices.clone(),
                    robot: added.robot,
                };
                self.rebuild(known, options, |first, _| NavError::Overlap {
                    obstacle: first,
                })?;
                Ok(index)
            }
            Err(e) => Err(match e {
                FieldError::World(WorldError::Overlap { first, .. }) => NavError::Overlap {
                    obstacle: joined.navigator_index(first),
                },
                FieldError::World(WorldError::InObstacle { .. }) => NavError::ContainsGoal,
                e => NavError::Field(e),
            }),
        }
    }

    fn sensed(&mut self, event: &ScanEvent, options: &Options) -> Result<(), NavError> {
        let before = |j: usize| event.keep.get(j).copied();
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
        self.rebuild(known, options, |first, second| NavError::NotStarWorld {
            obstacle: before(first).or(before(second)),
        })
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
        NavError::InObstacle { obstacle } => {
            match (core.inner.get(obstacle), world.joined.field_index(obstacle)) {
                (Some(inner), Some(i)) if !inner.contains(x) => Band::Obstacle(i),
                _ => return Err(error),
            }
        }
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
