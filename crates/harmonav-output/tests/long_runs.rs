//! Runs of any length: every state is judged and streamed, the kept trajectory stays bounded
//! and evenly spaced, and a recording streamed during the run equals one written after it.

use std::collections::BTreeMap;
use std::path::Path;

use harmonav_output::set::{Outputs, write_outputs};
use harmonav_scenario::{Prepared, Scenario};
use harmonav_sim::physics::{Physics, simulate, simulate_observed};
use harmonav_sim::run::run_observed;
use harmonav_sim::trace::{Event, Sample};
use harmonav_sim::trajectory::MAX_KEPT_STATES;
use nalgebra::Vector2;

fn parse(text: &str) -> Prepared {
    let path = Path::new("long.toml");
    Scenario::parse(path, text).unwrap().prepare(path).unwrap()
}

#[test]
fn a_run_longer_than_the_kept_states_is_judged_on_every_state() {
    // An empty disc crossed in about 1.3 s at a recording interval of 3 µs: some 4·10⁵ states,
    // three times what a run keeps.
    let prepared = parse(
        r#"
        name = "long"
        [workspace]
        type = "circle"
        center = [0.0, 0.0]
        radius = 1.0
        [robot]
        model = "kinematic"
        start = [-0.8, 0.0]
        goal = [0.8, 0.0]
        [sim]
        dt = 3e-6
        max_time = 20.0
        goal_tolerance = 0.01
        "#,
    );
    let mut streamed: Vec<[f64; 3]> = Vec::new();
    let run = run_observed(&prepared, None, &mut |e| {
        if let Event::State(s) = e {
            streamed.push([s.t, s.x[0], s.x[1]]);
        }
    })
    .unwrap();
    let s = &run.summary;
    assert!(s.reached && s.all_passed(), "{:?}", s.outcome);
    assert_eq!(streamed.len(), s.recorded_states);
    assert!(
        s.recorded_states > 2 * MAX_KEPT_STATES,
        "{} states: the test needs a run longer than the kept states",
        s.recorded_states
    );
    // The kept states: within the capacity (plus the start and the end, pinned), more than
    // half of it, and every grid state at one stride, a power of two of sim.dt.
    let kept = &run.samples;
    assert!(
        kept.len() <= MAX_KEPT_STATES + 2 && kept.len() > MAX_KEPT_STATES / 2,
        "{}",
        kept.len()
    );
    let gaps: Vec<f64> = kept[1..kept.len() - 1]
        .windows(2)
        .map(|w| w[1].t - w[0].t)
        .collect();
    let stride = gaps[0] / 3e-6;
    assert!((stride.round() - stride).abs() < 1e-3 && (stride.round() as usize).is_power_of_two());
    assert!(
        gaps.iter().all(|g| (g - gaps[0]).abs() < 1e-9),
        "even spacing"
    );
    assert_eq!(kept.first().unwrap().t, 0.0);
    assert_eq!(kept.last().unwrap().t, s.time_s);
    // The path length is that of every state, not of the kept ones.
    let length: f64 = streamed
        .windows(2)
        .map(|w| (Vector2::new(w[1][1], w[1][2]) - Vector2::new(w[0][1], w[0][2])).norm())
        .sum();
    assert!(
        (length - s.path_length).abs() < 1e-9 * length,
        "{length} vs {}",
        s.path_length
    );
    let kept_length: f64 = kept
        .windows(2)
        .map(|w| (Vector2::from(w[1].x) - Vector2::from(w[0].x)).norm())
        .sum();
    assert!(kept_length <= s.path_length + 1e-12);
}

/// Messages per topic of a recording.
fn topics(path: &Path) -> BTreeMap<String, usize> {
    let bytes = std::fs::read(path).unwrap();
    let mut counts = BTreeMap::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        *counts.entry(m.unwrap().channel.topic.clone()).or_default() += 1;
    }
    counts
}

#[test]
fn a_recording_streamed_during_the_run_equals_one_written_after_it() {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shapes/dynamic-small.toml");
    let prepared = Scenario::load(&file).unwrap();
    let base = std::env::temp_dir().join(format!("harmonav-stream-{}", std::process::id()));
    let (live, after) = (base.join("live"), base.join("after"));
    let mut outputs = Outputs::begin(&live, &prepared).unwrap();
    let mut states: Vec<Sample> = Vec::new();
    let run = simulate_observed(&prepared, None, Physics::Builtin, &mut |e| {
        if let Event::State(s) = e {
            states.push(s.clone());
        }
        outputs.observe(e);
    })
    .unwrap();
    outputs.finish(&run).unwrap();
    // A short run keeps every state, so the replay after the run sees the same events.
    assert_eq!(states, run.samples);
    assert!(!run.summary.discoveries.is_empty());
    write_outputs(
        &after,
        &prepared,
        &simulate(&prepared, None, Physics::Builtin).unwrap(),
    )
    .unwrap();
    let (a, b) = (
        topics(&live.join("run.mcap")),
        topics(&after.join("run.mcap")),
    );
    assert_eq!(a, b);
    assert_eq!(a["/robot/pose"], run.summary.recorded_states);
    for name in ["summary.json", "trajectory.svg", "speed.svg", "energy.svg"] {
        assert!(live.join(name).exists(), "{name}");
    }
    let summary = |dir: &Path| std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert_eq!(summary(&live), summary(&after));
    std::fs::remove_dir_all(&base).unwrap();
}

#[test]
fn outputs_dropped_before_their_finish_leave_nothing() {
    // A run that fails (or is interrupted) drops its outputs unfinished: the staging folder
    // with its half-written recording goes with them.
    let prepared = parse(
        r#"
        name = "blocked"
        [workspace]
        type = "circle"
        center = [0.0, 0.0]
        radius = 5.0
        [robot]
        model = "kinematic"
        start = [-3.0, 0.0]
        goal = [3.0, 0.0]
        "#,
    );
    let dir = std::env::temp_dir().join(format!("harmonav-failed-{}", std::process::id()));
    {
        let outputs = Outputs::begin(&dir, &prepared).unwrap();
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "the staging folder"
        );
        drop(outputs);
    }
    // The output folder this set created went with it: a failed run leaves no empty folder.
    assert!(!dir.exists());
    // One that existed before stays, empty as it was.
    std::fs::create_dir_all(&dir).unwrap();
    drop(Outputs::begin(&dir, &prepared).unwrap());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    std::fs::remove_dir_all(&dir).unwrap();
}
