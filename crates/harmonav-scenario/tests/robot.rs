//! `[robot]` read alike in both file formats (issue 51): `control_period`, read and checked
//! by name in a star world and on a floor plan.

use std::path::Path;

use harmonav_scenario::Scenario;
use harmonav_scenario::floorplan::FloorScenario;

/// A star world: a disc of radius 5 around one rock, with `robot` as its `[robot]` block and
/// `rest` after it.
fn star(robot: &str, rest: &str) -> String {
    format!(
        "name = \"star\"\n[workspace]\ntype = \"circle\"\ncenter = [0.0, 0.0]\nradius = 5.0\n\
         [[obstacles]]\ntype = \"circle\"\ncenter = [0.0, 0.0]\nradius = 1.0\n[robot]\n{robot}\n\
         {rest}"
    )
}

/// A floor plan: a 5 m square room, with `robot` as its `[robot]` block and `rest` after it.
fn floor(robot: &str, rest: &str) -> String {
    format!(
        "name = \"floor\"\n[floor_plan]\nouter = [[-5.0, -5.0], [5.0, -5.0], [5.0, 5.0], \
         [-5.0, 5.0]]\nmax_element = 0.5\n[robot]\n{robot}\n{rest}"
    )
}

const ROBOT: &str = "model = \"dynamic\"\nstart = [-3.0, 0.2]\ngoal = [3.0, 0.0]";

fn star_period(text: &str) -> Option<f64> {
    let path = Path::new("star.toml");
    let p = Scenario::parse(path, text)
        .and_then(|s| s.prepare(path))
        .unwrap_or_else(|e| panic!("{e}"));
    p.control_period()
}

fn floor_period(text: &str) -> Option<f64> {
    let path = Path::new("floor.toml");
    let p = FloorScenario::parse(path, text)
        .and_then(|s| s.prepare(path))
        .unwrap_or_else(|e| panic!("{e}"));
    p.control_period()
}

#[test]
fn both_formats_read_the_control_period_under_robot() {
    let with = format!("{ROBOT}\ncontrol_period = 0.02");
    assert_eq!(star_period(&star(&with, "")), Some(0.02));
    assert_eq!(floor_period(&floor(&with, "")), Some(0.02));
    // Absent: the law's default, as before the key existed.
    assert_eq!(star_period(&star(ROBOT, "")), None);
    assert_eq!(floor_period(&floor(ROBOT, "")), None);
    // Not a key of a star world's `[controller]`: one place for both formats.
    let path = Path::new("star.toml");
    let e = Scenario::parse(path, &star(ROBOT, "[controller]\ncontrol_period = 0.02")).unwrap_err();
    assert!(e.problem.contains("unknown field"), "{e}");
}

#[test]
fn a_star_world_with_a_control_period_round_trips() {
    let path = Path::new("star.toml");
    let parsed = Scenario::parse(path, &star(&format!("{ROBOT}\ncontrol_period = 0.02"), ""))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(parsed.controller.control_period, Some(0.02));
    let text = toml::to_string(&parsed).unwrap();
    assert!(text.contains("control_period = 0.02"), "{text}");
    assert_eq!(Scenario::parse(path, &text).unwrap(), parsed);
}

#[test]
fn a_bad_control_period_is_refused_naming_the_key_and_the_file() {
    for (value, problem) in [
        ("0.0", "must be finite"),
        ("-0.01", "must be finite"),
        ("nan", "must be finite"),
        ("inf", "must be finite"),
        ("1e10", "must be finite"),
        // 200 s of periods of 1e-8 s: 2e10 steps of a held-command loop.
        ("1e-8", "periods; at most"),
    ] {
        let robot = format!("{ROBOT}\ncontrol_period = {value}");
        let path = Path::new("star-bad.toml");
        let e = Scenario::parse(path, &star(&robot, ""))
            .and_then(|s| s.prepare(path))
            .unwrap_err();
        assert_eq!(e.field, "robot.control_period", "{value}: {e}");
        assert!(e.problem.contains(problem), "{value}: {e}");
        assert!(e.to_string().starts_with("star-bad.toml"), "{e}");
        let path = Path::new("floor-bad.toml");
        let e = FloorScenario::parse(path, &floor(&robot, ""))
            .and_then(|s| s.prepare(path))
            .unwrap_err();
        assert_eq!(e.field, "robot.control_period", "{value}: {e}");
        assert!(e.problem.contains(problem), "{value}: {e}");
        assert!(e.to_string().starts_with("floor-bad.toml"), "{e}");
    }
    // Not a number: the parser's error, naming the key and its line.
    let path = Path::new("star-bad.toml");
    let e = Scenario::parse(
        path,
        &star(&format!("{ROBOT}\ncontrol_period = \"fast\""), ""),
    )
    .unwrap_err();
    assert_eq!(e.field, "robot.control_period", "{e}");
    let path = Path::new("floor-bad.toml");
    let e = FloorScenario::parse(
        path,
        &floor(&format!("{ROBOT}\ncontrol_period = \"fast\""), ""),
    )
    .unwrap_err();
    assert_eq!(e.field, "robot.control_period", "{e}");
}
