//! A floor-plan run that follows a chain of certified funnels (`floor_plan.funnels`,
//! docs/maths.md §13.10, issue 52) shows the structure that certifies it: `trajectory.svg` draws
//! the funnels' goals, the links to their parents and the part of `W_δ` no funnel holds, and its
//! note gives the chain's certified fraction; `run.mcap`'s `/scene` has the entity `funnels`.
//! Without the key neither appears (the control).

use std::path::Path;

use foxglove::messages::SceneUpdate;
use harmonav_output::floor::FloorOutputs;
use harmonav_scenario::floorplan::{FloorPrepared, FloorScenario};
use harmonav_sim::floor::FloorSummary;
use harmonav_sim::physics::{Physics, simulate_floor_observed};
use prost::Message;

/// A 4 × 3 m room with a bar across it, the goal just behind the bar.
const ROOM: &str = r#"name = "small-bar"
[floor_plan]
outer = [[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]]
holes = [[[0.8, 1.3], [3.2, 1.3], [3.2, 1.7], [0.8, 1.7]]]
max_element = 0.1
funnels = true
[robot]
model = "kinematic"
start = [2.0, 0.7]
goal = [2.0, 2.1]
radius = 0.1
margin = 0.05
"#;

/// The run of `text` written to a fresh folder: `(prepared, trajectory.svg, /scene's updates)`.
fn outputs(text: &str, tag: &str) -> (FloorPrepared, String, Vec<SceneUpdate>) {
    let path = Path::new("small-bar.toml");
    let prepared = FloorScenario::parse(path, text)
        .and_then(|s| s.prepare(path))
        .unwrap();
    let start = nalgebra::Vector2::from(prepared.scenario.robot.start);
    let dir = std::env::temp_dir().join(format!("harmonav-funnels-{tag}-{}", std::process::id()));
    let mut out = FloorOutputs::begin(&dir, &prepared).unwrap();
    let run = simulate_floor_observed(&prepared, None, start, Physics::Builtin, &mut |e| {
        out.observe(e);
    })
    .unwrap();
    let summary = FloorSummary::new(&prepared, None, start, &run);
    assert!(summary.reached, "{summary:?}");
    out.finish(&summary, &run).unwrap();
    let svg = std::fs::read_to_string(dir.join("trajectory.svg")).unwrap();
    let bytes = std::fs::read(dir.join("run.mcap")).unwrap();
    let scenes = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(Result::unwrap)
        .filter(|m| m.channel.topic == "/scene")
        .map(|m| SceneUpdate::decode(&m.data[..]).unwrap())
        .collect();
    std::fs::remove_dir_all(&dir).unwrap();
    (prepared, svg, scenes)
}

#[test]
fn a_run_that_follows_funnels_draws_and_records_them() {
    let (prepared, svg, scenes) = outputs(ROOM, "on");
    let chain = prepared.funnels.as_deref().expect("a chain");
    let n = chain.funnels.len();
    assert!(n >= 2 && !chain.uncovered.is_empty(), "{n} funnels");
    let note = format!(
        "{n} funnels certify {:.1} % of the reachable area",
        100.0 * chain.fraction()
    );
    assert!(svg.contains(&note), "no note {note:?}");
    assert!(svg.contains("funnel goals") && svg.contains("not certified"));
    // The uncertified part in the light yellow of its key, at most one rectangle a sample (runs
    // of a row merged), at least one.
    let patches = svg.matches(r##"fill="#FAE68C""##).count();
    assert!(
        patches >= 2 && patches <= chain.uncovered.len() + 1,
        "{patches} patches for {} samples",
        chain.uncovered.len()
    );
    // The recording: one link a funnel but the root, one sphere a goal, at the goals.
    let funnels: Vec<_> = scenes
        .iter()
        .flat_map(|s| &s.entities)
        .filter(|e| e.id == "funnels")
        .collect();
    assert!(!funnels.is_empty());
    for e in funnels {
        assert_eq!(e.lines.len(), n - 1);
        assert_eq!(e.spheres.len(), n);
        for (s, f) in e.spheres.iter().zip(&chain.funnels) {
            let p = s.pose.as_ref().unwrap().position.as_ref().unwrap();
            assert_eq!([p.x, p.y], [f.goal.x, f.goal.y]);
        }
    }
}

#[test]
fn without_the_key_no_funnel_is_drawn_or_recorded() {
    let (prepared, svg, scenes) = outputs(&ROOM.replace("funnels = true\n", ""), "off");
    assert!(prepared.funnels.is_none());
    assert!(!svg.contains("funnel goals") && !svg.contains("funnels certify"));
    assert!(!svg.contains(r##"fill="#FAE68C""##));
    let ids = scenes
        .iter()
        .flat_map(|s| &s.entities)
        .map(|e| e.id.as_str());
    assert!(ids.clone().all(|id| id != "funnels"));
    assert!(ids.clone().any(|id| id == "walls"));
}
