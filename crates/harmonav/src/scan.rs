//! The navigator fed by range scans (issue 26, part 2; docs/maths.md §12.6):
//! [`Navigator::observe_scan`] turns a `sensor_msgs/LaserScan` into new and grown obstacles
//! through `harmonav-perception`, and treats each change like a discovery of
//! [`Navigator::add_obstacle`].
//!
//! **What it keeps.** The true workspace boundary (hits on it are explained), the exact shapes
//! of `add_obstacle` (the perception's map: their hits are explained, a fit that overlaps one is
//! refused) and the perceived shapes, each with its index among [`Navigator::obstacles`].
//!
//! **The event rule.** A hit is dropped when it lies within `ε_x = max(ε, ε_g)` of an exact
//! shape or the boundary, or less than `g_w − ε` from the boundary (eq. explained; `ε` =
//! [`crate::ScanOptions::range_noise`], `ε_g` = [`crate::ScanOptions::growth_threshold`], `g_w` =
//! [`crate::ScanOptions::wall_gap`]); a segment of hits is dropped when one perceived
//! shape is within `ε_x` of all of them and within `d_ev` ([`crate::ScanOptions::evidence`]) of
//! the hits it was fitted to (eq. attribution, docs/maths.md §12.8). Other segments are fitted,
//! so an event needs a hit that no shape explains: more than `ε_x` outside, or more than
//! `d_ev` from the evidence of, every shape. The hits of successive events are therefore
//! `min(ε_x, d_ev/2)` apart (less the distance bracket), and a robot whose lidar sees a bounded
//! region causes finitely many events (a packing bound; docs/maths.md §12.6, §12.8).

use harmonav_transform::StarShape;

pub use harmonav_perception::{LaserScan, Perceived, Pose, StarForm};

use crate::controller::event_speed;
use crate::error::NavError;
use crate::event::{Observed, observe};
use crate::navigator::Navigator;
use crate::scanning::ScanUpdate;
use crate::world::World;

impl<W: World> Navigator<W> {
    /// Observes one scan taken from `pose` (the sensor at the robot's centre, heading `yaw`):
    /// drops the hits that exact shapes or the boundary explain within `max(ε, ε_g)` (the
    /// boundary also less than `g_w − ε` away, under the wall prior) and the
    /// segments a perceived shape explains (eqs. explained, attribution), fits conservative
    /// stars to the rest, merges fits with the perceived shapes
    /// they overlap (shapes only grow), and hands every new or grown shape to the field grown
    /// by `radius + margin` (docs/maths.md §12). A change is an event, handled as a discovery
    /// of [`Navigator::add_obstacle`]: `k`, `Φ` and the dynamic law's `|ẋ(T_n)|` (the speed of
    /// the last commanded state) update. Allocates; a scan that changes nothing rebuilds
    /// nothing.
    ///
    /// Every perceived shape contains the true obstacle it saw when the truth satisfies the
    /// priors of [`crate::ScanOptions`] and [`crate::Options::rho_min`] (A1–A4 of `harmonav_perception`).
    ///
    /// Errors (the navigator, its perceived shapes included, is then unchanged):
    /// [`NavError::Perception`] for a scan or pose that is not valid (empty, non-finite angles,
    /// `angle_increment ≤ 0`, bad range limits, overlapping beams), a sensor inside a known
    /// shape or outside the boundary; [`NavError::NotStarWorld`] when a new or grown shape
    /// overlaps an exact shape of [`Navigator::add_obstacle`], or when the grown shapes overlap
    /// where the certified distances could not tell them apart (perceived shapes themselves
    /// always merge);
    /// [`NavError::ContainsRobot`] when a changed shape grown by `radius` contains the pose
    /// (by `radius + margin` under [`crate::ScanOptions::refuse_in_band`]). A pose outside the
    /// first but inside the second is in the shape's margin band, however thick the growth
    /// made it (a fallback of [`grow_perceived`](crate::grow_perceived) reaches past `radius + margin`): the next
    /// [`Navigator::command`] leads out along the ray from the shape's centre
    /// ([`crate::Mode::Recovering`]), which never enters the body (see `holds_robot`);
    /// [`NavError::ContainsGoal`]; [`NavError::CrossesBoundary`]. An update that certainly
    /// ends with `ContainsRobot` (a fit or a merge certainly within `radius` of the pose, or
    /// fits that share points all round it: `harmonav_perception::Perception::observe_guarded`)
    /// is refused as soon as that is certain, with that error: a scan of ranges at random
    /// (rain, dust, glass, a failing lidar) costs a few fits, not a fit and a merge per beam.
    ///
    /// On a floor plan hits within `max(ε, ε_g)` of the true walls (or nearer them than
    /// `g_w − ε` under the wall prior) are explained, fits are kept out of the walls (and `g_w`
    /// from them). A changed shape that does not lie in the certified region with its growth
    /// (decided by [`crate::FloorMap::star_room`], `docs/maths.md` §12.17) joins the walls
    /// ([`crate::FloorMap::carved`], §12.22): `H` is solved again without it and its gap to the
    /// wall, and [`Navigator::joined`] lists it; a join that would cut off the goal or the
    /// robot is [`crate::FloorError::CutOff`]. A sensor outside the walls is
    /// [`NavError::Perception`].
    ///
    /// A refused scan changes nothing in `Θ` or the perception; what it saw is not certified
    /// against, so every [`Navigator::command`] after it halts the robot
    /// ([`crate::Mode::Halted`]) until a scan is accepted (issue 56: it used to give the
    /// command from before the scan, as if the space were free). The simulator ends the run
    /// there (outcome `scan-refused`).
    pub fn observe_scan(&mut self, pose: Pose, scan: &LaserScan) -> Result<ScanUpdate, NavError> {
        let result = self.observe_once(pose, scan);
        self.core.scan_refused = result.is_err();
        result
    }

    /// [`Navigator::observe_scan`] without the memory of a refusal.
    fn observe_once(&mut self, pose: Pose, scan: &LaserScan) -> Result<ScanUpdate, NavError> {
        let old = self.world.known();
        let event = match observe(
            &self.core.scan,
            &old,
            &self.core.inner,
            &self.core.options,
            pose,
            scan,
        )? {
            Observed::Quiet(perception, update) => {
                // The same shapes, and the field stands; the perception keeps the evidence
                // the scan added (eq. attribution).
                self.core.scan.perception = perception;
                return Ok(update);
            }
            Observed::Event(event) => event,
        };
        self.world.sensed(&event, &self.core.options)?;
        self.world.discovered();
        self.core.inner = event.inner;
        let speed = self.core.last.map_or(0.0, |(_, v)| v.norm());
        let clearance = event.update.event_clearance.unwrap_or(f64::INFINITY);
        self.core.speed_at_discovery = event_speed(
            &self.core.controller,
            speed,
            clearance,
            self.core.options.margin,
        );
        self.core.scan = event.state;
        Ok(event.update)
    }

    /// The perceived shapes (not grown), each with its index among [`Navigator::obstacles`],
    /// in the perception's order. Each contains the true obstacle it saw under the priors.
    pub fn perceived(&self) -> impl Iterator<Item = (usize, &Perceived)> + '_ {
        self.core.scan.perceived()
    }

    /// The shapes given to [`Navigator::add_obstacle`] (true, not grown), each with its index
    /// among [`Navigator::obstacles`], in the order they were added. With
    /// [`Navigator::perceived`] they are every known obstacle.
    pub fn added(&self) -> impl Iterator<Item = (usize, &StarShape)> + '_ {
        self.core.scan.added()
    }
}
