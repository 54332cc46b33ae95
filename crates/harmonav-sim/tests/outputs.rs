//! Outputs: the MCAP recording reads back with the mcap crate (schemas, channels, counts),
//! the files are written atomically and the figures contain what they should.

use std::collections::BTreeMap;
use std::path::Path;

use harmonav_sim::record::{SECTOR_PERIOD, TOPICS, TRAJECTORY_SPACING, mcap_bytes, write_outputs};
use harmonav_sim::run::run;
use harmonav_sim::scenario::{Model, Scenario};

#[test]
fn mcap_reads_back_with_the_expected_channels_and_counts() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shapes/mixed.toml");
    let prepared = Scenario::load(&file).unwrap();
    let r = run(&prepared, Some(Model::Kinematic)).unwrap();
    let bytes = mcap_bytes(&prepared, &r).unwrap();
    assert_eq!(
        bytes,
        mcap_bytes(&prepared, &r).unwrap(),
        "recording is deterministic"
    );
    let summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("summary section");
    let schemas: BTreeMap<String, String> = summary
        .channels
        .values()
        .map(|c| {
            (
                c.topic.clone(),
                c.schema
                    .as_ref()
                    .map(|s| s.name.clone())
                    .unwrap_or_default(),
            )
        })
        .collect();
    assert_eq!(schemas["/robot/pose"], "foxglove.PoseInFrame");
    assert_eq!(schemas["/robot/trajectory"], "foxglove.PosesInFrame");
    assert_eq!(schemas["/scene"], "foxglove.SceneUpdate");
    assert_eq!(schemas["/state"], "harmonav.State");
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut last_time = 0;
    let mut last_path: Vec<(f64, f64)> = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        assert!(m.log_time >= last_time, "messages in time order");
        last_time = m.log_time;
        let body: serde_json::Value = serde_json::from_slice(&m.data).unwrap();
        if m.channel.topic == "/state" {
            let theta = body["theta"].as_f64().unwrap();
            assert!((0.0..=1.0).contains(&theta));
        }
        if m.channel.topic == "/robot/trajectory" {
            last_path = body["poses"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| {
                    let q = &p["position"];
                    (q["x"].as_f64().unwrap(), q["y"].as_f64().unwrap())
                })
                .collect();
        }
        *counts.entry(m.channel.topic.clone()).or_default() += 1;
    }
    // The final path is thinned to TRAJECTORY_SPACING and ends at the last sample.
    let end = r.samples.last().unwrap().x;
    assert_eq!(last_path.last(), Some(&(end[0], end[1])));
    for w in last_path[..last_path.len() - 1].windows(2) {
        let gap = (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1);
        assert!(gap >= TRAJECTORY_SPACING, "{gap}");
    }
    assert!(last_path.len() > 100, "{} vertices", last_path.len());
    let n = r.samples.len();
    let d = r.summary.discoveries.len();
    assert_eq!(counts["/robot/pose"], n);
    assert_eq!(counts["/state"], n);
    assert_eq!(counts["/discoveries"], d);
    assert_eq!(counts["/robot/trajectory"], d + 1);
    assert_eq!(
        counts["/scene"],
        1 + d.min(
            r.summary
                .discoveries
                .iter()
                .filter(|x| x.time_s > 0.0)
                .count()
        )
    );
    // Drawn every SECTOR_PERIOD while moving (the robot moves from the first sample on).
    let periods = r.summary.time_s / SECTOR_PERIOD;
    let sectors = counts["/sensor/sector"] as f64;
    assert!(
        (periods - 1.0..=periods + 2.0).contains(&sectors),
        "{sectors} sectors in {periods} periods"
    );
    assert_eq!(counts.len(), TOPICS.len());
}

#[test]
fn outputs_are_written_and_figures_show_the_run() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shapes/mixed.toml");
    let prepared = Scenario::load(&file).unwrap();
    let dir = std::env::temp_dir().join(format!("harmonav-outputs-{}", std::process::id()));
    let r = run(&prepared, Some(Model::Kinematic)).unwrap();
    let files = write_outputs(&dir, &prepared, &r).unwrap();
    let names: Vec<_> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().to_string())
        .collect();
    assert_eq!(
        names,
        ["summary.json", "run.mcap", "trajectory.svg"],
        "no speed plot for a kinematic run"
    );
    let svg = std::fs::read_to_string(dir.join("trajectory.svg")).unwrap();
    for name in &prepared.truth.names {
        assert!(svg.contains(&format!(">{name}</text>")), "label {name}");
    }
    assert!(svg.contains("goal reached"));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["reached"], true);
    assert!(
        std::fs::read_dir(&dir).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .ends_with(".tmp"))
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
