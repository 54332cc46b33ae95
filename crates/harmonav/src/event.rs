//! One scan through the navigator's perception ([`observe`]): the hits the known shapes
//! explain, the fits of the rest, and the obstacles after an event ([`ScanEvent`]), grown by
//! `radius + margin`, that a world takes ([`crate::World`]); the growth of a perceived shape
//! ([`grow_perceived`]).

use harmonav_perception::{LaserScan, Perception, Pose, StarForm};
use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::error::NavError;
use crate::options::Options;
use crate::scanning::{ScanState, ScanUpdate};

/// The obstacles after a scan that changed the perceived shapes: the navigator's list with
/// the absorbed shapes removed, the grown ones replaced and the new ones appended (each grown
/// by `radius + margin`, and by `radius` alone into `inner` under a margin), the perception
/// state to keep if the navigator accepts them, and what the scan did.
pub struct ScanEvent {
    /// The obstacles, grown by `radius + margin`, in the navigator's order.
    pub(crate) obstacles: Vec<StarShape>,
    /// The same grown by `radius` alone (empty without a margin).
    pub(crate) inner: Vec<StarShape>,
    /// For each obstacle kept from before the scan, its index before it.
    pub(crate) keep: Vec<usize>,
    /// The robot's position at the scan.
    pub(crate) robot: Vector2<f64>,
    pub(crate) state: ScanState,
    pub(crate) update: ScanUpdate,
}

/// What one scan through the navigator's perception did.
pub(crate) enum Observed {
    /// No shape changed (nothing absorbed either: an absorption is a growth): the perception
    /// to keep (with the scan's evidence) and what the scan did.
    Quiet(Perception, ScanUpdate),
    /// Shapes changed: the obstacles to build the field from.
    Event(ScanEvent),
}

/// One scan through the navigator's perception `scan_state` (its obstacles `old`, grown, and
/// their bodies `old_inner`), for [`Navigator::observe_scan`] and
/// [`crate::FloorNavigator::observe_scan`], which build their fields from an event.
///
/// # Errors
/// The perception's error ([`ScanState::error`]); [`NavError::ContainsRobot`] when a changed
/// shape holds the robot ([`holds_robot`]).
pub(crate) fn observe(
    scan_state: &ScanState,
    old: &[StarShape],
    old_inner: &[StarShape],
    options: &Options,
    pose: Pose,
    scan: &LaserScan,
) -> Result<Observed, NavError> {
    let mut perception = scan_state.perception.clone();
    // The distance within which a changed shape refuses the event below (`holds_robot`):
    // the perception stops at the first fit or merge that certainly comes that near (its
    // shape ends in a changed one, which only grows), instead of fitting and merging the
    // rest of a scan that will be refused (`PerceptionError::HoldsSensor`).
    let guard = if options.scan.refuse_in_band {
        options.inflation()
    } else {
        options.radius
    };
    let obs = perception
        .observe_guarded(pose, scan, guard)
        .map_err(|e| scan_state.error(e))?;
    let mut update = ScanUpdate {
        hits: obs.hits,
        explained: obs.explained,
        unfitted: obs.unfitted.len(),
        ..ScanUpdate::default()
    };
    if obs.added.is_empty() && obs.grown.is_empty() {
        return Ok(Observed::Quiet(perception, update));
    }
    let old_slots = &scan_state.slots;
    let surviving: Vec<usize> = (0..old_slots.len())
        .filter(|i| obs.absorbed.binary_search(i).is_err())
        .collect();
    let mut removed: Vec<usize> = obs.absorbed.iter().map(|&i| old_slots[i]).collect();
    removed.sort_unstable();
    // Old navigator index → index after the removals.
    let remap = |j: usize| j - removed.partition_point(|&r| r < j);
    let with_margin = options.margin > 0.0;
    let keep: Vec<usize> = (0..old.len())
        .filter(|j| removed.binary_search(j).is_err())
        .collect();
    let mut obstacles: Vec<StarShape> = keep.iter().map(|&j| old[j].clone()).collect();
    let mut inner: Vec<StarShape> = if with_margin {
        keep.iter().map(|&j| old_inner[j].clone()).collect()
    } else {
        Vec::new()
    };
    let mut slots: Vec<usize> = surviving.iter().map(|&i| remap(old_slots[i])).collect();
    let exact: Vec<usize> = scan_state.exact.iter().map(|&j| remap(j)).collect();
    let x = pose.position();
    let (radius, inflation) = (options.radius, options.inflation());
    let mut event_clearance = f64::INFINITY;
    for (p, shape) in perception.perceived().iter().enumerate() {
        let is_new = p >= slots.len();
        if !is_new && obs.grown.binary_search(&p).is_err() {
            continue;
        }
        let form = options.scan.form;
        let grown = grow_perceived_as(shape.shape(), inflation, form)?;
        let body = if with_margin {
            Some(grow_perceived_as(shape.shape(), radius, form)?)
        } else {
            None
        };
        let band = if options.scan.refuse_in_band {
            None
        } else {
            body.as_ref()
        };
        if holds_robot(&grown, band, x) {
            return Err(NavError::ContainsRobot);
        }
        event_clearance = event_clearance.min(grown.signed_distance(x));
        if is_new {
            slots.push(obstacles.len());
            obstacles.push(grown);
            inner.extend(body);
            update.added.push(obstacles.len() - 1);
        } else {
            let j = slots[p];
            obstacles[j] = grown;
            if let Some(b) = body {
                inner[j] = b;
            }
            update.grown.push(j);
        }
    }
    update.absorbed = removed;
    update.event_clearance = Some(event_clearance);
    Ok(Observed::Event(ScanEvent {
        obstacles,
        inner,
        keep,
        robot: x,
        state: ScanState {
            perception,
            slots,
            exact,
        },
        update,
    }))
}

/// Whether a changed shape, grown by `radius + margin` (`grown`) and by `radius` alone
/// (`body`, `None` under [`crate::ScanOptions::refuse_in_band`] or without a margin), refuses
/// the event for the robot at `x`: `x` in the body (the robot's disc would overlap the shape),
/// or, without a body, in `grown`.
///
/// A robot in `grown` but outside the body is in the margin band, where the next command leads
/// out along the ray from the centre `c` through `x` (`hold::way_out`). Both growths are stars
/// about the perceived shape's centre `c` (the offset, the dilated hull and the disc all are),
/// and a point `c + t·u` of the body with `t > |x − c|` would put `x` on the body's segment
/// from `c`: so that ray never enters the body, however far the growth reaches past the margin
/// (a disc fallback, `R_max + r` about `c`). The kinematic robot moves along it; the dynamic
/// one does under semi-implicit Euler (`v⁺` lies along it), while under the exact hold of the
/// force it moves by `h(v + v⁺)/2` and its velocity before the event may point inwards, as for
/// any recovery. Before 2026-12-04 a robot `margin` or more outside
/// the body was refused, for the simulator's continuous integrator, which could not follow the
/// band (docs/maths.md §12.12).
fn holds_robot(grown: &StarShape, body: Option<&StarShape>, x: Vector2<f64>) -> bool {
    match body {
        None => grown.contains(x),
        Some(b) => b.contains(x),
    }
}

/// A perceived shape as the navigator holds it: `shape ⊕ B(r)`, grown by `r` (the robot's
/// radius and margin; [`StarShape::offset`]); when the offset is not star-shaped about the
/// centre (a merged radial hull with deep bays, `harmonav_perception::merge`), the disc
/// `B(c, R_max + r)`, which contains it (`R_max` bounds the shape's radius from above): a
/// perceived shape is a conservative bound, and so is its growth.
pub fn grow_perceived(shape: &StarShape, r: f64) -> Result<StarShape, NavError> {
    grow_perceived_as(shape, r, StarForm::Fourier)
}

/// [`grow_perceived`] for shapes of `form`. Under [`StarForm::Hull`] the fallback between the
/// offset and the disc is the radial hull of the dilation ([`StarShape::dilated_hull`]), which
/// contains it and never folds (a hull's concave corners fold its offset). Not for Fourier
/// stars (the form before docs/maths.md §12.11): there the dilated hull accepted an event that left the robot in its margin
/// band, which the simulator's continuous integrator cannot follow (`scale/many-300-sector`
/// rerun with a lidar, docs/maths.md §12.9–12.10), where the disc refused the scan.
pub fn grow_perceived_as(shape: &StarShape, r: f64, form: StarForm) -> Result<StarShape, NavError> {
    let disc =
        || StarShape::circle(shape.centre(), shape.radius_bounds().1 + r).map_err(NavError::Shape);
    match shape.offset(r) {
        Ok(grown) => Ok(grown),
        Err(_) if form == StarForm::Hull => shape
            .dilated_hull(r, GROW_SPACING * (shape.radius_bounds().1 + r))
            .or_else(|_| disc()),
        Err(_) => disc(),
    }
}

/// The spacing of [`StarShape::dilated_hull`]'s discs in [`grow_perceived_as`], relative to
/// the grown shape's size: the hull lies at most `δ + h/2` (about 0.1 % of the size) beyond
/// the dilation, plus its shadows about the centre.
const GROW_SPACING: f64 = 2e-3;

#[cfg(test)]
mod tests {
    use super::*;

    /// A bow tie `R = 0.3 + 0.25 cos 2θ` (waist 0.05 m) whose offset by the margin is not
    /// star-shaped about its centre: [`grow_perceived`] falls back to the disc of radius
    /// `0.55 + 0.05`. A robot in the waist's bay, 0.09 m outside the body, is inside that disc,
    /// `margin` and more beyond a true band: it is outside the body, so the event is accepted,
    /// and the way out of the band (`hold::way_out`, along the ray from the centre) reaches the
    /// disc's edge with every point of the way outside the body (2 000 points checked; the way
    /// towards the centre would cross the tie's waist). Under [`StarForm::Hull`] the fallback
    /// is the dilated hull, which holds the dilation (64 000 points of `∂tie ⊕ B(margin)`) and
    /// leaves the bay free. Without a body (no margin, or `refuse_in_band`) the grown shape
    /// alone decides, and a robot in the body is always refused.
    #[test]
    fn a_robot_past_the_margin_band_is_led_out_along_the_ray() {
        let margin = 0.05;
        let tie = StarShape::fourier_star(Vector2::zeros(), 0.3, &[(2, 0.25, 0.0)]).unwrap();
        assert!(tie.offset(margin).is_err(), "the offset must fall back");
        let grown = grow_perceived(&tie, margin).unwrap();
        let body = grow_perceived(&tie, 0.0).unwrap();
        let bay = Vector2::new(0.0, 0.2);
        assert!(grown.contains(bay) && !body.contains(bay));
        assert!(
            body.signed_distance(bay) > margin,
            "{}",
            body.signed_distance(bay)
        );
        assert!(!holds_robot(&grown, Some(&body), bay));
        assert!(holds_robot(&grown, None, bay));
        let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
        let goal = Vector2::new(3.0, 0.0);
        let ws = harmonav_transform::Workspace::new(boundary, vec![grown.clone()], goal).unwrap();
        let (dir, length) =
            crate::hold::way_out(&ws, crate::certified::Band::Obstacle(0), bay, margin).unwrap();
        assert!(dir.dot(&bay) > 0.0, "outward along the ray: {dir:?}");
        for j in 0..=2000 {
            let p = bay + (length * j as f64 / 2000.0) * dir;
            assert!(body.signed_distance(p) > 0.0, "{p:?} in the body");
        }
        assert!(
            !grown.contains(bay + length * dir),
            "the way ends outside the band"
        );
        let hull = grow_perceived_as(&tie, margin, StarForm::Hull).unwrap();
        assert!(!hull.contains(bay) && !holds_robot(&hull, Some(&body), bay));
        for j in 0..4000 {
            let p = tie.boundary_point(std::f64::consts::TAU * j as f64 / 4000.0);
            for k in 0..16 {
                let a = std::f64::consts::TAU * k as f64 / 16.0;
                let q = p + margin * Vector2::new(a.cos(), a.sin());
                assert!(hull.contains(q) || hull.signed_distance(q) <= 1e-9);
            }
        }
        // A disc: the offset is exact, and the band is `margin` thick.
        let disc = StarShape::circle(Vector2::zeros(), 0.5).unwrap();
        let (grown, body) = (
            grow_perceived(&disc, margin).unwrap(),
            grow_perceived(&disc, 0.0).unwrap(),
        );
        assert!(!holds_robot(&grown, Some(&body), Vector2::new(0.53, 0.0)));
        assert!(holds_robot(&grown, Some(&body), Vector2::new(0.45, 0.0)));
        assert!(holds_robot(&grown, None, Vector2::new(0.53, 0.0)));
        assert!(!holds_robot(&grown, None, Vector2::new(0.56, 0.0)));
    }
}
