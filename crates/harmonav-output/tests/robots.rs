//! A `[[robots]]` file records and draws every robot's own trajectory (issue 54, item 4;
//! docs/movers.md §8): `/robots/<i>/pose`, `/robots/<i>/path`, `/robots/<i>/state` and `/tf`'s
//! `world → robot_<i>` in `run.mcap`, each robot's path, start, goal and body in
//! `trajectory.svg`, in a star world and on a floor plan.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use foxglove::messages::{FrameTransform, PoseInFrame};
use harmonav_output::floor::FloorOutputs;
use harmonav_output::record::write_mcap;
use harmonav_scenario::Scenario;
use harmonav_scenario::floorplan::FloorScenario;
use harmonav_sim::floor::FloorSummary;
use harmonav_sim::movers::FleetRobot;
use harmonav_sim::physics::{Physics, simulate, simulate_floor_observed};
use prost::Message;

fn file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/movers")
        .join(name)
}

/// Messages by topic.
type ByTopic = BTreeMap<String, Vec<Vec<u8>>>;

/// The messages of `bytes` by topic, and the `/tf` child frames with their counts.
fn topics(bytes: &[u8]) -> (ByTopic, BTreeMap<String, usize>) {
    let (mut by_topic, mut frames) = (BTreeMap::new(), BTreeMap::new());
    for m in mcap::MessageStream::new(bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == "/tf" {
            let tf = FrameTransform::decode(&m.data[..]).unwrap();
            *frames.entry(tf.child_frame_id).or_insert(0) += 1;
        }
        by_topic
            .entry(m.channel.topic.clone())
            .or_insert_with(Vec::new)
            .push(m.data.to_vec());
    }
    (by_topic, frames)
}

/// Every other robot has its own topics, one pose per recorded state ending where its run
/// ended, its path and its transforms.
fn check_recording(bytes: &[u8], others: &[FleetRobot]) {
    let (by_topic, frames) = topics(bytes);
    assert!(!others.is_empty());
    for (k, robot) in others.iter().enumerate() {
        let i = k + 1;
        let poses = &by_topic[&format!("/robots/{i}/pose")];
        assert!(poses.len() > 10, "robot {i}: {} poses", poses.len());
        assert_eq!(poses.len(), robot.samples.len());
        assert_eq!(by_topic[&format!("/robots/{i}/state")].len(), poses.len());
        assert!(!by_topic[&format!("/robots/{i}/path")].is_empty());
        assert_eq!(frames[&format!("robot_{i}")], poses.len());
        let last = PoseInFrame::decode(&poses[poses.len() - 1][..]).unwrap();
        let p = last.pose.unwrap().position.unwrap();
        let end = robot.samples.last().unwrap().x;
        assert!((p.x - end[0]).abs() < 1e-12 && (p.y - end[1]).abs() < 1e-12);
        // It arrived: its last state is at its goal, not at the first robot's.
        let to_goal = (end[0] - robot.goal[0]).hypot(end[1] - robot.goal[1]);
        assert!(robot.reached && to_goal < 0.06, "robot {i}: {to_goal}");
    }
    // The first robot's own topics are as before.
    assert!(by_topic.contains_key("/robot/pose") && by_topic.contains_key("/robot/path"));
    assert!(!by_topic.contains_key(&format!("/robots/{}/pose", others.len() + 1)));
}

/// Each other robot's path, start label and the key, drawn in its blue.
fn check_figure(svg: &str, others: &[FleetRobot]) {
    for k in 1..=others.len() {
        assert!(svg.contains(&format!("\nR{k}\n")), "label R{k}");
    }
    assert!(svg.contains("other robots"));
    assert!(svg.contains("#3273E6"), "the robots' blue");
}

#[test]
fn a_star_worlds_robots_are_each_recorded_and_drawn() {
    let prepared = Scenario::load(&file("four-robots-swap.toml")).unwrap();
    let run = simulate(&prepared, None, Physics::Builtin).unwrap();
    let fleet = run.summary.fleet.as_ref().unwrap();
    assert_eq!(fleet.others.len(), 3);
    let dir = std::env::temp_dir().join(format!("harmonav-robots-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.mcap");
    write_mcap(&path, &prepared, &run).unwrap();
    check_recording(&std::fs::read(&path).unwrap(), &fleet.others);
    let svg = harmonav_output::figures::trajectory_svg(&prepared, &run).unwrap();
    check_figure(&svg, &fleet.others);
    // The other robots are no longer drawn as movers: no "other robot" patch.
    assert!(!svg.contains("\nother robot\n"));
    // Not in summary.json.
    let json = serde_json::to_string(&run.summary).unwrap();
    assert!(!json.contains("samples"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_floor_plans_robots_are_each_recorded_and_drawn() {
    let prepared = FloorScenario::load(&file("floor-corridor-swap.toml")).unwrap();
    let start = nalgebra::Vector2::from(prepared.scenario.robot.start);
    let dir = std::env::temp_dir().join(format!("harmonav-floor-robots-{}", std::process::id()));
    let mut outputs = FloorOutputs::begin(&dir, &prepared).unwrap();
    let run = simulate_floor_observed(&prepared, None, start, Physics::Builtin, &mut |e| {
        outputs.observe(e);
    })
    .unwrap();
    let summary = FloorSummary::new(&prepared, None, start, &run);
    outputs.finish(&summary, &run).unwrap();
    let fleet = run.fleet.as_ref().unwrap();
    assert_eq!(fleet.others.len(), 3);
    check_recording(&std::fs::read(dir.join("run.mcap")).unwrap(), &fleet.others);
    let svg = std::fs::read_to_string(dir.join("trajectory.svg")).unwrap();
    check_figure(&svg, &fleet.others);
    let json = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(json.contains("\"fleet\"") && json.contains("no-collision-between-robots"));
    std::fs::remove_dir_all(&dir).unwrap();
}
