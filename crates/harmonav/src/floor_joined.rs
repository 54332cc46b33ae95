//! Obstacles that join a floor plan's walls: furniture against a wall (issue 52).
//!
//! A floor plan takes a sensed obstacle into `B` only when the obstacle and its band lie in
//! the certified region `W_δ` ([`FloorError::ObstacleNearWall`] otherwise, eq. starroom of
//! `docs/maths/12-range-scans.md` §12.17). Before 2026-12-06 that refused the scan, and with
//! it every later one that saw the same furniture. Now the walls take it in
//! ([`FloorMap::carved`], eq. wallcut): `W_s` loses a polygon holding the obstacle grown by
//! the floor's shrink `s`, `H` is solved again on what is left (the component of the goal),
//! and the field is built over that floor and the other obstacles. An obstacle that then
//! reaches the new layer joins too, until the field can be built.
//!
//! **What is cut.** `W_δ' = {sd' ≥ δ}` must keep `s + δ = radius + margin` from the true
//! obstacle. With a margin of at most `δ` the shape grown by `radius` alone holds the
//! obstacle grown by `s = radius + margin − δ ≤ radius`; with a larger margin the shape grown
//! by `radius + margin` does. Either costs at most `δ` of free space around the joined
//! obstacle, which a floor plan's walls do not (its cost: gaps up to `δ` narrower).
//!
//! The navigator's obstacle indices do not change ([`FloorJoined`] maps the field's to them).
//! With no obstacle joined nothing changes, bit for bit: the field is built as before.
//!
//! A join is refused when the goal or the robot would be cut off ([`FloorError::CutOff`]:
//! behind the obstacle, or the robot not in the new `W_s`), and beyond [`MAX_JOINED`]
//! ([`FloorError::TooManyJoined`]); the scan (or `add_obstacle`) is then refused as before,
//! and the navigator unchanged. Every obstacle that reaches the layer joins in one pass (one
//! solve).

use std::cmp::Ordering;
use std::sync::Arc;

use harmonav_floorplan::{FloorError, FloorField, FloorMap};
use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::error::NavError;
use crate::joined::{Known, field_index, navigator_index};
use crate::options::Options;

/// The most obstacles that may join a floor plan's walls (each join solves `H` again).
const MAX_JOINED: usize = 64;

/// The floor as built, and the obstacles that joined its walls.
#[derive(Clone, Debug)]
pub(crate) struct FloorJoined {
    /// The floor before any obstacle joined.
    base: Arc<FloorMap>,
    /// The navigator's indices of the obstacles that joined the walls, sorted.
    pub(crate) indices: Vec<usize>,
    /// Every known obstacle, grown by `radius + margin`, in the navigator's order (empty
    /// while none joined).
    all: Vec<StarShape>,
    /// The shapes cut out of `W_s` for `indices`, in that order (module docs).
    cuts: Vec<StarShape>,
    /// The obstacles of `indices` grown by `radius` (by `radius + margin` where no body was
    /// given): the robot's disc is clear of the obstacle when its centre is outside.
    bodies: Vec<StarShape>,
}

impl FloorJoined {
    /// Nothing joined, over the floor as built.
    pub(crate) fn new(base: Arc<FloorMap>) -> Self {
        Self {
            base,
            indices: Vec::new(),
            all: Vec::new(),
            cuts: Vec::new(),
            bodies: Vec::new(),
        }
    }

    /// Whether any obstacle joined the walls.
    pub(crate) fn any(&self) -> bool {
        !self.indices.is_empty()
    }

    /// Every known obstacle in the navigator's order, if any joined (else the field's list is).
    pub(crate) fn all(&self) -> Option<&[StarShape]> {
        self.any().then_some(&self.all[..])
    }

    /// The navigator's index of the field's obstacle `i`.
    pub(crate) fn navigator_index(&self, i: usize) -> usize {
        navigator_index(&self.indices, i)
    }

    /// The field's index of the navigator's obstacle `j`, `None` if it joined the walls.
    pub(crate) fn field_index(&self, j: usize) -> Option<usize> {
        field_index(&self.indices, j)
    }

    /// `sd(x)` on the floor before any obstacle joined (`FloorMap::signed_distance`).
    pub(crate) fn base_signed_distance(&self, x: Vector2<f64>) -> f64 {
        self.base.signed_distance(x)
    }

    /// A certified lower bound on the distance from `x` to the joined obstacles' bodies,
    /// less `radius` (`+∞` with none joined): positive when the robot's disc at `x` is clear
    /// of every joined obstacle. 1-Lipschitz.
    pub(crate) fn body_clearance(&self, x: Vector2<f64>) -> f64 {
        self.bodies
            .iter()
            .map(|b| b.signed_distance_bounds(x).0)
            .fold(f64::INFINITY, f64::min)
    }

    /// The field over `known`'s obstacles, with those that reach the boundary layer joined to
    /// the walls (module docs), starting from `known.joined`; `field` is the field before (its
    /// goal, `k` policy and shortest path; its floor is kept when the cuts are the same).
    ///
    /// # Errors
    /// [`FloorError::CutOff`] when the goal or the robot would be cut off;
    /// [`FloorError::TooManyJoined`] beyond [`MAX_JOINED`]; `overlap` of the navigator's
    /// indices when two obstacles overlap; the floor's other errors.
    pub(crate) fn rebuild(
        &self,
        field: &FloorField,
        known: Known<'_>,
        options: &Options,
        overlap: impl Fn(usize, usize) -> NavError,
    ) -> Result<(FloorField, FloorJoined), NavError> {
        let goal = field.transform().goal();
        // Grown by `radius` holds the obstacle grown by `s` when `margin ≤ δ` (module docs).
        let by_body = options.margin <= self.base.delta();
        // The bodies only when there is one for every obstacle (none without a margin): a list
        // that does not line up with the grown shapes is not used.
        let bodies = (known.bodies.len() == known.grown.len()).then_some(known.bodies);
        let body = |j: usize| bodies.map_or(&known.grown[j], |b| &b[j]);
        let mut joined = known.joined;
        loop {
            let cuts: Vec<StarShape> = joined
                .iter()
                .map(|&j| {
                    if by_body {
                        body(j).clone()
                    } else {
                        known.grown[j].clone()
                    }
                })
                .collect();
            let same = cuts.len() == self.cuts.len()
                && cuts.iter().zip(&self.cuts).all(|(a, b)| a.is_clone_of(b));
            let floor = if joined.is_empty() {
                self.base.clone()
            } else if same {
                field.floor().clone()
            } else {
                let carved = Arc::new(self.base.carved(&cuts, goal)?);
                // A new cut must leave the robot in the free space (not behind or in it).
                if let Some(x) = known.robot
                    && carved.signed_distance(x).partial_cmp(&0.0) != Some(Ordering::Greater)
                {
                    return Err(FloorError::CutOff { what: "robot" }.into());
                }
                carved
            };
            let rest: Vec<StarShape> = (0..known.grown.len())
                .filter(|j| joined.binary_search(j).is_err())
                .map(|j| known.grown[j].clone())
                .collect();
            // Every obstacle that reaches this floor's layer joins at once (the field's own
            // test, `FloorMap::star_room`), one solve of `H` for them all.
            let near: Vec<usize> = rest
                .iter()
                .enumerate()
                .filter(|(_, o)| floor.star_room(o).partial_cmp(&0.0) != Some(Ordering::Greater))
                .map(|(i, _)| navigator_index(&joined, i))
                .collect();
            if !near.is_empty() {
                if joined.len() + near.len() > MAX_JOINED {
                    return Err(FloorError::TooManyJoined {
                        count: joined.len() + near.len(),
                        max: MAX_JOINED,
                    }
                    .into());
                }
                joined.extend(near);
                joined.sort_unstable();
                continue;
            }
            let built = if Arc::ptr_eq(&floor, field.floor()) {
                field.with_sensed(&rest)
            } else {
                FloorField::with_obstacles(floor, &rest, goal, field.k_policy()).map(|f| {
                    if field.geodesic().is_some() {
                        f.with_geodesic()
                    } else {
                        f
                    }
                })
            };
            match built {
                Ok(field) => {
                    let any = !joined.is_empty();
                    let bodies = joined.iter().map(|&j| body(j).clone()).collect();
                    let joined = FloorJoined {
                        base: self.base.clone(),
                        all: if any {
                            known.grown.to_vec()
                        } else {
                            Vec::new()
                        },
                        indices: joined,
                        cuts,
                        bodies,
                    };
                    return Ok((field, joined));
                }
                Err(FloorError::ObstacleNearWall { obstacle }) => {
                    // Not found by the test above (the same one): kept as the field's error.
                    return Err(FloorError::ObstacleNearWall {
                        obstacle: navigator_index(&joined, obstacle),
                    }
                    .into());
                }
                Err(FloorError::Overlap { first, second }) => {
                    return Err(overlap(
                        navigator_index(&joined, first),
                        navigator_index(&joined, second),
                    ));
                }
                Err(FloorError::ContainsGoal { obstacle }) => {
                    return Err(FloorError::ContainsGoal {
                        obstacle: navigator_index(&joined, obstacle),
                    }
                    .into());
                }
                Err(e) => return Err(e.into()),
            }
        }
    }
}
