//! [`FloorField`]: `Θ = sigma∘phi_k∘Phi` on a floor plan.

use std::sync::Arc;

use harmonav_field::{FieldError, FieldEval, KPolicy};
use harmonav_potential::{PointWorld, Singularity};
use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::compose::{FloorTransform, NotFree};
use crate::geodesic::Geodesic;
use crate::plan::{FloorError, FloorMap};

/// The radius of the guard disc about a saddle `P_s` of `phi_k` in the point world, relative
/// to the distance from `P_s` to the nearest point (`P_d` or a `P_i`): within it
/// [`FloorField::heading`] is `None`, and the kinematic law follows `−∇Θ`.
pub const SADDLE_GUARD: f64 = 0.05;

impl From<NotFree> for FieldError {
    /// A sensed obstacle keeps its index; the boundary layer and the walls are `Outside`.
    fn from(e: NotFree) -> Self {
        match e {
            NotFree::Obstacle(obstacle) => FieldError::InObstacle { obstacle },
            NotFree::BoundaryLayer | NotFree::Outside => FieldError::Outside,
        }
    }
}

/// `Θ(x) = sigma(phi_k(Phi(x)))` on a floor plan, `Phi = S ∘ M_a ∘ H ∘ B` ([`FloorTransform`]),
/// `∇Θ = sigma'(phi_k)·J_Phiᵀ ∇phi_k` (the chain rule of theorem `isNF`), over the holes and
/// the sensed obstacles: `k = policy.k_for(M + n, layer)` with the layer ratio
/// `max_i |M_a(H(x_d)) − p_i|/(1 − |p_i|)` of the points in the disk (`p_i` after `M_a`; the star world's rule,
/// `docs/maths.md` §8, with the unit circle as the boundary). [`FloorField::with_obstacle`] adds a sensed
/// obstacle without a new solve of `H`.
#[derive(Clone, Debug)]
pub struct FloorField {
    transform: FloorTransform,
    world: PointWorld,
    policy: KPolicy,
    /// The smallest eigenvalue of `H(Θ)(x_d) = s·J_Phiᵀ J_Phi` (at `x_d`, `Phi` is not the
    /// identity).
    stiffness: f64,
    /// The shortest-path distance to the goal, whose direction is the kinematic law's nominal
    /// heading ([`FloorField::with_geodesic`]).
    geodesic: Option<Arc<Geodesic>>,
    /// The saddles of `phi_k` and the radii of their guard discs, in the point world (built
    /// with the geodesic distance).
    guards: Vec<(Vector2<f64>, f64)>,
}

impl FloorField {
    /// `Θ` on `floor` towards `goal` with no sensed obstacle.
    ///
    /// # Errors
    /// As [`FloorTransform::new`].
    pub fn new(
        floor: Arc<FloorMap>,
        goal: Vector2<f64>,
        policy: KPolicy,
    ) -> Result<Self, FloorError> {
        Self::with_obstacles(floor, &[], goal, policy)
    }

    /// `Θ` with the sensed obstacles `obstacles` (grown by `radius + margin`).
    ///
    /// # Errors
    /// As [`FloorTransform::new`].
    pub fn with_obstacles(
        floor: Arc<FloorMap>,
        obstacles: &[StarShape],
        goal: Vector2<f64>,
        policy: KPolicy,
    ) -> Result<Self, FloorError> {
        let transform = FloorTransform::new(floor, obstacles, goal, 0.0)?;
        // k and the valley radius from the points in the disk (before S, which depends on r*).
        let raw: Vec<_> = transform.raw_points().collect();
        let pd = transform.destination_image();
        let layer = raw
            .iter()
            .map(|p| (pd - p).norm() / (1.0 - p.norm()))
            .fold(0.0, f64::max);
        let k = policy.k_for(raw.len(), layer);
        let disk = PointWorld::new(pd, raw)?.with_k(k)?;
        let transform = transform.with_valley_radius(disk.valley_radius(Vector2::zeros()))?;
        let points: Vec<_> = transform.points().collect();
        let world = PointWorld::new(transform.destination_point(), points)?.with_k(k)?;
        let j = transform
            .nav_transform(goal)
            .map_err(|_| FloorError::GoalNotCertified {
                clearance: transform.floor().signed_distance(goal),
                delta: transform.floor().delta(),
            })?
            .jacobian;
        let smallest = (j.transpose() * j).symmetric_eigenvalues().min();
        let stiffness = world.destination_stiffness() * smallest.max(0.0);
        Ok(Self {
            transform,
            world,
            policy,
            stiffness,
            geodesic: None,
            guards: Vec::new(),
        })
    }

    /// The same field with one more sensed obstacle (grown); `k` and the bands update, `H` is
    /// reused. `self` is unchanged on error.
    ///
    /// # Errors
    /// As [`FloorTransform::new`].
    pub fn with_obstacle(&self, obstacle: StarShape) -> Result<Self, FloorError> {
        let mut all: Vec<StarShape> = self.transform.obstacles().cloned().collect();
        all.push(obstacle);
        self.with_sensed(&all)
    }

    /// The same field with the sensed obstacles `obstacles` (grown) in place of its own (a
    /// scan that grew, merged or added perceived shapes); `k` and the bands update, `H` and
    /// the shortest path's map are reused. `self` is unchanged on error.
    ///
    /// # Errors
    /// As [`FloorTransform::new`].
    pub fn with_sensed(&self, obstacles: &[StarShape]) -> Result<Self, FloorError> {
        let field = Self::with_obstacles(
            self.transform.floor().clone(),
            obstacles,
            self.transform.goal(),
            self.policy,
        )?;
        Ok(match &self.geodesic {
            Some(geodesic) => Self {
                geodesic: Some(geodesic.clone()),
                ..field
            }
            .with_saddle_guards(),
            None => field,
        })
    }

    /// `Θ(x)`, `∇Θ(x)` and the descent direction. No allocation.
    ///
    /// # Errors
    /// [`FieldError::NotFinite`] for a non-finite point, [`FieldError::InObstacle`] inside a
    /// sensed obstacle, [`FieldError::Outside`] in the boundary layer (`sd(x) < δ`) or beyond a
    /// wall ([`FloorField::locate`] tells them apart).
    pub fn eval(&self, x: Vector2<f64>) -> Result<FieldEval, FieldError> {
        if !(x.x.is_finite() && x.y.is_finite()) {
            return Err(FieldError::NotFinite);
        }
        let m = self.transform.nav_transform(x)?;
        let (phi, g) = match self.world.phi_and_grad(m.h, None) {
            Ok(v) => v,
            Err(Singularity::Destination) => {
                return Ok(FieldEval {
                    value: 0.0,
                    gradient: Vector2::zeros(),
                    direction: None,
                    h: m.h,
                    phi: f64::NEG_INFINITY,
                });
            }
            // A hole's puncture is reached only from the layer (to rounding); a sensed one is
            // the obstacle's centre.
            Err(Singularity::Obstacle(slot)) => {
                return Err(match slot.checked_sub(self.transform.holes()) {
                    Some(obstacle) => FieldError::InObstacle { obstacle },
                    None => FieldError::Outside,
                });
            }
        };
        Ok(FieldEval::from_pullback(m.h, &m.jacobian, phi, g))
    }

    /// Why `Phi` is not defined at `x`, or `None` if it is.
    #[must_use]
    pub fn locate(&self, x: Vector2<f64>) -> Option<NotFree> {
        self.transform.nav_transform(x).err()
    }

    /// The transformation.
    #[must_use]
    pub fn transform(&self) -> &FloorTransform {
        &self.transform
    }

    /// The floor plan and its map.
    #[must_use]
    pub fn floor(&self) -> &Arc<FloorMap> {
        self.transform.floor()
    }

    /// The point world (`P_d`, the punctures then the sensed points, `k`).
    #[must_use]
    pub fn point_world(&self) -> &PointWorld {
        &self.world
    }

    /// The `k` policy.
    #[must_use]
    pub fn k_policy(&self) -> KPolicy {
        self.policy
    }

    /// `k` of `phi_k`.
    #[must_use]
    pub fn k(&self) -> f64 {
        self.world.k()
    }

    /// The smallest eigenvalue of `H(Θ)(x_d) = s·J_Phi(x_d)ᵀ J_Phi(x_d)`, `s` the point world's
    /// [`PointWorld::destination_stiffness`] (eq. `destphik2`, exponent `2/k`,
    /// `docs/maths.md` §2): the stiffness of the softest direction, the input of `λ_c`.
    #[must_use]
    pub fn destination_stiffness(&self) -> f64 {
        self.stiffness
    }

    /// The same field with the shortest-path distance to its goal on the walls' `W_δ`
    /// ([`Geodesic::new`], one fast march; kept by [`FloorField::with_obstacle`]) and the
    /// guard discs of the point world's saddles ([`SADDLE_GUARD`]).
    #[must_use]
    pub fn with_geodesic(self) -> Self {
        let geodesic = Geodesic::new(self.floor(), self.transform.goal());
        Self {
            geodesic: Some(Arc::new(geodesic)),
            ..self
        }
        .with_saddle_guards()
    }

    /// The same field with `other`'s shortest-path distance ([`FloorField::with_geodesic`],
    /// shared, not marched again; none if `other` has none) and its own saddles' guard discs: a
    /// funnel's field ([`crate::Funnels`]) keeps the heading towards the file's goal.
    #[must_use]
    pub fn with_geodesic_of(self, other: &FloorField) -> Self {
        match &other.geodesic {
            Some(g) => Self {
                geodesic: Some(g.clone()),
                ..self
            }
            .with_saddle_guards(),
            None => Self {
                geodesic: None,
                guards: Vec::new(),
                ..self
            },
        }
    }

    /// The guard discs about the saddles of the point world: centre `P_s` and radius
    /// [`SADDLE_GUARD`] times the distance from `P_s` to the nearest of `P_d` and the `P_i`.
    fn with_saddle_guards(self) -> Self {
        let world = &self.world;
        let points: Vec<Vector2<f64>> = std::iter::once(world.destination())
            .chain(world.obstacles().iter().copied())
            .collect();
        let guards = world
            .critical_points()
            .iter()
            .map(|c| {
                let near = points
                    .iter()
                    .map(|p| (p - c.position).norm())
                    .fold(f64::INFINITY, f64::min);
                (c.position, SADDLE_GUARD * near)
            })
            .collect();
        Self { guards, ..self }
    }

    /// The geodesic distance of [`FloorField::with_geodesic`], if built.
    #[must_use]
    pub fn geodesic(&self) -> Option<&Geodesic> {
        self.geodesic.as_deref()
    }

    /// The nominal heading at `x`, whose evaluation is `e`: the shortest-path direction
    /// [`Geodesic::heading`] if the geodesic distance is built and defined at `x`; `None`
    /// without it, and where `Phi(x) = e.h` lies in the guard disc of a saddle of `phi_k`
    /// (there the kinematic law is the paper's, whose saddles attract only the starts of a
    /// null set; that this survives the heading elsewhere is assumed, `docs/maths.md` §13.3).
    #[must_use]
    pub fn heading(&self, x: Vector2<f64>, e: &FieldEval) -> Option<Vector2<f64>> {
        let geodesic = self.geodesic.as_ref()?;
        if self.guards.iter().any(|(c, r)| (e.h - c).norm() < *r) {
            return None;
        }
        geodesic.heading(x)
    }
}
