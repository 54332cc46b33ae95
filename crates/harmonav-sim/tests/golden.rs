//! The golden command traces (issue 51's instrument, `cargo xtask traces`): a file's movers
//! reach the navigator, and a differential drive is traced by `command_pose`.

use std::path::Path;

use harmonav_scenario::{Model, Scenario};
use harmonav_sim::golden;

fn load(path: &str) -> harmonav_scenario::Prepared {
    Scenario::load(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios")
            .join(path),
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The hex words of a trace line: `t x.x x.y v.x v.y c.x c.y`, then the mode.
fn words(line: &str) -> (Vec<f64>, &str) {
    let mut parts: Vec<&str> = line.split(' ').collect();
    let mode = parts.pop().unwrap_or("");
    let numbers = parts
        .iter()
        .map(|w| f64::from_bits(u64::from_str_radix(w, 16).unwrap()))
        .collect();
    (numbers, mode)
}

/// The person walking across the robot's way is given to the navigator: the trace yields to
/// it, and differs from the trace of the same file without its movers (the trace before
/// 2026-12-07, which was the same for both).
#[test]
fn a_files_movers_reach_the_traced_navigator() {
    let with = load("movers/person-crossing.toml");
    let mut without = with.clone();
    without.scenario.sim.movers.clear();
    let a = golden::star(&with, Model::Kinematic, 2000).unwrap();
    let b = golden::star(&without, Model::Kinematic, 2000).unwrap();
    assert_ne!(a, b);
    assert!(a.lines().any(|l| l.ends_with(" yielding")), "{a:.400}");
    assert!(!b.lines().any(|l| l.ends_with(" yielding")));
}

/// A differential drive is traced by `command_pose`: each command is `(v, ω)` within the
/// base's bounds, forward only, and the first turns in place (the robot starts facing away).
#[test]
fn a_differential_drive_is_traced_by_its_pose_commands() {
    let p = load("diff/six-discs-away.toml");
    let trace = golden::star(&p, Model::Kinematic, 2000).unwrap();
    let commands: Vec<(f64, f64)> = trace
        .lines()
        .filter(|l| !l.starts_with("end"))
        .map(|l| {
            let (w, _) = words(l);
            (w[5], w[6])
        })
        .collect();
    assert!(commands.len() > 10);
    for &(v, omega) in &commands {
        assert!((0.0..=0.5).contains(&v), "v = {v}");
        assert!(omega.abs() <= 2.0, "ω = {omega}");
    }
    assert_eq!(commands[0].0, 0.0, "{:?}", commands[0]);
    assert!(commands[0].1.abs() > 0.0);
}
