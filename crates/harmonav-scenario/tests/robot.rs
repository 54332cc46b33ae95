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

/// Issue 51: a star world and a floor plan with the same `[robot]` block run with the same
/// `μ`, arrival tolerance and control period (before, `μ` was 10 in a star world and 1 on a
/// floor plan, the arrival 0.01 m and 0.05 m).
#[test]
fn the_same_robot_block_gets_the_same_defaults_in_both_formats() {
    for robot in [
        ROBOT.to_string(),
        format!("{ROBOT}\ncontrol_period = 0.02"),
        format!("{ROBOT}\nmass = 2.0"),
    ] {
        let path = Path::new("star.toml");
        let s = Scenario::parse(path, &star(&robot, ""))
            .and_then(|s| s.prepare(path))
            .unwrap_or_else(|e| panic!("{e}"));
        let path = Path::new("floor.toml");
        let f = FloorScenario::parse(path, &floor(&robot, ""))
            .and_then(|s| s.prepare(path))
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.scenario.controller.mu, f.scenario.robot.mu, "{robot}");
        assert_eq!(s.scenario.controller.gain, f.scenario.robot.gain, "{robot}");
        assert_eq!(s.scenario.robot.mass, f.scenario.robot.mass, "{robot}");
        assert_eq!(
            s.scenario.sim.goal_tolerance, f.scenario.sim.arrival,
            "{robot}"
        );
        assert_eq!(s.control_period(), f.control_period(), "{robot}");
    }
    // The values: the star world's, and Python's `mu`.
    let path = Path::new("floor.toml");
    let f = FloorScenario::parse(path, &floor(ROBOT, "")).unwrap();
    assert_eq!(f.robot.mu, harmonav_scenario::DEFAULT_MU);
    assert_eq!(f.sim.arrival, harmonav_scenario::DEFAULT_ARRIVAL);
    assert_eq!((f.robot.mu, f.sim.arrival), (10.0, 0.01));
}

/// The arrival tolerance takes either name in either format (`sim.goal_tolerance`, a star
/// world's, and `sim.arrival`, a floor plan's), but not both at once.
#[test]
fn the_arrival_takes_either_name_in_either_format() {
    for key in ["goal_tolerance", "arrival"] {
        let sim = format!("[sim]\n{key} = 0.05");
        let path = Path::new("star.toml");
        let s = Scenario::parse(path, &star(ROBOT, &sim)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.sim.goal_tolerance, 0.05, "{key}");
        let path = Path::new("floor.toml");
        let f = FloorScenario::parse(path, &floor(ROBOT, &sim)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(f.sim.arrival, 0.05, "{key}");
    }
    let both = "[sim]\ngoal_tolerance = 0.05\narrival = 0.05";
    let path = Path::new("star.toml");
    let e = Scenario::parse(path, &star(ROBOT, both)).unwrap_err();
    assert!(e.problem.contains("duplicate"), "{e}");
    let path = Path::new("floor.toml");
    let e = FloorScenario::parse(path, &floor(ROBOT, both)).unwrap_err();
    assert!(e.problem.contains("duplicate"), "{e}");
    // A bad value under the other format's name is refused naming this format's key.
    let path = Path::new("star.toml");
    let e = Scenario::parse(path, &star(ROBOT, "[sim]\narrival = -1.0"))
        .and_then(|s| s.prepare(path))
        .unwrap_err();
    assert_eq!(e.field, "sim.goal_tolerance", "{e}");
    let path = Path::new("floor.toml");
    let e = FloorScenario::parse(path, &floor(ROBOT, "[sim]\ngoal_tolerance = -1.0"))
        .and_then(|s| s.prepare(path))
        .unwrap_err();
    assert_eq!(e.field, "sim.arrival", "{e}");
}

/// `[field] k` and `[controller] damping`/`speed` are read alike in both formats: the same
/// table, key and names; a floor plan's `[controller]` refuses the keys it keeps under
/// `[robot]` (gain, `μ`, `v_max`), by name.
#[test]
fn both_formats_read_k_damping_and_speed_under_the_same_keys() {
    use harmonav::{DampingPolicy, KPolicy, SpeedPolicy};
    let rest = "[field]\nk = \"paper\"\n[controller]\ndamping = \"shaped\"\nspeed = \"paper\"";
    let path = Path::new("star.toml");
    let s = Scenario::parse(path, &star(ROBOT, rest)).unwrap();
    assert_eq!(
        (s.field.k, s.controller.damping, s.controller.speed),
        (KPolicy::Paper, DampingPolicy::Shaped, SpeedPolicy::Paper)
    );
    let path = Path::new("floor.toml");
    let f = FloorScenario::parse(path, &floor(ROBOT, rest)).unwrap();
    assert_eq!(
        (f.field.k, f.controller.damping, f.controller.speed),
        (KPolicy::Paper, DampingPolicy::Shaped, SpeedPolicy::Paper)
    );
    // Absent: the defaults, the star world's.
    let f = FloorScenario::parse(path, &floor(ROBOT, "")).unwrap();
    assert_eq!(
        (f.field.k, f.controller.damping, f.controller.speed),
        Default::default()
    );
    for (text, key) in [
        ("[controller]\ngain = 2.0", "gain"),
        ("[controller]\ndamping = \"critical\"", "critical"),
        ("[field]\nk = \"n+1\"", "n+1"),
    ] {
        let e = FloorScenario::parse(path, &floor(ROBOT, text)).unwrap_err();
        assert!(e.to_string().contains(key), "{text}: {e}");
    }
}

/// `FloorPrepared::random_starts` draws by the file's `[starts]` rule: the same count and seed
/// give the file's own seeded starts, bit for bit, and another seed other starts, each a valid
/// `robot.start`.
#[test]
fn random_starts_are_the_files_starts_rule() {
    let path = Path::new("floor.toml");
    let text = floor(ROBOT, "[starts]\ncount = 5\nseed = 9");
    let p = FloorScenario::parse(path, &text)
        .and_then(|s| s.prepare(path))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(p.starts.len(), 6);
    assert_eq!(p.random_starts(5, 9).unwrap(), p.starts[1..].to_vec());
    let other = p.random_starts(5, 10).unwrap();
    assert_ne!(other, p.starts[1..].to_vec());
    for s in other {
        p.check_start(s).unwrap_or_else(|e| panic!("{s:?}: {e}"));
    }
}

/// `[robot] force_bound` (issue 54, the braking certificate) is read alike in both formats,
/// round-trips in a star world, and a bad value is refused naming the key and the file.
#[test]
fn both_formats_read_the_force_bound_and_refuse_a_bad_one() {
    let with = format!("{ROBOT}\nforce_bound = 2.5");
    let path = Path::new("star.toml");
    let parsed = Scenario::parse(path, &star(&with, "")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(parsed.controller.force_bound, Some(2.5));
    let text = toml::to_string(&parsed).unwrap();
    assert!(text.contains("force_bound = 2.5"), "{text}");
    assert_eq!(Scenario::parse(path, &text).unwrap(), parsed);
    let path = Path::new("floor.toml");
    let floor_plan =
        FloorScenario::parse(path, &floor(&with, "")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(floor_plan.robot.force_bound, Some(2.5));
    for value in ["0.0", "-1.0", "nan", "inf"] {
        let robot = format!("{ROBOT}\nforce_bound = {value}");
        let path = Path::new("star-bad.toml");
        let e = Scenario::parse(path, &star(&robot, ""))
            .and_then(|s| s.prepare(path))
            .unwrap_err();
        assert_eq!(e.field, "robot.force_bound", "{value}: {e}");
        assert!(e.to_string().starts_with("star-bad.toml"), "{e}");
        let path = Path::new("floor-bad.toml");
        let e = FloorScenario::parse(path, &floor(&robot, ""))
            .and_then(|s| s.prepare(path))
            .unwrap_err();
        assert_eq!(e.field, "robot.force_bound", "{value}: {e}");
        assert!(e.to_string().starts_with("floor-bad.toml"), "{e}");
    }
}

/// `[robot] comfort` (docs/movers.md §7) is read alike in both formats, round-trips in a star
/// world (left out at its default 0), and a bad value is refused naming the key and the file.
#[test]
fn both_formats_read_the_comfort_and_refuse_a_bad_one() {
    let with = format!("{ROBOT}\ncomfort = 0.3");
    let path = Path::new("star.toml");
    let parsed = Scenario::parse(path, &star(&with, "")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(parsed.controller.comfort, 0.3);
    let text = toml::to_string(&parsed).unwrap();
    assert!(text.contains("comfort = 0.3"), "{text}");
    assert_eq!(Scenario::parse(path, &text).unwrap(), parsed);
    let plain = Scenario::parse(path, &star(ROBOT, "")).unwrap();
    assert_eq!(plain.controller.comfort, 0.0);
    assert!(!toml::to_string(&plain).unwrap().contains("comfort"));
    let path = Path::new("floor.toml");
    let floor_plan =
        FloorScenario::parse(path, &floor(&with, "")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(floor_plan.robot.comfort, 0.3);
    for value in ["-0.1", "nan", "inf"] {
        let robot = format!("{ROBOT}\ncomfort = {value}");
        let path = Path::new("star-bad.toml");
        let e = Scenario::parse(path, &star(&robot, ""))
            .and_then(|s| s.prepare(path))
            .unwrap_err();
        assert_eq!(e.field, "robot.comfort", "{value}: {e}");
        assert!(e.to_string().starts_with("star-bad.toml"), "{e}");
        let path = Path::new("floor-bad.toml");
        let e = FloorScenario::parse(path, &floor(&robot, ""))
            .and_then(|s| s.prepare(path))
            .unwrap_err();
        assert_eq!(e.field, "robot.comfort", "{value}: {e}");
        assert!(e.to_string().starts_with("floor-bad.toml"), "{e}");
    }
}
