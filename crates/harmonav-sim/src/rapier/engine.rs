//! What the two rapier harnesses share (the star world's, `rapier.rs`, and the floor plan's,
//! `rapier/floor.rs`): a world with no gravity, static walls, the robot a dynamic ball driven
//! by a command (its velocity for the kinematic model, a force for the dynamic one), and the
//! counting of its contact events with the walls ([`TOUCH`]).

use std::collections::BTreeSet;
use std::f64::consts::TAU;

use harmonav_scenario::Model;
use harmonav_transform::StarShape;
use nalgebra::Vector2;
use rapier2d_f64::prelude::{
    ColliderBuilder, ColliderHandle, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle, Rotation,
    Vector,
};

/// rapier's ball touches a wall when the exact distance from its centre to the true shape is
/// at most its radius plus this (m). rapier's active contact pairs also hold speculative
/// contacts within its prediction distance (they were counted at 0.5–1 mm of clearance); those
/// are not counted. A point robot is a ball of 1 mm in rapier, so its contact events happen at
/// a true clearance of up to 1 mm: a margin of the engine, not a collision, which the
/// no-collision monitor judges on the true clearance.
pub(super) const TOUCH: f64 = 1e-6;

/// The radius of rapier's ball for a robot of `radius`: a point robot is a ball of 1 mm.
#[must_use]
pub(super) fn ball_radius(radius: f64) -> f64 {
    radius.max(1e-3)
}

/// A point as rapier's vector.
pub(super) fn v(p: Vector2<f64>) -> Vector {
    Vector::new(p.x, p.y)
}

/// The closed polyline through `points` (a ring: the last point joins the first), as one
/// static collider.
pub(super) fn ring(points: impl IntoIterator<Item = Vector2<f64>>) -> ColliderBuilder {
    rings([points])
}

/// Several closed polylines (rings) as one static collider: a polyline whose index buffer
/// closes each ring on itself, so no segment joins two rings.
pub(super) fn rings<R: IntoIterator<Item = Vector2<f64>>>(
    rings: impl IntoIterator<Item = R>,
) -> ColliderBuilder {
    let mut pts = Vec::new();
    let mut idx = Vec::new();
    for ring in rings {
        let first = pts.len() as u32;
        pts.extend(ring.into_iter().map(v));
        let last = pts.len() as u32;
        idx.extend((first..last).map(|i| [i, if i + 1 == last { first } else { i + 1 }]));
    }
    ColliderBuilder::polyline(pts, Some(idx))
}

/// A rapier world with static walls and the robot's ball; its state, its command and its
/// contact events. `gap(i, x)`, the exact distance from `x` to the true shape of wall `i`
/// (in the order the walls were given), decides which of rapier's active pairs touch
/// ([`TOUCH`]).
pub(super) struct Engine {
    world: PhysicsWorld,
    robot: RigidBodyHandle,
    robot_collider: ColliderHandle,
    walls: Vec<ColliderHandle>,
    radius: f64,
    /// Walls touched after the last step.
    touching: BTreeSet<usize>,
    /// Contact events so far: robot–wall pairs that started touching in a step.
    contacts: usize,
}

impl Engine {
    /// A world of fixed step `h` with `walls` (static, in order), the robot's ball of
    /// [`ball_radius`]`(radius)` and `mass` at `start` (no damping, never asleep, CCD on).
    /// Walls the ball already reaches at the start are touching, not a contact event.
    pub(super) fn new(
        h: f64,
        walls: impl IntoIterator<Item = ColliderBuilder>,
        (start, radius, mass): (Vector2<f64>, f64, f64),
        gap: &dyn Fn(usize, Vector2<f64>) -> f64,
    ) -> Self {
        let mut world = PhysicsWorld {
            gravity: Vector::new(0.0, 0.0),
            ..PhysicsWorld::default()
        };
        world.integration_parameters.dt = h;
        let walls: Vec<ColliderHandle> = walls
            .into_iter()
            .map(|c| world.insert(RigidBodyBuilder::fixed(), c).1)
            .collect();
        let radius = ball_radius(radius);
        let (robot, robot_collider) = world.insert(
            RigidBodyBuilder::dynamic()
                .translation(v(start))
                .linear_damping(0.0)
                .can_sleep(false)
                .ccd_enabled(true),
            ColliderBuilder::ball(radius).density(mass / (std::f64::consts::PI * radius * radius)),
        );
        let touching = (0..walls.len())
            .filter(|&i| gap(i, start) <= radius + TOUCH)
            .collect();
        Self {
            world,
            robot,
            robot_collider,
            walls,
            radius,
            touching,
            contacts: 0,
        }
    }

    /// The robot's position and velocity.
    pub(super) fn state(&self) -> (Vector2<f64>, Vector2<f64>) {
        let b = &self.world.bodies[self.robot];
        (
            Vector2::new(b.translation().x, b.translation().y),
            Vector2::new(b.linvel().x, b.linvel().y),
        )
    }

    /// Drives the robot for the next steps: `command` is its velocity (kinematic) or the force
    /// on it (dynamic).
    pub(super) fn drive(&mut self, model: Model, command: Vector2<f64>) {
        let body = &mut self.world.bodies[self.robot];
        match model {
            Model::Kinematic => body.set_linvel(v(command), true),
            Model::Dynamic => {
                body.reset_forces(true);
                body.add_force(v(command), true);
            }
        }
    }

    /// The robot's heading `θ`, rad, in `(−π, π]`: its body's rotation (a differential drive).
    pub(super) fn yaw(&self) -> f64 {
        self.world.bodies[self.robot].rotation().angle()
    }

    /// Turns the robot's body to the heading `yaw`, rad (a differential drive's start).
    pub(super) fn set_yaw(&mut self, yaw: f64) {
        self.world.bodies[self.robot].set_rotation(Rotation::new(yaw), true);
    }

    /// Drives a differential drive for the next step: the body's linear velocity is set to
    /// `v·e(θ)` along its heading `θ` now and its angular velocity to `ω`. rapier then moves it
    /// `h·v·e(θ)` and turns it by `ωh` (exactly); set again at every step, the velocity follows
    /// the heading, so the body never moves sideways by more than a step's turn.
    pub(super) fn drive_unicycle(&mut self, v: f64, omega: f64) {
        let body = &mut self.world.bodies[self.robot];
        let yaw = body.rotation().angle();
        body.set_linvel(Vector::new(v * yaw.cos(), v * yaw.sin()), true);
        body.set_angvel(omega, true);
    }

    /// One fixed step, then its contact events: robot–wall pairs that started touching in
    /// it. rapier's active pairs include speculative contacts within its prediction distance;
    /// a pair counts as touching only if the ball is also within [`TOUCH`] of that wall by
    /// `gap`, the exact distance to the true shape.
    pub(super) fn step(&mut self, gap: &dyn Fn(usize, Vector2<f64>) -> f64) {
        self.world.step();
        let (x, _) = self.state();
        let robot = self.robot_collider;
        let now: BTreeSet<usize> = self
            .world
            .narrow_phase
            .contact_pairs_with(robot)
            .filter(|p| p.has_any_active_contact())
            .map(|p| {
                if p.collider1 == robot {
                    p.collider2
                } else {
                    p.collider1
                }
            })
            .filter_map(|c| self.walls.iter().position(|w| *w == c))
            .filter(|&i| gap(i, x) <= self.radius + TOUCH)
            .collect();
        self.contacts += now.difference(&self.touching).count();
        self.touching = now;
    }

    /// Contact events so far.
    pub(super) fn contacts(&self) -> usize {
        self.contacts
    }
}

/// A static collider for `shape`: an exact ball for a circular obstacle, otherwise (and always
/// for a star world's boundary, which the robot is inside) a closed polyline through the true
/// boundary (720 points).
pub(super) fn star(shape: &StarShape, obstacle: bool) -> ColliderBuilder {
    let (lo, hi) = shape.radius_bounds();
    if obstacle && (hi - lo).abs() <= 1e-12 * hi {
        return ColliderBuilder::ball(hi).translation(v(shape.centre()));
    }
    let n = 720;
    ring((0..n).map(|i| shape.boundary_point(TAU * f64::from(i) / f64::from(n))))
}
