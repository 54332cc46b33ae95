//! harmonav in your own robot loop: your integrator, your perception (discs within 1 m are
//! reported), the Navigator's commands. Runs both laws and exits non-zero if a run fails.
//!
//! `cargo run --release --manifest-path examples/Cargo.toml --bin own_loop` (a project of its
//! own, outside the workspace, whose only dependency is `harmonav`)

use harmonav::{Law, NavError, Navigator, Options, StarShape, Vector2};

/// The world as it is, unknown to the robot.
fn truth() -> Result<Vec<StarShape>, harmonav::ShapeError> {
    [([-1.5, 0.4], 0.5), ([0.6, -0.5], 0.6), ([2.0, 1.2], 0.4)]
        .iter()
        .map(|&([x, y], r)| StarShape::circle(Vector2::new(x, y), r))
        .collect()
}

/// One run at `hz` with `law`; returns the time to the goal.
fn run(law: Law, hz: f64) -> Result<f64, Box<dyn std::error::Error>> {
    let boundary = StarShape::circle(Vector2::zeros(), 4.0)?;
    let goal = Vector2::new(3.0, 0.0);
    let options = Options::default()
        .with_sensor(1.0, 60.0)
        .with_robot(0.1, 0.05);
    let mut nav = Navigator::new(boundary, goal, law, options)?;
    let world = truth()?;
    let mut seen = vec![false; world.len()];
    let (mut x, mut v, h) = (Vector2::new(-3.2, -0.3), Vector2::zeros(), 1.0 / hz);
    let mut t = 0.0;
    while (x - goal).norm() > 0.01 {
        // Perception: a disc whose outline is within 1 m is reported once.
        for (o, s) in world.iter().zip(seen.iter_mut()) {
            if !*s && o.signed_distance(x) < 1.0 {
                nav.add_obstacle(o.clone())?;
                *s = true;
                // A spurious detection overlapping a known obstacle is refused, and the
                // navigator goes on unchanged.
                let ghost = StarShape::circle(o.centre() + Vector2::new(0.1, 0.0), 0.3)?;
                match nav.add_obstacle(ghost) {
                    Err(NavError::Overlap { .. }) => {}
                    other => return Err(format!("the ghost was not refused: {other:?}").into()),
                }
            }
        }
        let cmd = nav.command(x, v)?.value;
        match law {
            Law::Kinematic { .. } => x += h * cmd,
            Law::Dynamic { mass, .. } => {
                v += h * cmd / mass; // semi-implicit Euler
                x += h * v;
            }
        }
        t += h;
        let clearance = world
            .iter()
            .map(|o| o.signed_distance(x))
            .fold(f64::INFINITY, f64::min);
        if clearance <= 0.1 {
            return Err(format!("collision at t = {t:.2} s, x = {x:?}").into());
        }
        if t > 120.0 {
            return Err("no arrival within 120 s".into());
        }
    }
    Ok(t)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let kinematic = run(Law::kinematic(1.0), 200.0)?;
    let dynamic = run(Law::dynamic(1.0, 10.0), 1000.0)?;
    println!(
        "kinematic (200 Hz): goal in {kinematic:.2} s; dynamic (1 kHz): goal in {dynamic:.2} s"
    );
    Ok(())
}
