//! Sampled-data safety of the Navigator in the user's own loop (`docs/maths.md` §10): 300
//! seeded disc worlds (`harmonav::checks::disc_world`), point and disc robots with and without
//! a margin, at every documented control rate, and the negative control with the hold off.

use harmonav::checks::{SuiteReport, suite};
use harmonav::{HoldPolicy, Law, Options, SpeedPolicy};

use super::{Check, Outcome, outcome};

/// Worlds of the suite.
const WORLDS: u64 = 300;

/// The arrival the suite must show at each rate (the "done when").
const ARRIVAL: f64 = 0.98;

pub fn checks() -> Vec<Check> {
    let mut all = Vec::new();
    for (hz, law) in [
        (100, Law::kinematic(1.0)),
        (50, Law::kinematic(1.0)),
        (20, Law::kinematic(1.0)),
        (1000, Law::dynamic(1.0, 10.0)),
        (500, Law::dynamic(1.0, 10.0)),
        (250, Law::dynamic(1.0, 10.0)),
    ] {
        let name = match law {
            Law::Kinematic { .. } => format!("navigator.sampled-data.kinematic-{hz}hz"),
            Law::Dynamic { .. } => format!("navigator.sampled-data.dynamic-{hz}hz"),
        };
        all.push(Check::new(name, move || safe_at(law, hz)).early());
    }
    all.push(Check::new("navigator.sampled-data.negative-control", negative_control).early());
    all
}

fn run(law: Law, hz: u32, hold: HoldPolicy) -> Result<SuiteReport, String> {
    let options = Options::default().with_hold(hold);
    suite(0..WORLDS, law, options, 1.0 / f64::from(hz)).map_err(|e| e.to_string())
}

/// Every flight safe (no true shape touched, no grown shape entered, every command finite and
/// accepted), at least 98 % arrive, and the dynamic robot stays below √(2μ/m).
fn safe_at(law: Law, hz: u32) -> Outcome {
    let r = run(law, hz, HoldPolicy::Auto)?;
    let bound = match law {
        Law::Dynamic { mass, mu } => (2.0 * mu / mass).sqrt(),
        Law::Kinematic { .. } => f64::INFINITY,
    };
    let first = r
        .failures
        .first()
        .map_or(String::new(), |(seed, radius, margin, f)| {
            format!(
                "; first: world {seed}, radius {radius}, margin {margin}: true clearance {:.2e}, \
             grown {:.2e}, error {:?}",
                f.true_clearance, f.grown_clearance, f.error
            )
        });
    outcome(
        r.failures.is_empty() && r.arrival() >= ARRIVAL && r.max_speed < bound,
        format!(
            "{} runs: {} unsafe, {:.1} % arrived ({} stalled), median {:.2} s, {} commands \
             capped, top speed {:.2} m/s{first}",
            r.runs,
            r.failures.len(),
            100.0 * r.arrival(),
            r.stalled,
            r.median_time,
            r.capped,
            r.max_speed
        ),
    )
}

/// The same suite with the hold off (`HoldPolicy::Paper`, the continuous law sampled as is)
/// must show the defect, at the documented 100 Hz (kinematic) and at 250 Hz (dynamic): the
/// suite can see what the hold prevents. The kinematic law keeps the paper's speed `K√(2Θ)`
/// here, under which the defect was found (the paper's law sampled as is).
fn negative_control() -> Outcome {
    let paper_speed = Options::default()
        .with_hold(HoldPolicy::Paper)
        .with_speed(SpeedPolicy::Paper);
    let kinematic =
        suite(0..WORLDS, Law::kinematic(1.0), paper_speed, 0.01).map_err(|e| e.to_string())?;
    let dynamic = run(Law::dynamic(1.0, 10.0), 250, HoldPolicy::Paper)?;
    let count = |r: &SuiteReport| {
        let touched = r
            .failures
            .iter()
            .filter(|f| f.3.true_clearance <= 0.0)
            .count();
        (r.failures.len(), touched)
    };
    let (k, kt) = count(&kinematic);
    let (d, dt) = count(&dynamic);
    outcome(
        k > 0 && d > 0,
        format!(
            "hold off: kinematic 100 Hz {k} of {} runs unsafe ({kt} touched a true shape), \
             dynamic 250 Hz {d} of {} ({dt} touched)",
            kinematic.runs, dynamic.runs
        ),
    )
}
