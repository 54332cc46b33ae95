//! [`Space`]: what the sampled-data hold needs of a navigation function and its free space —
//! `Θ`, the certified clearance `d(x)` and the way out of the blind layer — for a star world
//! ([`Field`]) and a floor plan ([`FloorField`]), so that one hold serves both. It is the
//! field of a [`crate::World`] (sealed: public in a private module).

use harmonav_control::{Calibration, Dynamic};
use harmonav_field::{Field, FieldError, FieldEval};
use harmonav_floorplan::FloorField;
use nalgebra::Vector2;

use crate::certified::{self, Band};

/// The hold's view of a navigation function over its free space (`docs/maths.md` §10).
pub trait Space {
    /// `Θ`, `∇Θ` and the direction at `x`; an error outside the free space.
    fn eval(&self, x: Vector2<f64>) -> Result<FieldEval, FieldError>;
    /// The goal `x_d` (the kinematic law's speed policy brakes on `|x − x_d|`).
    fn goal(&self) -> Vector2<f64>;
    /// The certified clearance `d(x)` clipped at `need`: a lower bound on the distance to every
    /// known grown shape (but `except`) and to the boundary (for a floor plan: to the boundary
    /// layer `sd < δ`).
    fn clearance(&self, x: Vector2<f64>, need: f64, except: Option<Band>) -> f64;
    /// The way out of the blind layer of a shape that is not a circle (`hold::kinematic_escape`, the dynamic hold).
    fn blind_exit(&self, x: Vector2<f64>, most: f64) -> Option<(Band, Vector2<f64>, f64)>;
    /// The motion `u` the hold should certify at `x` for a step of length `reach`: `u` itself
    /// in a star world; on a floor plan, within `2·reach` of the boundary layer or of a sensed
    /// obstacle, `u` without its component into it, each projected in turn (a later projection
    /// can restore some of an earlier one's component: the hold's caps, applied after, keep
    /// every step certified).
    fn slide(&self, x: Vector2<f64>, u: Vector2<f64>, reach: f64) -> Vector2<f64> {
        let _ = (x, reach);
        u
    }
    /// What the dynamic law reads of this `Θ` ([`Calibration`]): the destination stiffness
    /// (the smallest eigenvalue of `H(Θ)(x_d)`) and the scale shift of the law's potential:
    /// `Dynamic::scale_shift` of a star world's field; 0 on a floor plan, whose `Θ` is free of
    /// the world's scale already (its harmonic map goes onto the unit disk).
    fn calibration(&self, law: &Dynamic) -> Calibration;
    /// The nominal heading at `x` (evaluated: `e`; `Kinematic::velocity_toward`,
    /// `Dynamic::turned`): none in a star world; on a floor plan the shortest-path direction,
    /// if built.
    fn heading(&self, x: Vector2<f64>, e: &FieldEval) -> Option<Vector2<f64>> {
        let _ = (x, e);
        None
    }
}

impl Space for Field {
    fn eval(&self, x: Vector2<f64>) -> Result<FieldEval, FieldError> {
        Field::eval(self, x)
    }

    fn goal(&self) -> Vector2<f64> {
        self.workspace().destination()
    }

    fn clearance(&self, x: Vector2<f64>, need: f64, except: Option<Band>) -> f64 {
        certified::clearance(self.workspace(), x, need, except)
    }

    fn blind_exit(&self, x: Vector2<f64>, most: f64) -> Option<(Band, Vector2<f64>, f64)> {
        certified::blind_exit(self.workspace(), x, most)
    }

    fn calibration(&self, law: &Dynamic) -> Calibration {
        law.calibration(self)
    }
}

/// On a floor plan, [`Band::Boundary`] is the boundary layer of the walls: its clearance is
/// `sd(x) − δ` (parry's exact point–segment distances, `FloorMap::clearance`), so a step that
/// the hold certifies never enters the layer; the sensed obstacles keep their certified
/// star-shape bounds.
impl Space for FloorField {
    fn eval(&self, x: Vector2<f64>) -> Result<FieldEval, FieldError> {
        FloorField::eval(self, x)
    }

    fn goal(&self) -> Vector2<f64> {
        self.transform().goal()
    }

    fn clearance(&self, x: Vector2<f64>, need: f64, except: Option<Band>) -> f64 {
        let mut best = need;
        if except != Some(Band::Boundary) {
            best = best.min(self.floor().clearance(x));
        }
        for (i, o) in self.transform().obstacles().enumerate() {
            if except == Some(Band::Obstacle(i)) {
                continue;
            }
            let cheap = (x - o.centre()).norm() - o.radius_bounds().1;
            if cheap < best {
                best = best.min(certified::lower(o, x));
            }
        }
        best
    }

    /// Projected descent on `W_δ` minus the sensed obstacles (`docs/maths.md` §13): where the
    /// step could reach the layer (`sd(x) − δ < 2·reach`) and `u` points into it (`u·n > 0`,
    /// `n` the unit vector from `x` to the nearest point of `∂W_s`), the hold certifies
    /// `u − (u·n)n` instead; then the same for each grown sensed obstacle within `2·reach`, with
    /// `n` the unit vector from `x` to its centre (a star shape's ray, the normal only for a
    /// circle). For the kinematic law
    /// `u = −c∇Θ`, so for any unit `n`, `u'·∇Θ = −c|∇Θ|² + c(∇Θ·n)² ≤ 0`: still a descent
    /// direction (the halving then makes `Θ` decrease). After two or more projections (a
    /// corner of the layer, or an obstacle beside it) that is not proved: the kinematic hold
    /// checks it (`hold::slid_descent`) and every held step is still certified free. Where
    /// `−∇Θ` points exactly at a sensed obstacle's centre the slid `u` is 0 and the hold rests
    /// there, though it is not a critical point of `Θ` (a null set of states, unstable). Without it the descent around a
    /// reflex corner ran into the layer edge and stalled there (the L room: 3 of 7 starts),
    /// and a robot sent round a sensed obstacle whose repulsion is a thin shell (§13.2) stopped
    /// on it (the office: the clearance cap shortens every step that aims into the shell).
    fn slide(&self, x: Vector2<f64>, u: Vector2<f64>, reach: f64) -> Vector2<f64> {
        let project = |u: Vector2<f64>, n: Vector2<f64>| {
            let into = u.dot(&n);
            if into > 0.0 { u - into * n } else { u }
        };
        let floor = self.floor();
        let mut u = u;
        if floor.clearance(x) < 2.0 * reach
            && let Some(n) = floor.toward_boundary(x)
        {
            u = project(u, n);
        }
        for o in self.transform().obstacles() {
            let to_centre = o.centre() - x;
            let r = to_centre.norm();
            // Cheapest first: near the shape's bounding disc, heading towards it, then the
            // certified distance.
            if r > 0.0
                && r - o.radius_bounds().1 < 2.0 * reach
                && u.dot(&to_centre) > 0.0
                && certified::lower(o, x) < 2.0 * reach
            {
                u = project(u, to_centre / r);
            }
        }
        u
    }

    fn calibration(&self, law: &Dynamic) -> Calibration {
        let _ = law;
        Calibration {
            stiffness: self.destination_stiffness(),
            shift: 0.0,
        }
    }

    fn heading(&self, x: Vector2<f64>, e: &FieldEval) -> Option<Vector2<f64>> {
        FloorField::heading(self, x, e)
    }

    /// Only a sensed obstacle has a blind layer (the walls' distances are exact to rounding):
    /// the ray from its centre through `x`, as the star world's. `None` when the walls are the
    /// nearest: the hold then keeps its (shortened) law step.
    fn blind_exit(&self, x: Vector2<f64>, most: f64) -> Option<(Band, Vector2<f64>, f64)> {
        let mut worst: Option<(usize, f64)> = None;
        for (i, o) in self.transform().obstacles().enumerate() {
            let d = certified::lower(o, x);
            if worst.is_none_or(|(_, w)| d < w) {
                worst = Some((i, d));
            }
        }
        let (i, d) = worst?;
        if d > self.floor().clearance(x) {
            return None;
        }
        let shape = self.transform().obstacles().nth(i)?;
        let (dir, _) = certified::ray(shape, x)?;
        let band = Band::Obstacle(i);
        let others = self.clearance(x, 2.0 * most, Some(band)).max(0.0);
        let length = certified::blind_layer(shape, x).min(0.5 * others).min(most);
        (length > 0.0).then_some((band, dir, length))
    }
}
