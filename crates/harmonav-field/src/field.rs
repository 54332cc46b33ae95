//! [`Field`]: `Θ` over the known obstacles.

use std::sync::Arc;

use harmonav_potential::batch::CHUNK;
use harmonav_potential::{CriticalPoint, PointWorld, PotentialError, Singularity, sigma_and_prime};
use harmonav_transform::{Active, NavTransform, NotFree, StarShape, Workspace, WorldError};
use nalgebra::{Matrix2, Vector2};

use crate::k_policy::{KPolicy, Layer};

/// Why `Θ` cannot be evaluated or the field not built.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum FieldError {
    /// The point lies in (or on) known obstacle `obstacle` (a workspace index).
    InObstacle {
        /// The obstacle.
        obstacle: usize,
    },
    /// The point lies on or outside the workspace boundary.
    Outside,
    /// The point has a NaN or infinite coordinate.
    NotFinite,
    /// The workspace or an obstacle index is invalid.
    World(WorldError),
    /// The point world is invalid (e.g. two obstacles share a centre).
    Potential(PotentialError),
}

impl std::fmt::Display for FieldError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InObstacle { obstacle } => write!(f, "the point lies inside obstacle {obstacle}"),
            Self::Outside => write!(f, "the point lies on or outside the workspace boundary"),
            Self::NotFinite => write!(f, "the point is not finite"),
            Self::World(e) => write!(f, "{e}"),
            Self::Potential(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for FieldError {}

impl From<WorldError> for FieldError {
    fn from(e: WorldError) -> Self {
        Self::World(e)
    }
}

impl From<PotentialError> for FieldError {
    fn from(e: PotentialError) -> Self {
        Self::Potential(e)
    }
}

/// One evaluation of the field at a workspace point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldEval {
    /// `Θ(x) ∈ [0, 1]`.
    pub value: f64,
    /// `∇Θ(x)` (may underflow to 0 far from the goal; use `direction`).
    pub gradient: Vector2<f64>,
    /// `−∇Θ/|∇Θ|`, from `J_Phiᵀ∇phi_k` so that it survives the underflow of `sigma'`;
    /// `None` at the goal and at exact critical points.
    pub direction: Option<Vector2<f64>>,
    /// `h = Phi(x)`.
    pub h: Vector2<f64>,
    /// `phi_k(h)`.
    pub phi: f64,
}

impl FieldEval {
    /// `Θ(x)`, the field [`FieldEval::value`] under its glossary name (docs/ARCHITECTURE.md).
    #[must_use]
    pub fn theta(&self) -> f64 {
        self.value
    }
}

/// A critical point of `Θ` in the workspace: the destination (minimum) or the pull-back of a
/// saddle of `phi_k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Critical {
    /// Workspace position.
    pub x: Vector2<f64>,
    /// The point-world critical point (`None` for the destination, the minimum).
    pub point_world: Option<CriticalPoint>,
}

/// `Θ = sigma∘phi_k∘Phi` over the known obstacles, with obstacle memory.
#[derive(Clone, Debug)]
pub struct Field {
    workspace: Arc<Workspace>,
    transform: NavTransform,
    world: PointWorld,
    /// `H(Θ)(x_d) = stiffness·I`, computed at discovery.
    stiffness: f64,
    /// How `k` follows the known obstacles.
    policy: KPolicy,
    /// The terms of `layer_ratio`, kept for [`Field::push_obstacle`].
    layer: Layer,
}

impl Field {
    /// The field with the obstacles `known` already known (assumption `localobs`) and `k` from
    /// the default policy ([`KPolicy::Auto`]).
    pub fn new(
        workspace: Arc<Workspace>,
        known: impl IntoIterator<Item = usize>,
    ) -> Result<Self, FieldError> {
        Self::with_policy(workspace, known, KPolicy::default())
    }

    /// The field with the obstacles `known` already known and `k = policy.k_for(n, layer_ratio)`
    /// (recomputed at every discovery, as the paper's `k = n + 1` is).
    pub fn with_policy(
        workspace: Arc<Workspace>,
        known: impl IntoIterator<Item = usize>,
        policy: KPolicy,
    ) -> Result<Self, FieldError> {
        // First occurrences, in order: O(n) with a seen-flag per obstacle (was O(n²)).
        let mut seen = vec![false; workspace.obstacles().len()];
        let mut ids: Vec<usize> = Vec::new();
        for i in known {
            match seen.get_mut(i) {
                Some(s) if *s => {}
                Some(s) => {
                    *s = true;
                    ids.push(i);
                }
                // Out of range: `build` reports it (NoSuchObstacle); keep the first of each.
                None if !ids.contains(&i) => ids.push(i),
                None => {}
            }
        }
        let (transform, world, layer) = build(&workspace, &ids, policy, None)?;
        Ok(Self::from_parts(workspace, transform, world, policy, layer))
    }

    /// The field of `Phi` and the point world built over `workspace` (the destination's
    /// stiffness from the point world).
    fn from_parts(
        workspace: Arc<Workspace>,
        transform: NavTransform,
        world: PointWorld,
        policy: KPolicy,
        layer: Layer,
    ) -> Self {
        let stiffness = world.destination_stiffness();
        Self {
            workspace,
            transform,
            world,
            stiffness,
            policy,
            layer,
        }
    }

    /// The field with every obstacle known (global sensing), default policy.
    pub fn all_known(workspace: Arc<Workspace>) -> Result<Self, FieldError> {
        Self::all_known_with(workspace, KPolicy::default())
    }

    /// The field with every obstacle known (global sensing) and `k` from `policy`.
    pub fn all_known_with(workspace: Arc<Workspace>, policy: KPolicy) -> Result<Self, FieldError> {
        let n = workspace.obstacles().len();
        Self::with_policy(workspace, 0..n, policy)
    }

    /// [`Self::all_known_with`] on `workspace`, a workspace that extends this field's by
    /// obstacles appended after its own (`Workspace::with_obstacle`, as a discovery of
    /// `Navigator::add_obstacle` makes it): the same field, but the point world's multipole
    /// tree (from [`harmonav_potential::far::FAR_MIN`] obstacles on) is extended rather than
    /// rebuilt (`PointWorld::new_after`).
    pub fn all_known_after(
        &self,
        workspace: Arc<Workspace>,
        policy: KPolicy,
    ) -> Result<Self, FieldError> {
        let ids: Vec<usize> = (0..workspace.obstacles().len()).collect();
        let (transform, world, layer) = build(&workspace, &ids, policy, Some(&self.world))?;
        Ok(Self::from_parts(workspace, transform, world, policy, layer))
    }

    /// This field with the point world summed directly at every point
    /// ([`PointWorld::without_far_field`]): the reference of the multipole path.
    #[must_use]
    pub fn without_far_field(mut self) -> Self {
        self.world = self.world.without_far_field();
        self
    }

    /// Eq. (`phiseq`): obstacle `id` becomes known; `k` becomes the policy's value for `n + 1`
    /// known obstacles and `Phi` is rebuilt with new widths. Returns `false` if it was already
    /// known (obstacles are never forgotten, assumption `objpers`). On error the field is
    /// unchanged.
    pub fn discover(&mut self, id: usize) -> Result<bool, FieldError> {
        if self.transform.known().contains(&id) {
            return Ok(false);
        }
        let mut ids = self.transform.known().to_vec();
        ids.push(id);
        let (transform, world, layer) =
            build(&self.workspace, &ids, self.policy, Some(&self.world))?;
        self.transform = transform;
        self.stiffness = world.destination_stiffness();
        self.world = world;
        self.layer = layer;
        Ok(true)
    }

    /// A discovery in place: `obstacle` is added to the workspace as obstacle `M` (validated
    /// as `Workspace::with_obstacle` validates it) and becomes known, in the next slot. The
    /// result is the field [`Self::with_policy`] builds over that workspace with the same known
    /// obstacles and `M` last: the same `Phi` bit for bit (the same widths `ε_i`, `ε_0`, gain
    /// `A` and `k`: [`NavTransform::push`] narrows only the bands the new obstacle can narrow),
    /// the same point world (its multipole sums to their tolerance, as
    /// [`PointWorld::new_after`]'s), the same stiffness. Returns `M`.
    ///
    /// Cost: the new obstacle's own distances (to the boundary, the destination and its near
    /// obstacles), a few index queries, the multipole push (`PointWorld::push`), and `O(M)`
    /// comparisons and additions (the point world's duplicate check and valley sum, the layer
    /// ratio when `ε_0` moves). Nothing is copied unless the workspace or the multipole tree is
    /// shared with a clone of this field (then that one is copied once); the multipole tree is
    /// built when `M` reaches `FAR_MIN` and rebuilt when it doubles (docs/maths.md §15), so
    /// those discoveries cost a tree build (milliseconds at `M` = 1 000, docs/benchmarks.md).
    ///
    /// Everything that can fail is checked before anything changes: on error the field is
    /// unchanged. Errors: the workspace's ([`FieldError::World`]: overlap, outside the
    /// boundary, containing the destination), a point world that cannot take the point, `k`
    /// or the valley radius not finite (guards).
    pub fn push_obstacle(&mut self, obstacle: StarShape) -> Result<usize, FieldError> {
        let admitted = self.workspace.admit(obstacle)?;
        let p = admitted.obstacle().centre();
        let eps0 = self.transform.outer_width_with(admitted.to_boundary());
        let term = Layer::term(&self.workspace, p);
        let ratio = self.layer.ratio_with(term, eps0);
        let k = self.policy.k_for(self.transform.known().len() + 1, ratio);
        self.world.check_push(p, k)?;
        let valley = self
            .world
            .valley_radius_with(p, k, self.transform.outer_centre());
        if !(valley.is_finite() && valley >= 0.0) {
            return Err(WorldError::InvalidValleyRadius { value: valley }.into());
        }
        // Commit: nothing below can fail (each error was ruled out above).
        let ws = Arc::make_mut(&mut self.workspace);
        let index = ws.commit(admitted)?;
        self.transform.push(ws, index)?;
        self.world.push(p, k)?;
        self.transform.set_valley_radius(valley)?;
        self.layer.push(term, eps0, ratio);
        self.stiffness = self.world.destination_stiffness();
        Ok(index)
    }

    /// The workspace.
    pub fn workspace(&self) -> &Workspace {
        &self.workspace
    }

    /// Known obstacles (workspace indices), in discovery order.
    pub fn known(&self) -> &[usize] {
        self.transform.known()
    }

    /// `k` of `phi_k` for the known obstacles (`policy.k_for(n, layer_ratio)`).
    pub fn k(&self) -> f64 {
        self.world.k()
    }

    /// The policy that sets `k`.
    pub fn k_policy(&self) -> KPolicy {
        self.policy
    }

    /// The navigation transformation for the known obstacles.
    pub fn transform(&self) -> &NavTransform {
        &self.transform
    }

    /// The point world (`P_d`, `P_i`, `k`) the controllers need, e.g. for `lambda_c`.
    pub fn point_world(&self) -> &PointWorld {
        &self.world
    }

    /// `H(Θ)(x_d) = s·I` with `s = 2/Π_i|P_d − P_i|^{2/k}` (eq. `destphik2` with the exponent
    /// established in `docs/maths.md` §2; `Phi` is the identity around `x_d`). The spring
    /// constant of eq. `critdamp` is `μ·s`.
    pub fn destination_stiffness(&self) -> f64 {
        self.stiffness
    }

    /// `Θ(x)`, `∇Θ(x)` and the descent direction (eq. `NFcand` with the chain rule of theorem
    /// `isNF`). Errors if `x` is not in the free space of the known obstacles. No allocation.
    pub fn eval(&self, x: Vector2<f64>) -> Result<FieldEval, FieldError> {
        // Guard: a NaN point would pass every band test and come back as a NaN Θ.
        if !(x.x.is_finite() && x.y.is_finite()) {
            return Err(FieldError::NotFinite);
        }
        let mapped = self.transform.nav_transform(x).map_err(|e| match e {
            NotFree::Obstacle(slot) => FieldError::InObstacle {
                obstacle: self.transform.known()[slot],
            },
            NotFree::Outside => FieldError::Outside,
        })?;
        let exact = match mapped.active {
            Active::Obstacle { slot, offset } => Some((slot, offset)),
            _ => None,
        };
        let (phi, g) = match self.world.phi_and_grad(mapped.h, exact) {
            Ok(v) => v,
            Err(Singularity::Destination) => {
                return Ok(FieldEval {
                    value: 0.0,
                    gradient: Vector2::zeros(),
                    direction: None,
                    h: mapped.h,
                    phi: f64::NEG_INFINITY,
                });
            }
            Err(Singularity::Obstacle(slot)) => {
                return Err(FieldError::InObstacle {
                    obstacle: self.transform.known()[slot],
                });
            }
        };
        Ok(finish(mapped.h, &mapped.jacobian, phi, g))
    }

    /// [`Field::eval`] at every point of `xs` into `out` (the same values, bit for bit),
    /// faster for batches: points outside the obstacle bands (where `Phi` needs no exact
    /// offset) go through [`PointWorld::phi_and_grad_many`] in chunks, vectorised across
    /// points; the others through `eval`. No allocation.
    ///
    /// Errors: `out` not as long as `xs` ([`PotentialError::LengthMismatch`]; nothing written).
    pub fn eval_many(
        &self,
        xs: &[Vector2<f64>],
        out: &mut [Result<FieldEval, FieldError>],
    ) -> Result<(), FieldError> {
        if xs.len() != out.len() {
            return Err(PotentialError::LengthMismatch {
                lengths: [xs.len(), xs.len(), out.len(), out.len()],
            }
            .into());
        }
        for (xs, out) in xs.chunks(CHUNK).zip(out.chunks_mut(CHUNK)) {
            let len = xs.len();
            let mut hs = [Vector2::zeros(); CHUNK];
            let mut jacobians = [Matrix2::zeros(); CHUNK];
            let mut mapped = [false; CHUNK];
            self.transform.identity_mask(xs, &mut mapped[..len]);
            for (i, &x) in xs.iter().enumerate() {
                if mapped[i] {
                    hs[i] = x;
                    jacobians[i] = Matrix2::identity();
                    continue;
                }
                match self.transform.nav_transform(x) {
                    Ok(m) if !matches!(m.active, Active::Obstacle { .. }) => {
                        hs[i] = m.h;
                        jacobians[i] = m.jacobian;
                        mapped[i] = true;
                    }
                    _ => out[i] = self.eval(x),
                }
            }
            let mut potential = [None; CHUNK];
            self.world
                .phi_and_grad_many(&hs[..len], &mut potential[..len])?;
            for i in (0..len).filter(|&i| mapped[i]) {
                out[i] = match potential[i] {
                    Some((phi, g)) => Ok(finish(hs[i], &jacobians[i], phi, g)),
                    None => self.eval(xs[i]),
                };
            }
        }
        Ok(())
    }

    /// The critical points of `Θ`: the destination (the unique minimum) and the `M` saddles of
    /// `phi_k` pulled back through `Phi⁻¹` (theorem `isNF`: `C(phi_k) = Phi(C(Θ) − {x_d})`).
    pub fn critical_points(&self) -> Vec<Critical> {
        let mut out = vec![Critical {
            x: self.workspace.destination(),
            point_world: None,
        }];
        for c in self.world.critical_points() {
            if let Some(x) = self.transform.inverse(c.position) {
                out.push(Critical {
                    x,
                    point_world: Some(c),
                });
            }
        }
        out
    }
}

impl FieldEval {
    /// `Θ = sigma(phi)`, `∇Θ = sigma'(phi)·J_Phiᵀ∇phi_k` and the direction at `h = Phi(x)`,
    /// from `phi = phi_k(h)`, `g = ∇phi_k(h)` and `J_Phi(x)`: the chain rule of every
    /// navigation function `sigma ∘ phi_k ∘ Phi` (star worlds here, floor plans in
    /// harmonav-floorplan). The direction is taken from `J_Phiᵀ∇phi_k` scaled, so that it
    /// survives the underflow of `sigma'`.
    #[must_use]
    pub fn from_pullback(
        h: Vector2<f64>,
        jacobian: &Matrix2<f64>,
        phi: f64,
        g: Vector2<f64>,
    ) -> Self {
        finish(h, jacobian, phi, g)
    }
}

/// [`FieldEval::from_pullback`].
fn finish(h: Vector2<f64>, jacobian: &Matrix2<f64>, phi: f64, g: Vector2<f64>) -> FieldEval {
    let gx = jacobian.transpose() * g;
    // Guard: normalise a scaled copy so that |gx| neither overflows nor underflows.
    let scale = gx.x.abs().max(gx.y.abs());
    let direction = (scale > 0.0 && scale.is_finite()).then(|| {
        let s = gx / scale;
        -s / s.norm()
    });
    let (value, slope) = sigma_and_prime(phi);
    FieldEval {
        value,
        gradient: slope * gx,
        direction,
        h,
        phi,
    }
}

/// `Phi` and the point world over `known`; the point world reuses `previous`'s multipole tree
/// when its points are the first of the new ones (`PointWorld::new_after`).
fn build(
    ws: &Workspace,
    known: &[usize],
    policy: KPolicy,
    previous: Option<&PointWorld>,
) -> Result<(NavTransform, PointWorld, Layer), FieldError> {
    // The bands do not depend on k; the layer rule of KPolicy::Auto depends on the bands.
    let transform = NavTransform::new(ws, known, 0.0)?;
    let layer = Layer::new(ws, &transform);
    let k = policy.k_for(known.len(), layer.ratio);
    let mut points = Vec::with_capacity(known.len());
    for &obstacle in known {
        let o = ws.obstacles().get(obstacle);
        points.push(o.ok_or(WorldError::NoSuchObstacle { obstacle })?.centre());
    }
    let world = match previous {
        Some(previous) => PointWorld::new_after(previous, ws.destination(), points)?,
        None => PointWorld::new(ws.destination(), points)?,
    }
    .with_k(k)?;
    // The potential supplies the radius of its far-field valley, which Phi's outer band holds.
    let c0 = transform.outer_centre();
    let transform = transform.with_valley_radius(world.valley_radius(c0))?;
    Ok((transform, world, layer))
}
