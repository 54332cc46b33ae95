//! Messages that name what is wrong (issue 56, D19): a key missing at the top level is named
//! as itself, not as the first table; a map_server YAML given as the scenario is said to be
//! one, in either loader.

use std::path::Path;

use harmonav_scenario::Scenario;
use harmonav_scenario::floorplan::FloorScenario;

const FLOOR: &str = "[floor_plan]\nouter = [[-5.0, -5.0], [5.0, -5.0], [5.0, 5.0], [-5.0, 5.0]]\n\
                     [robot]\nmodel = \"kinematic\"\nstart = [-3.0, 0.2]\ngoal = [3.0, 0.0]\n";

const STAR: &str = "[workspace]\ntype = \"circle\"\ncenter = [0.0, 0.0]\nradius = 5.0\n\
                    [robot]\nmodel = \"kinematic\"\nstart = [-3.0, 0.2]\ngoal = [3.0, 0.0]\n";

/// Without `name` both formats name `name` (before: "`floor_plan`: missing field `name`",
/// "`workspace`: …"), with no line; with it, both files load (the control).
#[test]
fn a_missing_top_level_key_is_named() {
    let path = Path::new("f.toml");
    let e = FloorScenario::parse(path, FLOOR).unwrap_err();
    assert_eq!((e.field.as_str(), e.line), ("name", None), "{e}");
    assert!(e.to_string().contains("top-level"), "{e}");
    let e = Scenario::parse(path, STAR).unwrap_err();
    assert_eq!((e.field.as_str(), e.line), ("name", None), "{e}");
    FloorScenario::parse(path, &format!("name = \"f\"\n{FLOOR}")).unwrap();
    Scenario::parse(path, &format!("name = \"s\"\n{STAR}")).unwrap();
    // A key missing inside a table still names the table.
    let e = FloorScenario::parse(
        path,
        &format!(
            "name = \"f\"\n{}",
            FLOOR.replace("model = \"kinematic\"\n", "")
        ),
    )
    .unwrap_err();
    assert_eq!(e.field, "robot", "{e}");
}

/// A map_server YAML given as the scenario is said to be one, with what to do (before: "key
/// with no value, expected `=`").
#[test]
fn a_map_yaml_is_not_a_scenario() {
    let yaml = "image: room.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n\
                occupied_thresh: 0.65\nfree_thresh: 0.196\n";
    let path = Path::new("room.yaml");
    for e in [
        FloorScenario::parse(path, yaml).unwrap_err(),
        Scenario::parse(path, yaml).unwrap_err(),
    ] {
        let text = e.to_string();
        assert!(
            text.contains("room.yaml") && text.contains("map_server YAML"),
            "{text}"
        );
        assert!(text.contains("[floor_plan] map"), "{text}");
    }
    // Other text that is not TOML keeps the parser's message.
    let e = Scenario::parse(path, "image = \nresolution: 1\n").unwrap_err();
    assert!(!e.to_string().contains("map_server"), "{e}");
}

/// An obstacle that cannot be grown by `radius + margin` is named as `obstacles[0]`, and the
/// problem is not blamed on `robot.radius` (issue 56, D19.10: "`robot.radius`: offsetting the
/// shape by 0.2 makes it lose its star shape").
#[test]
fn an_obstacle_that_cannot_grow_is_named() {
    let text = format!(
        "name = \"f09\"\n{FLOOR}radius = 0.1\nmargin = 0.1\n[[obstacles]]\ntype = \"star\"\n\
         center = [0.0, 0.0]\nradius = 0.3\nharmonics = [[1000, 0.01, 0.0]]\n"
    );
    let path = Path::new("f09.toml");
    let Err(e) = FloorScenario::parse(path, &text).unwrap().prepare(path) else {
        panic!("an obstacle that cannot be grown was taken");
    };
    let message = e.to_string();
    assert_eq!(e.field, "obstacles[0]", "{message}");
    assert!(message.contains("star shape"), "{message}");
    assert!(!message.contains("`robot.radius`"), "{message}");
}
