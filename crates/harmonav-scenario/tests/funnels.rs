//! `[floor_plan] funnels` (docs/maths.md §13.10): the chain is built at load for the kinematic
//! law, and refused by key for the dynamic law and for `[[robots]]`.

use std::path::Path;

use harmonav_scenario::ScenarioError;
use harmonav_scenario::floorplan::{FloorPrepared, FloorScenario};

/// A 4 × 3 m room with `model` and `rest` after the table.
fn floor(model: &str, rest: &str) -> String {
    format!(
        "name = \"room\"\n[floor_plan]\nouter = [[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]]\n\
         max_element = 0.1\nfunnels = true\n[robot]\nmodel = \"{model}\"\nstart = [0.8, 0.8]\n\
         goal = [3.2, 2.2]\nradius = 0.1\nmargin = 0.05\n{rest}"
    )
}

fn load(text: &str) -> Result<FloorPrepared, ScenarioError> {
    let path = Path::new("room.toml");
    FloorScenario::parse(path, text).and_then(|s| s.prepare(path))
}

#[test]
fn a_chain_is_built_for_the_kinematic_law_and_refused_by_key_otherwise() {
    // A convex room: the goal's own funnel holds all of it (the slide has no rest point).
    let p = load(&floor("kinematic", "")).unwrap();
    let chain = p.funnels.expect("a chain");
    assert_eq!(chain.funnels.len(), 1);
    assert!(chain.fraction() > 0.99, "{}", chain.fraction());
    assert_eq!(chain.entry(p.starts[0]), Some(0));
    // Without the key, none.
    let p = load(&floor("kinematic", "").replace("funnels = true\n", "")).unwrap();
    assert!(p.funnels.is_none());
    let e = load(&floor("dynamic", "")).unwrap_err();
    assert_eq!(e.field, "floor_plan.funnels", "{e}");
    assert!(
        e.to_string()
            .contains("certify the kinematic law; robot.model is \"dynamic\""),
        "{e}"
    );
    let robots = "[[robots]]\nstart = [0.8, 2.2]\ngoal = [3.2, 0.8]\n";
    let e = load(&floor("kinematic", robots)).unwrap_err();
    assert_eq!(e.field, "floor_plan.funnels", "{e}");
}
