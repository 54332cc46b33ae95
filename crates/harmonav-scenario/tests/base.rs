//! `[robot] base`, `omega_max` and `yaw` (issue 53, item 4): a differential-drive base read
//! and refused by key, and a file without them read as before.

use std::path::Path;

use harmonav::Base;
use harmonav_scenario::{BaseKind, Prepared, Scenario, ScenarioError};

/// A star world: a disc of radius 5 around one rock, with `robot` after the `[robot]` keys
/// below and `rest` after the table.
fn star(robot: &str, rest: &str) -> String {
    format!(
        "name = \"star\"\n[workspace]\ntype = \"circle\"\ncenter = [0.0, 0.0]\nradius = 5.0\n\
         [[obstacles]]\ntype = \"circle\"\ncenter = [0.0, 0.0]\nradius = 1.0\n[robot]\n\
         model = \"kinematic\"\nstart = [-3.0, 0.2]\ngoal = [3.0, 0.0]\n{robot}\n{rest}"
    )
}

fn load(text: &str) -> Result<Prepared, ScenarioError> {
    let path = Path::new("star.toml");
    Scenario::parse(path, text).and_then(|s| s.prepare(path))
}

const DIFF: &str = "base = \"diff\"\nomega_max = 2.0\nyaw = 3.0";
const V_MAX: &str = "[controller]\nv_max = 0.5";

#[test]
fn a_diff_base_is_read_with_its_bounds_and_yaw() {
    let p = load(&star(DIFF, V_MAX)).unwrap();
    assert_eq!(p.scenario.controller.base, BaseKind::Diff);
    assert_eq!(p.base(), Some(Base::diff(0.5, 2.0)));
    assert_eq!(p.start_yaw(), 3.0);
    // The yaw defaults to 0.
    let p = load(&star("base = \"diff\"\nomega_max = 2.0", V_MAX)).unwrap();
    assert_eq!(p.start_yaw(), 0.0);
    // It round-trips through TOML, and a holonomic file writes none of the keys.
    let text = toml::to_string(&load(&star(DIFF, V_MAX)).unwrap().scenario).unwrap();
    assert!(
        text.contains("base = \"diff\"") && text.contains("omega_max"),
        "{text}"
    );
    assert_eq!(load(&text).unwrap().base(), Some(Base::diff(0.5, 2.0)));
    let plain = toml::to_string(&load(&star("", "")).unwrap().scenario).unwrap();
    assert!(!plain.contains("base") && !plain.contains("omega_max") && !plain.contains("yaw"));
}

#[test]
fn without_a_base_the_robot_is_holonomic_as_before() {
    let p = load(&star("", "")).unwrap();
    assert_eq!(p.scenario.controller.base, BaseKind::Holonomic);
    assert_eq!(p.base(), None);
    assert_eq!(
        load(&star("base = \"holonomic\"", "")).unwrap().base(),
        None
    );
}

/// Every refusal names its key.
#[test]
fn bad_values_are_refused_by_key() {
    let refused = |robot: &str, rest: &str, field: &str, says: &str| {
        let e = load(&star(robot, rest)).unwrap_err();
        assert!(
            e.to_string().contains(field) && e.problem.contains(says),
            "{robot} / {rest}: {e}"
        );
    };
    refused("base = \"tank\"", "", "base", "unknown base `tank`");
    for bad in ["nan", "inf", "-1.0", "0.0"] {
        let robot = format!("base = \"diff\"\nomega_max = {bad}");
        refused(&robot, V_MAX, "robot.omega_max", "must be finite");
        let rest = format!("[controller]\nv_max = {bad}");
        refused(
            "base = \"diff\"\nomega_max = 2.0",
            &rest,
            "controller.v_max",
            "",
        );
    }
    refused(
        "base = \"diff\"\nomega_max = 2.0\nyaw = nan",
        V_MAX,
        "robot.yaw",
        "finite",
    );
    refused(
        "base = \"diff\"",
        V_MAX,
        "robot.omega_max",
        "needs its top turn rate",
    );
    refused(
        "base = \"diff\"\nomega_max = 2.0",
        "",
        "controller.v_max",
        "top forward speed",
    );
    refused(
        "omega_max = 2.0",
        "",
        "robot.omega_max",
        "only a differential-drive base",
    );
    refused(
        "yaw = 1.0",
        "",
        "robot.yaw",
        "only a differential-drive base",
    );
    // The dynamic law: the navigator refuses it, the file says so by key.
    let dynamic = star(DIFF, V_MAX).replace("model = \"kinematic\"", "model = \"dynamic\"");
    let e = load(&dynamic).unwrap_err();
    assert!(
        e.field == "robot.base" && e.problem.contains("kinematic law only"),
        "{e}"
    );
    // `[[robots]]`: a start heading only on a differential drive, and finite.
    let robots = "[[robots]]\nstart = [3.0, 0.2]\ngoal = [-3.0, 0.0]\nyaw = 1.0";
    refused(
        "",
        robots,
        "robots[0].yaw",
        "only a differential-drive base",
    );
    let robots = format!("{V_MAX}\n[[robots]]\nstart = [3.0, 0.2]\ngoal = [-3.0, 0.0]\nyaw = nan");
    refused(DIFF, &robots, "robots[0].yaw", "finite");
}

/// A differential drive takes movers and other robots (docs/movers.md §8), each robot with
/// its own start heading or `[robot]`'s.
#[test]
fn a_diff_base_takes_movers_and_robots() {
    let movers = format!(
        "{V_MAX}\n[[movers]]\nradius = 0.25\nspeed_bound = 0.8\nstart = [0.0, -3.0]\n\
         velocity = [0.0, 0.5]"
    );
    let p = load(&star(DIFF, &movers)).unwrap();
    assert_eq!(p.base(), Some(Base::diff(0.5, 2.0)));
    assert_eq!(p.scenario.sim.movers.len(), 1);
    let robots = format!(
        "{V_MAX}\n[[robots]]\nstart = [3.0, 0.2]\ngoal = [-3.0, 0.0]\nyaw = 1.5\n\
         [[robots]]\nstart = [0.0, 3.0]\ngoal = [0.0, -3.0]"
    );
    let p = load(&star(DIFF, &robots)).unwrap();
    let yaws: Vec<Option<f64>> = p.scenario.sim.robots.iter().map(|r| r.yaw).collect();
    assert_eq!(yaws, [Some(1.5), None]);
    // Written back with its yaw, and read again.
    let text = toml::to_string(&p.scenario).unwrap();
    assert_eq!(
        load(&text).unwrap().scenario.sim.robots,
        p.scenario.sim.robots
    );
}

/// A floor plan: a 4 × 3 m room, with `robot` after the `[robot]` keys below and `rest` after
/// the table.
fn floor(robot: &str, rest: &str) -> String {
    format!(
        "name = \"room\"\n[floor_plan]\nouter = [[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]]\n\
         max_element = 0.1\n[robot]\nmodel = \"kinematic\"\nstart = [0.8, 0.8]\n\
         goal = [3.2, 2.2]\nradius = 0.1\nmargin = 0.05\n{robot}\n{rest}"
    )
}

fn load_floor(text: &str) -> Result<harmonav_scenario::floorplan::FloorPrepared, ScenarioError> {
    let path = Path::new("room.toml");
    harmonav_scenario::floorplan::FloorScenario::parse(path, text).and_then(|s| s.prepare(path))
}

/// A floor plan takes the same keys (its top speed is its own `[robot] v_max`), refused by the
/// same rules, by key; without them the robot is holonomic as before.
#[test]
fn a_floor_plan_takes_the_same_base_keys() {
    let p = load_floor(&floor(&format!("{DIFF}\nv_max = 0.5"), "")).unwrap();
    assert_eq!(p.base(), Some(Base::diff(0.5, 2.0)));
    assert_eq!(p.start_yaw(), 3.0);
    let p = load_floor(&floor("", "")).unwrap();
    assert_eq!((p.base(), p.start_yaw()), (None, 0.0));
    let cases = [
        (DIFF.to_string(), "robot.v_max"),
        ("omega_max = 2.0".to_string(), "robot.omega_max"),
        ("yaw = 1.0".to_string(), "robot.yaw"),
        (
            "base = \"diff\"\nv_max = 0.5".to_string(),
            "robot.omega_max",
        ),
        (format!("{DIFF}\nv_max = 0.5\nomega_max_ = 1"), "omega_max_"),
        (
            "base = \"diff\"\nomega_max = -1.0\nv_max = 0.5".to_string(),
            "robot.omega_max",
        ),
        ("base = \"unicycle\"".to_string(), "robot.base"),
    ];
    for (keys, field) in cases {
        let e = load_floor(&floor(&keys, "")).unwrap_err();
        assert!(
            e.field == field || e.to_string().contains(field),
            "{keys}: {e}"
        );
    }
    let dynamic = floor(&format!("{DIFF}\nv_max = 0.5"), "").replace("kinematic", "dynamic");
    assert_eq!(load_floor(&dynamic).unwrap_err().field, "robot.base");
}

/// `[robot] a_max` and `alpha_max`: a differential drive's acceleration limits, both or
/// neither, in either format; refused by name on a holonomic robot.
#[test]
fn acceleration_limits_are_read_and_checked_by_name() {
    let text = |keys: &str| star(keys, V_MAX);
    let diff = "base = \"diff\"\nomega_max = 2.0";
    let p = load(&text(&format!("{diff}\na_max = 0.4\nalpha_max = 3.0"))).unwrap();
    assert_eq!(p.base(), Some(Base::diff(0.5, 2.0).with_accel(0.4, 3.0)));
    for (keys, field) in [
        (format!("{diff}\na_max = 0.4"), "robot.alpha_max"),
        (format!("{diff}\nalpha_max = 3.0"), "robot.a_max"),
        (
            format!("{diff}\na_max = -0.4\nalpha_max = 3.0"),
            "robot.a_max",
        ),
        ("a_max = 0.4\nalpha_max = 3.0".to_string(), "robot.a_max"),
    ] {
        let e = load(&text(&keys)).unwrap_err();
        assert!(e.to_string().contains(field), "{keys}: {e}");
    }
}
