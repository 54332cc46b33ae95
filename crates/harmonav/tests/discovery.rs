//! `Navigator::add_obstacle` (a discovery in place) against the field built at once over the
//! same grown obstacles: the same `Phi` and `k`, the same `Θ`, `∇Θ` (direct point-world sums:
//! bit for bit; with the multipole tree: to its tolerance).

use std::sync::Arc;

use harmonav::{Law, Navigator, Options};
use harmonav_field::Field;
use harmonav_transform::Workspace;
use harmonav_transform::random::{self, Kind, Rng};

#[test]
fn discoveries_give_the_field_built_at_once() {
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let w = random::scattered(&mut Rng::new(3), 30.0, 200, &kinds, 0.3).unwrap();
    let options = Options::default().with_robot(0.1, 0.02);
    let mut nav = Navigator::new(w.boundary.clone(), w.goal, Law::kinematic(1.0), options).unwrap();
    let mut added = 0;
    for o in &w.obstacles {
        // A few stars cannot be grown by the robot's radius and stay stars: skipped.
        match nav.add_obstacle(o.clone()) {
            Ok(i) => {
                assert_eq!(i, added);
                added += 1;
            }
            Err(e) => assert!(matches!(e, harmonav::NavError::Shape(_)), "{e}"),
        }
    }
    assert!(added > 150, "{added}");
    let ws = nav.field().workspace();
    let scratch = Workspace::new(ws.boundary().clone(), nav.obstacles().to_vec(), w.goal).unwrap();
    let built = Field::all_known_with(Arc::new(scratch), options.k).unwrap();
    assert_eq!(nav.k().to_bits(), built.k().to_bits());
    let (a, b) = (nav.field().transform(), built.transform());
    assert!(
        a.widths()
            .zip(b.widths())
            .all(|(x, y)| x.to_bits() == y.to_bits())
    );
    assert_eq!(a.outer_band(), b.outer_band());
    let direct = (
        nav.field().clone().without_far_field(),
        built.clone().without_far_field(),
    );
    let mut rng = Rng::new(8);
    for _ in 0..1000 {
        let x = random::free_point(&mut rng, built.workspace(), 1e-9);
        assert_eq!(a.nav_transform(x), b.nav_transform(x));
        assert_eq!(direct.0.eval(x), direct.1.eval(x));
        let (ea, eb) = (nav.field().eval(x).unwrap(), built.eval(x).unwrap());
        assert!((ea.value - eb.value).abs() <= 1e-11 * eb.value.max(1e-300));
        assert!((ea.gradient - eb.gradient).norm() <= 1e-8 * eb.gradient.norm() + 1e-300);
    }
}
