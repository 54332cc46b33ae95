//! Obstacles that join a star world's boundary: furniture against a wall.
//!
//! A star world holds disjoint obstacles strictly inside its boundary, all grown by
//! `radius + margin`. An obstacle found within `2(radius + margin)` of a wall breaks that: the
//! gap behind it is closed to the robot, but the world cannot say so, and before 2026-12-06
//! the navigator refused it (`NavError::CrossesBoundary`, and with it the scan). Now the
//! boundary takes it in: the navigator's boundary becomes the star about the boundary's centre
//! with the obstacle and its shadow cut out ([`StarShape::carved`], eq. carve in
//! `harmonav_transform::carve`), and the field is built over that boundary and the other
//! obstacles. A shape that then reaches the carved boundary (one in the shadow, or against the
//! dent) joins it too, until the world is valid.
//!
//! The navigator's obstacle indices do not change: [`Joined`] keeps every known obstacle in
//! the navigator's order, which ones joined the boundary, and maps the field's indices to the
//! navigator's. With no obstacle joined, nothing changes, bit for bit.
//!
//! Joining is refused ([`NavError::CrossesBoundary`]) when the goal or the robot would be left
//! outside (behind the obstacle, as seen from the centre), or the obstacle holds the
//! boundary's centre.

use std::sync::Arc;

use harmonav_field::Field;
use harmonav_transform::{StarShape, Workspace, WorldError};
use nalgebra::Vector2;

use crate::error::NavError;
use crate::options::Options;

/// The most obstacles that may join the boundary in one rebuild (each costs one carve).
const MAX_JOINED: usize = 64;

/// The boundaries before any obstacle joined, and the obstacles that did.
#[derive(Clone, Debug)]
pub(crate) struct Joined {
    /// The boundary shrunk by `radius + margin`, as built.
    boundary: StarShape,
    /// The boundary shrunk by `radius` alone, as built (`None` without a margin).
    inner: Option<StarShape>,
    /// The navigator's indices of the obstacles that joined the boundary, sorted.
    pub(crate) indices: Vec<usize>,
    /// Every known obstacle, grown, in the navigator's order (empty while none joined).
    all: Vec<StarShape>,
}

/// What a rebuild of a star world gives: the field, the inner boundary and the joined state.
pub(crate) struct Rebuilt {
    pub(crate) field: Field,
    pub(crate) inner: Option<StarShape>,
    pub(crate) joined: Joined,
}

/// The obstacles, grown, to build a star world from, with their bodies and the robot.
pub(crate) struct Known<'a> {
    /// Every obstacle, grown by `radius + margin`, in the navigator's order.
    pub(crate) grown: &'a [StarShape],
    /// The same grown by `radius` alone (empty without a margin).
    pub(crate) bodies: &'a [StarShape],
    /// The obstacles that joined the boundary before, in this order's indices.
    pub(crate) joined: Vec<usize>,
    /// The robot's position, if known: it must stay inside the boundary it leaves.
    pub(crate) robot: Option<Vector2<f64>>,
}

impl Joined {
    /// Nothing joined, over the boundaries as built.
    pub(crate) fn new(boundary: StarShape, inner: Option<StarShape>) -> Self {
        Self {
            boundary,
            inner,
            indices: Vec::new(),
            all: Vec::new(),
        }
    }

    /// Whether any obstacle joined the boundary.
    pub(crate) fn any(&self) -> bool {
        !self.indices.is_empty()
    }

    /// Every known obstacle in the navigator's order, if any joined (else the field's list is).
    pub(crate) fn all(&self) -> Option<&[StarShape]> {
        self.any().then_some(&self.all[..])
    }

    /// Records an obstacle the field took as its own (appended to both lists).
    pub(crate) fn push(&mut self, grown: StarShape) {
        self.all.push(grown);
    }

    /// The navigator's index of the field's obstacle `i`.
    pub(crate) fn navigator_index(&self, i: usize) -> usize {
        navigator_index(&self.indices, i)
    }

    /// The field's index of the navigator's obstacle `j`, `None` if it joined the boundary.
    pub(crate) fn field_index(&self, j: usize) -> Option<usize> {
        field_index(&self.indices, j)
    }

    /// The field over `known`'s obstacles towards `goal`, with the obstacles that reach the
    /// boundary joined to it (module docs), starting from `known.joined`; `field` is the field
    /// before, whose discovery state the new one keeps ([`Field::all_known_after`]).
    ///
    /// # Errors
    /// [`NavError::CrossesBoundary`] when an obstacle cannot join (the goal, the robot or the
    /// centre behind it, or more than [`MAX_JOINED`]); `overlap` of the navigator's indices
    /// when two obstacles overlap; [`NavError::ContainsGoal`]; the field's.
    pub(crate) fn rebuild(
        &self,
        field: &Field,
        known: Known<'_>,
        goal: Vector2<f64>,
        options: &Options,
        overlap: impl Fn(usize, usize) -> NavError,
    ) -> Result<Rebuilt, NavError> {
        let mut joined = known.joined;
        loop {
            let (boundary, inner) = if joined.is_empty() {
                (self.boundary.clone(), self.inner.clone())
            } else {
                self.carve(&joined, known.grown, known.bodies)?
            };
            if let (false, Some(x)) = (joined.is_empty(), known.robot) {
                // The robot's disc clear of the true boundary, cut: not behind a joined shape.
                if !inner.as_ref().unwrap_or(&boundary).contains(x) {
                    return Err(NavError::CrossesBoundary);
                }
            }
            let rest: Vec<StarShape> = (0..known.grown.len())
                .filter(|j| joined.binary_search(j).is_err())
                .map(|j| known.grown[j].clone())
                .collect();
            match Workspace::new(boundary, rest, goal) {
                Ok(ws) => {
                    let field = field
                        .all_known_after(Arc::new(ws), options.k)
                        .map_err(NavError::Field)?;
                    let all = if joined.is_empty() {
                        Vec::new()
                    } else {
                        known.grown.to_vec()
                    };
                    return Ok(Rebuilt {
                        field,
                        inner,
                        joined: Joined {
                            boundary: self.boundary.clone(),
                            inner: self.inner.clone(),
                            indices: joined,
                            all,
                        },
                    });
                }
                Err(WorldError::OutsideBoundary { obstacle }) => {
                    let j = navigator_index(&joined, obstacle);
                    if joined.len() >= MAX_JOINED {
                        return Err(NavError::CrossesBoundary);
                    }
                    let at = joined.partition_point(|&k| k < j);
                    joined.insert(at, j);
                }
                Err(WorldError::Overlap { first, second }) => {
                    return Err(overlap(
                        navigator_index(&joined, first),
                        navigator_index(&joined, second),
                    ));
                }
                Err(WorldError::InObstacle { .. }) => return Err(NavError::ContainsGoal),
                Err(_) => return Err(NavError::CrossesBoundary),
            }
        }
    }

    /// The boundaries with the obstacles `joined` (navigator indices into `grown` and
    /// `bodies`) cut out: the field's from the grown shapes, the inner one from the bodies.
    fn carve(
        &self,
        joined: &[usize],
        grown: &[StarShape],
        bodies: &[StarShape],
    ) -> Result<(StarShape, Option<StarShape>), NavError> {
        let cut = |boundary: &StarShape, shapes: &[StarShape]| {
            let list: Vec<&StarShape> = joined.iter().filter_map(|&j| shapes.get(j)).collect();
            boundary
                .carved(&list)
                .map_err(|_| NavError::CrossesBoundary)
        };
        let boundary = cut(&self.boundary, grown)?;
        let inner = match &self.inner {
            Some(inner) => Some(cut(inner, bodies)?),
            None => None,
        };
        Ok((boundary, inner))
    }
}

/// The field's index of the navigator's obstacle `j` when the navigator's obstacles `joined`
/// (sorted) joined the boundary (or the walls): `None` if `j` is among them, else `j` less
/// how many joined before it. The inverse of [`navigator_index`].
pub(crate) fn field_index(joined: &[usize], j: usize) -> Option<usize> {
    match joined.binary_search(&j) {
        Ok(_) => None,
        Err(before) => Some(j - before),
    }
}

/// The navigator's index of the field's obstacle `i` when the navigator's obstacles `joined`
/// (sorted) joined the boundary: the `i`-th index not among them.
pub(crate) fn navigator_index(joined: &[usize], i: usize) -> usize {
    let mut j = i;
    for &k in joined {
        if k <= j {
            j += 1;
        } else {
            break;
        }
    }
    j
}
