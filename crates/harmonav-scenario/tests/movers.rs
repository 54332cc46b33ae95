//! `[[movers]]` in a star-world file (issue 54, item 4): every bad value is refused naming the
//! file and the key (`movers[1].speed_bound`), and a file without movers reads as before.

use std::path::Path;

use harmonav_scenario::{MoverKindSpec, Scenario};

const WORLD: &str = r#"
name = "crossing"
[workspace]
type = "circle"
center = [0.0, 0.0]
radius = 6.0
[robot]
model = "kinematic"
start = [-4.0, 0.1]
goal = [4.0, 0.0]
radius = 0.2
"#;

const GOOD: &str = r#"
[[movers]]
radius = 0.25
speed_bound = 0.8
start = [0.0, -3.0]
velocity = [0.0, 0.5]
"#;

fn load(movers: &str) -> Result<harmonav_scenario::Prepared, String> {
    let path = Path::new("m.toml");
    Scenario::parse(path, &format!("{WORLD}{GOOD}{movers}"))
        .and_then(|s| s.prepare(path))
        .map_err(|e| e.to_string())
}

/// The error of a second mover `body`, which must name `field`.
fn refused(body: &str, field: &str) {
    let e = load(&format!("[[movers]]\n{body}")).unwrap_err();
    assert!(
        e.starts_with("m.toml") && e.contains(&format!("`{field}`")),
        "{body}: {e}"
    );
}

#[test]
fn good_movers_read_with_their_defaults() {
    let p = load(
        "[[movers]]\nradius = 0.2\nspeed_bound = 1.0\nerror = 0.05\nkind = \"reciprocal\"\n\
         start = [2.0, 2.0]\nwaypoints = [[2.0, -2.0], [-2.0, 2.0]]\n\
         [[movers]]\nradius = 0.2\nspeed_bound = 1.0\nstart = [3.0, 3.0]\n\
         random_walk = { seed = 7 }\n",
    )
    .unwrap();
    let m = &p.scenario.sim.movers;
    assert_eq!(m.len(), 3);
    assert_eq!(
        (m[0].error, m[0].kind, m[0].share()),
        (0.0, MoverKindSpec::Noncooperative, None)
    );
    assert_eq!(
        (m[1].kind, m[1].share()),
        (MoverKindSpec::Reciprocal, Some(0.5))
    );
    assert_eq!(m[2].random_walk.as_ref().unwrap().turn_every, 1.0);
}

#[test]
fn bad_movers_are_refused_by_name() {
    let base = "radius = 0.2\nspeed_bound = 1.0\nstart = [2.0, 2.0]\n";
    let with = |extra: &str| format!("{base}{extra}");
    refused(&with("velocity = [2.0, 0.0]\n"), "movers[1].velocity");
    refused(
        &with("velocity = [0.5, 0.0]\nerror = -1.0\n"),
        "movers[1].error",
    );
    refused(
        &with("velocity = [0.5, 0.0]\nshare = 0.3\n"),
        "movers[1].share",
    );
    refused(
        &with("velocity = [0.5, 0.0]\nkind = \"reciprocal\"\nshare = 1.5\n"),
        "movers[1].share",
    );
    refused(
        &with("velocity = [0.5, 0.0]\nkind = \"friendly\"\n"),
        "movers[1].kind",
    );
    refused(&with(""), "movers[1]");
    refused(
        &with("velocity = [0.5, 0.0]\nwaypoints = [[0.0, 0.0]]\n"),
        "movers[1]",
    );
    refused(&with("waypoints = []\n"), "movers[1].waypoints");
    refused(
        &with("random_walk = { seed = 1, turn_every = 0.0 }\n"),
        "movers[1].random_walk.turn_every",
    );
    refused(
        &with("random_walk = { seed = 1, speed = 3.0 }\n"),
        "movers[1].random_walk.speed",
    );
    refused(
        &with("velocity = [0.5, 0.0]\nreport_seed = 3\n"),
        "movers[1].report_seed",
    );
    refused(&with("velocity = [0.5, 0.0]\nwings = 2\n"), "movers[1]");
    refused(
        "radius = 0.2\nspeed_bound = -1.0\nstart = [2.0, 2.0]\nvelocity = [0.0, 0.0]\n",
        "movers[1].speed_bound",
    );
    refused(
        "radius = nan\nspeed_bound = 1.0\nstart = [2.0, 2.0]\nvelocity = [0.0, 0.0]\n",
        "movers[1].radius",
    );
    refused(
        "radius = 0.2\nspeed_bound = \"fast\"\nstart = [2.0, 2.0]\nvelocity = [0.0, 0.0]\n",
        "movers[1].speed_bound",
    );
    // A mover on the robot at its start.
    refused(
        "radius = 0.2\nspeed_bound = 1.0\nstart = [-3.7, 0.1]\nvelocity = [0.0, 0.0]\n",
        "movers[1].start",
    );
}

#[test]
fn a_file_without_movers_writes_back_as_before() {
    let path = Path::new("m.toml");
    let s = Scenario::parse(path, WORLD).unwrap();
    assert!(s.sim.movers.is_empty());
    let text = toml::to_string(&s).unwrap();
    assert!(!text.contains("movers"), "{text}");
    let with = Scenario::parse(path, &format!("{WORLD}{GOOD}")).unwrap();
    let again = Scenario::parse(path, &toml::to_string(&with).unwrap()).unwrap();
    assert_eq!(again, with);
}

#[test]
fn a_floor_plan_refuses_a_bad_mover_by_name() {
    let plan = r#"
name = "corridor"
[floor_plan]
outer = [[0.0, 0.0], [6.0, 0.0], [6.0, 2.0], [0.0, 2.0]]
max_element = 0.2
[robot]
model = "kinematic"
start = [0.5, 1.0]
goal = [5.5, 1.0]
radius = 0.1
[[movers]]
radius = 0.2
speed_bound = 0.5
start = [5.0, 1.0]
velocity = [-0.5, 0.0]
[[movers]]
radius = 0.2
speed_bound = 0.5
start = [3.0, 1.0]
velocity = [-0.9, 0.0]
"#;
    let path = Path::new("f.toml");
    let e = harmonav_scenario::floorplan::FloorScenario::parse(path, plan)
        .and_then(|s| s.prepare(path))
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("f.toml") && e.contains("`movers[1].velocity`"),
        "{e}"
    );
}

#[test]
fn bad_robots_are_refused_by_name() {
    let path = Path::new("m.toml");
    let with = |robots: &str| {
        Scenario::parse(path, &format!("{WORLD}{robots}"))
            .and_then(|s| s.prepare(path))
            .map(|p| p.scenario.sim.robots.len())
            .map_err(|e| e.to_string())
    };
    assert_eq!(
        with("[[robots]]\nstart = [4.0, 0.5]\ngoal = [-4.0, 0.5]\n"),
        Ok(1)
    );
    for (robots, field) in [
        (
            "[[robots]]\nstart = [-3.9, 0.1]\ngoal = [3.0, 0.0]\n",
            "robots[0].start",
        ),
        (
            "[[robots]]\nstart = [4.0, 0.5]\ngoal = [5.95, 0.0]\n",
            "robots[0].goal",
        ),
        ("[[robots]]\nstart = [4.0, 0.5]\n", "robots[0]"),
        (
            "[[robots]]\nstart = [4.0, 0.5]\ngoal = [1.0, 1.0]\n[[robots]]\nstart = [4.0, nan]\ngoal = [1.0, 2.0]\n",
            "robots[1].start",
        ),
    ] {
        let e = with(robots).unwrap_err();
        assert!(e.contains(&format!("`{field}`")), "{robots}: {e}");
    }
}

/// A floor plan takes `[[robots]]` with the star world's keys and checks (one `check_fleet`
/// for both formats), each start and goal placed as `robot.start` is (in the certified
/// region, clear of the grown obstacles); `[starts]` and `require_certified_start` ask one
/// robot's questions and are refused with robots.
#[test]
fn a_floor_plan_takes_robots_with_the_star_worlds_keys() {
    const PLAN: &str = r#"
name = "corridor"
[floor_plan]
outer = [[0.0, 0.0], [6.0, 0.0], [6.0, 2.0], [0.0, 2.0]]
max_element = 0.2
[robot]
model = "kinematic"
start = [0.5, 1.0]
goal = [5.5, 1.0]
radius = 0.1
margin = 0.05
[[obstacles]]
type = "circle"
center = [3.0, 1.0]
radius = 0.2
"#;
    let path = Path::new("f.toml");
    let load = |text: &str| {
        harmonav_scenario::floorplan::FloorScenario::parse(path, text)
            .and_then(|s| s.prepare(path))
            .map(|p| (p.scenario.robots.len(), p.starts.len()))
            .map_err(|e| e.to_string())
    };
    let with = |rest: &str| load(&format!("{PLAN}{rest}"));
    let good = "[[robots]]\nstart = [5.5, 1.0]\ngoal = [0.5, 1.0]\n";
    assert_eq!(with(good), Ok((1, 1)));
    for (rest, field, says) in [
        (
            "[[robots]]\nstart = [0.6, 1.0]\ngoal = [5.0, 0.5]\n",
            "robots[0].start",
            "overlaps the one at robot.start",
        ),
        (
            "[[robots]]\nstart = [5.5, 1.0]\ngoal = [5.95, 1.0]\n",
            "robots[0].goal",
            "certified region",
        ),
        (
            "[[robots]]\nstart = [3.0, 1.3]\ngoal = [0.5, 0.5]\n",
            "robots[0].start",
            "obstacles[0]",
        ),
        ("[[robots]]\nstart = [5.5, 1.0]\n", "robots[0]", "goal"),
        (
            "[[robots]]\nstart = [5.5, 1.0]\ngoal = [1.0, 1.0]\n[[robots]]\nstart = [4.0, nan]\ngoal = [1.0, 1.5]\n",
            "robots[1].start",
            "NaN",
        ),
        (
            "[[robots]]\nstart = [5.5, 1.0]\ngoal = [1.0, 1.0]\nyaw = 1.0\n",
            "robots[0].yaw",
            "only a differential-drive base",
        ),
        (
            "[[movers]]\nradius = 0.2\nspeed_bound = 0.5\nstart = [5.2, 1.0]\nvelocity = [0.0, 0.1]\n\
             [[robots]]\nstart = [5.5, 1.0]\ngoal = [0.5, 1.5]\n",
            "movers[0].start",
            "(robots[0])",
        ),
        (
            "[starts]\ncount = 2\n[[robots]]\nstart = [5.5, 1.0]\ngoal = [0.5, 1.5]\n",
            "starts",
            "[[robots]]",
        ),
    ] {
        let e = with(rest).unwrap_err();
        assert!(
            e.starts_with("f.toml") && e.contains(&format!("`{field}`")) && e.contains(says),
            "{rest}: {e}"
        );
    }
    let certified = format!("{PLAN}{good}").replace(
        "max_element = 0.2\n",
        "max_element = 0.2\nrequire_certified_start = true\n",
    );
    let e = load(&certified).unwrap_err();
    assert!(e.contains("`floor_plan.require_certified_start`"), "{e}");
}
