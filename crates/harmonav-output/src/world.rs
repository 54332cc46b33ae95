//! The world a recording draws ([`crate::record::Stream`]): a star world's scenario or a
//! floor plan's, each with its scene, its `Θ` grids and its policies; and `Θ` of a floor plan
//! as the robot knew it ([`FloorTheta`]), shared with the floor-plan figure.

use foxglove::messages::{Grid, SceneEntity, SceneUpdate, SpherePrimitive, Vector3};
use harmonav::floorplan::{FloorField, Funnels};
use harmonav::{FloorNavigator, StarShape};
use harmonav_field::Field;
use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_scenario::{Prepared, Sensor};
use harmonav_sim::floor::{navigator, obstacle_name};
use nalgebra::Vector2;

use crate::drawing::closed_outline;
use crate::levels::ThetaGrid;
use crate::messages::{color, entity, grid_message, line, pose};

/// Cells along each side of the `/theta` grid.
pub const GRID_CELLS: u32 = 160;

/// The world of a recording.
pub(crate) enum World<'p> {
    /// A star world's scenario.
    Star(&'p Prepared),
    /// A floor plan, with its navigator knowing no obstacle (its `Θ` is rebuilt from it at
    /// each discovery or scan event without a new solve of the harmonic map).
    Floor {
        prepared: &'p FloorPrepared,
        base: Box<FloorNavigator>,
    },
}

/// The colours of the scene: the boundary or walls, an obstacle not known yet, a known one,
/// a floor plan's shrunk walls `∂W_s` (the certified region `W_δ` lies `δ` inside them), the goal.
const WALL: [f64; 4] = [1.0, 1.0, 1.0, 1.0];
const UNKNOWN: [f64; 4] = [0.6, 0.6, 0.6, 1.0];
const KNOWN: [f64; 4] = [0.9, 0.2, 0.2, 1.0];
const EDGE: [f64; 4] = [0.5, 0.5, 0.5, 1.0];
const GOAL: [f64; 4] = [0.2, 0.8, 0.3, 1.0];
/// A chain of funnels' goals and their links to their parents (teal, as `trajectory.svg`).
const FUNNEL: [f64; 4] = [0.0, 0.55, 0.55, 1.0];

impl<'p> World<'p> {
    /// The floor plan of `prepared`, with the navigator of its runs
    /// ([`harmonav_sim::floor::navigator`]).
    ///
    /// # Errors
    /// The navigator could not be built, as text.
    pub(crate) fn floor(prepared: &'p FloorPrepared) -> Result<Self, String> {
        let base = navigator(prepared, None).map_err(|e| e.to_string())?;
        Ok(Self::Floor {
            prepared,
            base: Box::new(base),
        })
    }

    /// The scene at `t`: the boundary (a floor plan: its true walls, and the certified
    /// region's edge in grey), the obstacles (`known` ones red, by scenario index), the goal.
    pub(crate) fn scene(&self, known: &[usize], t: f64) -> SceneUpdate {
        let mut entities = Vec::new();
        let (obstacles, goal): (Vec<(String, &StarShape)>, Vector2<f64>) = match self {
            World::Star(prepared) => {
                let truth = &prepared.truth;
                let b = line(closed_outline(&truth.boundary), WALL, 0.03);
                entities.push(entity(t, "world", "boundary", vec![b]));
                let names = truth.names.iter().cloned().zip(&truth.obstacles);
                (names.collect(), truth.goal())
            }
            World::Floor { prepared, .. } => {
                let (walls, domain) = (prepared.floor.walls(), prepared.floor.domain());
                let rings = |outer: &[Vector2<f64>], holes: &[Vec<Vector2<f64>>], rgba, width| {
                    std::iter::once(outer)
                        .chain(holes.iter().map(Vec::as_slice))
                        .map(|r| line(r.iter().chain(r.first()).copied(), rgba, width))
                        .collect()
                };
                let lines = rings(walls.outer(), walls.holes(), WALL, 0.03);
                entities.push(entity(t, "world", "walls", lines));
                let lines = rings(domain.outer(), domain.holes(), EDGE, 0.01);
                entities.push(entity(t, "world", "shrunk-walls", lines));
                if let Some(chain) = prepared.funnels.as_deref() {
                    entities.push(funnels_entity(chain, t));
                }
                let names = (0..prepared.obstacles.len()).map(|i| obstacle_name(prepared, i));
                let goal = Vector2::from(prepared.scenario.robot.goal);
                (names.zip(&prepared.obstacles).collect(), goal)
            }
        };
        // An obstacle's id is its name under `obstacle/`: one named `goal` or `walls` does not
        // replace the entity of that id.
        for (i, (name, o)) in obstacles.into_iter().enumerate() {
            let rgba = if known.contains(&i) { KNOWN } else { UNKNOWN };
            entities.push(entity(
                t,
                "world",
                &format!("obstacle/{name}"),
                vec![line(closed_outline(o), rgba, 0.03)],
            ));
        }
        let mut g = entity(t, "world", "goal", Vec::new());
        g.spheres.push(SpherePrimitive {
            pose: Some(pose(goal, 0.0)),
            size: Some(Vector3 {
                x: 0.12,
                y: 0.12,
                z: 0.12,
            }),
            color: color(GOAL),
        });
        entities.push(g);
        SceneUpdate {
            deletions: Vec::new(),
            entities,
        }
    }

    /// `Θ` of the known world (the obstacles `known`, by scenario index) on a
    /// [`GRID_CELLS`]² grid over the workspace's bounding square (NaN outside the free space;
    /// a floor plan's: outside the certified region).
    pub(crate) fn theta_grid(&self, known: &[usize], t: f64) -> Result<Grid, String> {
        match self {
            World::Star(prepared) => {
                let ws = prepared.truth.workspace.clone();
                let field = Field::with_policy(ws, known.iter().copied(), prepared.k_policy())
                    .map_err(|e| e.to_string())?;
                star_grid(prepared, &field, t)
            }
            World::Floor { prepared, base } => {
                let theta = FloorTheta::new(prepared, base, known, &[])?;
                Ok(floor_grid(prepared, &theta, t))
            }
        }
    }

    /// `Θ` of the obstacles as perceived by a lidar (not grown; grown here by the robot's
    /// radius and margin as the navigator grows them), on the grid of [`World::theta_grid`].
    pub(crate) fn perceived_grid(&self, perceived: &[StarShape], t: f64) -> Result<Grid, String> {
        match self {
            World::Star(prepared) => {
                let field = crate::figures::perceived_field(prepared, perceived)?;
                star_grid(prepared, &field, t)
            }
            World::Floor { prepared, base } => {
                let theta = FloorTheta::new(prepared, base, &[], perceived)?;
                Ok(floor_grid(prepared, &theta, t))
            }
        }
    }

    /// The sensing sector in the robot's frame (its axis along the robot's x axis): a star
    /// world's sector sensing only (a floor plan senses within a disc, or by a lidar).
    pub(crate) fn sector(&self) -> Option<SceneUpdate> {
        let World::Star(prepared) = self else {
            return None;
        };
        let Sensor::Sector(sec) = prepared.truth.sensor else {
            return None;
        };
        let mut pts = vec![Vector2::zeros()];
        for i in 0..=24 {
            let a = -0.5 * sec.aperture() + sec.aperture() * i as f64 / 24.0;
            pts.push(sec.range() * Vector2::new(a.cos(), a.sin()));
        }
        pts.push(Vector2::zeros());
        Some(SceneUpdate {
            deletions: Vec::new(),
            entities: vec![entity(
                0.0,
                "robot",
                "sector",
                vec![line(pts.into_iter(), [0.2, 0.5, 0.9, 1.0], 0.015)],
            )],
        })
    }

    /// The names of the `k` policy and of the damping policy the dynamic law's states are
    /// labelled with (a floor plan's: the navigator's, the dynamic law's default damping).
    pub(crate) fn policies(&self) -> (String, String) {
        match self {
            World::Star(prepared) => (
                prepared.k_policy().as_str().into(),
                prepared.damping_policy().as_str().into(),
            ),
            World::Floor { base, .. } => {
                let damping = match base.controller() {
                    harmonav::Controller::Dynamic(law) => law.damping_policy(),
                    harmonav::Controller::Kinematic(_) => harmonav::DampingPolicy::default(),
                };
                (
                    base.field().k_policy().as_str().into(),
                    damping.as_str().into(),
                )
            }
        }
    }
}

/// `Θ` of `field` on a [`GRID_CELLS`]² grid over the star world's bounding disc's square.
fn star_grid(prepared: &Prepared, field: &Field, t: f64) -> Result<Grid, String> {
    let b = &prepared.truth.boundary;
    let grid = ThetaGrid::sample(field, b.centre(), b.radius_bounds().1, GRID_CELLS as usize)
        .map_err(|e| e.to_string())?;
    Ok(grid_message(&grid, t))
}

/// `Θ` on a [`GRID_CELLS`]² grid over [`floor_square`].
fn floor_grid(prepared: &FloorPrepared, theta: &FloorTheta, t: f64) -> Grid {
    let (c, half) = floor_square(prepared);
    let grid = ThetaGrid::from_fn(c, half, GRID_CELLS as usize, |p| theta.at(p));
    grid_message(&grid, t)
}

/// The square a floor plan is drawn and gridded in: its centre and half-side, the walls'
/// bounding box's centre and 52 % of its longer side.
pub(crate) fn floor_square(prepared: &FloorPrepared) -> (Vector2<f64>, f64) {
    let (lo, hi) = prepared.floor.walls().bounding_box();
    (0.5 * (lo + hi), 0.52 * (hi - lo).max())
}

/// `Θ` of a floor plan as the robot knew it: over the walls and the obstacles it sensed
/// exactly, or (a lidar) over the shapes it perceived, grown by `radius + margin` as the
/// navigator grows them. `None` outside the certified region.
pub(crate) struct FloorTheta(FloorField);

impl FloorTheta {
    /// `Θ` of `base` (a navigator of `prepared` knowing no obstacle) with the obstacles
    /// `discovered` (scenario indices) added, or the shapes `perceived` (not grown) when
    /// there are some and the file has a lidar.
    ///
    /// # Errors
    /// An obstacle that cannot be added, or perceived shapes that cannot be grown, as text.
    pub(crate) fn new(
        prepared: &FloorPrepared,
        base: &FloorNavigator,
        discovered: &[usize],
        perceived: &[StarShape],
    ) -> Result<Self, String> {
        match &prepared.lidar {
            Some((lidar, _)) if !perceived.is_empty() => {
                let r = &prepared.scenario.robot;
                let grown = perceived
                    .iter()
                    .map(|p| harmonav::grow_perceived_as(p, r.radius + r.margin, lidar.scan.form))
                    .collect::<Result<Vec<_>, _>>()
                    .map_err(|e| e.to_string())?;
                let field = base.field().with_sensed(&grown);
                Ok(Self(field.map_err(|e| e.to_string())?))
            }
            _ => {
                let mut nav = base.clone();
                for &i in discovered {
                    nav.add_obstacle(prepared.obstacles[i].clone())
                        .map_err(|e| e.to_string())?;
                }
                Ok(Self(nav.field().clone()))
            }
        }
    }

    /// `Θ` at `p`; `None` outside the certified region.
    pub(crate) fn at(&self, p: Vector2<f64>) -> Option<f64> {
        self.0.eval(p).ok().map(|e| e.value)
    }
}

/// The entity `funnels` of a floor plan's `/scene`: a line from each funnel's goal to its
/// parent's and a small sphere at each goal (the chain the navigator follows, docs/maths.md
/// §13.10).
fn funnels_entity(chain: &Funnels, t: f64) -> SceneEntity {
    let links = chain
        .funnels
        .iter()
        .filter_map(|f| {
            let parent = chain.funnels.get(f.parent?)?.goal;
            Some(line([f.goal, parent].into_iter(), FUNNEL, 0.01))
        })
        .collect();
    let mut e = entity(t, "world", "funnels", links);
    e.spheres = chain
        .funnels
        .iter()
        .map(|f| SpherePrimitive {
            pose: Some(pose(f.goal, 0.0)),
            size: Some(Vector3 {
                x: 0.06,
                y: 0.06,
                z: 0.06,
            }),
            color: color(FUNNEL),
        })
        .collect();
    e
}
