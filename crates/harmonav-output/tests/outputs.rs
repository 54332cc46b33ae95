//! Outputs: the MCAP recording reads back with the mcap crate (schemas, channels, counts),
//! the files are written atomically and the figures contain what they should.

use std::collections::BTreeMap;
use std::path::Path;

use foxglove::messages::{FrameTransform, Grid, Log, PoseInFrame, SceneUpdate};
use harmonav_output::record::{
    GRID_CELLS, LIDAR_TOPICS, PATH_PERIOD, PATH_SPACING, TOPICS, write_mcap,
};
use harmonav_output::set::write_outputs;
use harmonav_scenario::{Model, Prepared, Scenario};
use harmonav_sim::run::run;
use prost::Message;

fn scenario(name: &str) -> Prepared {
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name);
    Scenario::load(&file).unwrap()
}

/// Decodes `data` as the message its schema names, with the foxglove crate's types; the
/// harmonav state through the schema's own descriptor (field names checked).
fn decode(schema: &mcap::Schema, data: &[u8]) -> Result<String, String> {
    let e = |e: prost::DecodeError| e.to_string();
    Ok(match schema.name.as_str() {
        "foxglove.SceneUpdate" => format!(
            "{} entities",
            SceneUpdate::decode(data).map_err(e)?.entities.len()
        ),
        "foxglove.Grid" => {
            let g = Grid::decode(data).map_err(e)?;
            format!(
                "grid {}x{}",
                g.column_count,
                g.data.len() / g.row_stride as usize
            )
        }
        "foxglove.PoseInFrame" => {
            format!("{:?}", PoseInFrame::decode(data).map_err(e)?.pose.is_some())
        }
        "foxglove.FrameTransform" => FrameTransform::decode(data).map_err(e)?.child_frame_id,
        "foxglove.Log" => Log::decode(data).map_err(e)?.message,
        name if name.ends_with("State") => format!("{} bytes", data.len()),
        other => return Err(format!("unexpected schema {other}")),
    })
}

#[test]
fn every_message_decodes_with_the_schema_the_file_carries() {
    let prepared = scenario("shapes/dynamic-small.toml");
    let r = run(&prepared, None).unwrap();
    let dir = std::env::temp_dir().join(format!("harmonav-mcap-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.mcap");
    write_mcap(&path, &prepared, &r).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut last_time = 0;
    let mut grids = Vec::new();
    let mut logs = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        assert!(m.log_time >= last_time, "messages in time order");
        last_time = m.log_time;
        let schema = m
            .channel
            .schema
            .as_ref()
            .expect("every channel has a schema");
        assert_eq!(schema.encoding, "protobuf", "{}", m.channel.topic);
        assert_eq!(m.channel.message_encoding, "protobuf");
        // The schema is a FileDescriptorSet that defines the message it names.
        let fds = foxglove::prost_types::FileDescriptorSet::decode(&schema.data[..]).unwrap();
        let defined = fds.file.iter().any(|f| {
            f.message_type
                .iter()
                .any(|d| format!("{}.{}", f.package(), d.name()) == schema.name)
        });
        assert!(
            defined,
            "{} defines {}: {fds:?}",
            m.channel.topic, schema.name
        );
        let text = decode(schema, &m.data).unwrap_or_else(|e| panic!("{}: {e}", m.channel.topic));
        if m.channel.topic == "/theta" {
            grids.push(Grid::decode(&m.data[..]).unwrap());
        }
        if m.channel.topic == "/log" {
            logs.push(text);
        }
        *counts.entry(m.channel.topic.clone()).or_default() += 1;
    }
    let (n, d) = (r.samples.len(), r.summary.discoveries.len());
    assert_eq!(counts.len(), TOPICS.len(), "{counts:?}");
    for topic in ["/robot/pose", "/tf", "/harmonav/state"] {
        assert_eq!(counts[topic], n, "{topic}");
    }
    assert_eq!(
        counts["/sensor/sector"], 1,
        "drawn once, in the robot frame"
    );
    let events = 1 + r
        .summary
        .discoveries
        .iter()
        .filter(|x| x.time_s > 0.0)
        .count();
    assert_eq!((counts["/scene"], counts["/theta"]), (events, events));
    let paths = counts["/robot/path"] as f64;
    let periods = r.summary.time_s / PATH_PERIOD;
    assert!(
        (periods - 1.0..=periods + 2.0).contains(&paths),
        "{paths} path updates in {periods} periods"
    );
    assert!(
        logs.iter().filter(|l| l.starts_with("discovered")).count() == d,
        "{logs:?}"
    );
    // The Θ grid: float32 values in [0, 1] in the free space, NaN in the obstacles.
    let g = grids.last().unwrap();
    assert_eq!(g.column_count, GRID_CELLS);
    let values: Vec<f32> = g
        .data
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(values.len(), (GRID_CELLS * GRID_CELLS) as usize);
    let nan = values.iter().filter(|v| v.is_nan()).count();
    assert!(nan > 0 && nan < values.len() / 2, "{nan} NaN cells");
    assert!(
        values
            .iter()
            .filter(|v| !v.is_nan())
            .all(|v| (0.0..=1.0).contains(v))
    );
    assert!(
        std::fs::read_dir(&dir).unwrap().count() == 1,
        "no temporary file left"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_path_grows_linearly_and_in_order() {
    let prepared = scenario("shapes/mixed.toml");
    let r = run(&prepared, Some(Model::Kinematic)).unwrap();
    let path = std::env::temp_dir().join(format!("harmonav-path-{}.mcap", std::process::id()));
    write_mcap(&path, &prepared, &r).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let mut points: Vec<(f64, f64)> = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == "/robot/path" {
            let u = SceneUpdate::decode(&m.data[..]).unwrap();
            let segment: Vec<(f64, f64)> = u.entities[0].lines[0]
                .points
                .iter()
                .map(|p| (p.x, p.y))
                .collect();
            // Each update carries only the new part, starting where the last one ended.
            if let Some(&end) = points.last() {
                assert_eq!(segment[0], end);
                points.extend(&segment[1..]);
            } else {
                points.extend(segment);
            }
        }
    }
    let end = r.samples.last().unwrap().x;
    assert_eq!(points.last(), Some(&(end[0], end[1])));
    assert_eq!(points[0], (r.samples[0].x[0], r.samples[0].x[1]));
    for w in points[..points.len() - 1].windows(2) {
        assert!((w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) >= PATH_SPACING);
    }
    std::fs::remove_file(path).unwrap();
}

#[test]
fn outputs_are_written_and_figures_show_the_run() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shapes/mixed.toml");
    let prepared = Scenario::load(&file).unwrap();
    let dir = std::env::temp_dir().join(format!("harmonav-outputs-{}", std::process::id()));
    // A dynamic run first: its speed and energy figures must not outlive it.
    let dynamic = run(&prepared, Some(Model::Dynamic)).unwrap();
    write_outputs(&dir, &prepared, &dynamic).unwrap();
    // Drawn at 4× and shown at their nominal size, as the plane figures are: no stair steps.
    for (name, size) in [("speed.svg", (760, 360)), ("energy.svg", (760, 620))] {
        let svg = std::fs::read_to_string(dir.join(name)).unwrap();
        let head = format!(
            "<svg width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\"",
            size.0,
            size.1,
            4 * size.0,
            4 * size.1
        );
        assert!(
            svg.starts_with(&head),
            "{name}: {}",
            &svg[..120.min(svg.len())]
        );
        // Every stroke is scaled with the figure: none is thinner than one nominal pixel (4
        // backend pixels), so none was left at plotters' 1× default.
        for w in svg.split("stroke-width=\"").skip(1) {
            let w: f64 = w.split('"').next().unwrap().parse().unwrap();
            assert!(w == 0.0 || w >= 4.0, "{name}: a stroke {w} px wide at 4×");
        }
    }
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
    let labels: Vec<&str> = svg
        .split("<text")
        .skip(1)
        .filter_map(|t| {
            t.split_once('>')
                .and_then(|(_, rest)| rest.split_once("</text>"))
        })
        .map(|(text, _)| text.trim())
        .collect();
    for name in &prepared.truth.names {
        assert!(
            labels.contains(&name.as_str()),
            "label {name} in {labels:?}"
        );
    }
    assert!(labels.iter().any(|l| l.contains("goal reached")));
    // The level sets of Θ: one path per level line, in the levels' colours.
    let level_paths = svg.matches("<polyline").count();
    assert!(level_paths > 20, "{level_paths} polylines");
    // Drawn at 4× and shown at 720 px (plotters' SVG backend writes whole pixels): the path's
    // vertices keep a quarter of a pixel.
    assert!(
        svg.starts_with(r#"<svg width="720" height="800" viewBox="0 0 2880 3200""#),
        "{}",
        &svg[..120]
    );
    let path = svg
        .split("<polyline")
        .filter(|e| e.contains(r##"stroke="#D9480F""##))
        .max_by_key(|e| e.len())
        .unwrap();
    let quarters = path
        .split("points=\"")
        .nth(1)
        .unwrap()
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter_map(|v| v.parse::<i64>().ok())
        .filter(|v| v % 4 != 0)
        .count();
    assert!(
        quarters > 100,
        "{quarters} sub-pixel coordinates in the path"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["reached"], true);
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        3,
        "no temporary files left"
    );
    // A file where the folder should be is refused before anything is written.
    let file_path = dir.join("summary.json");
    let e = write_outputs(&file_path, &prepared, &r).unwrap_err();
    assert!(e.to_string().contains("not a directory"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// docs/foxglove-layout.json names only topics (and `/harmonav/state` fields) that the
/// recording has, so the layout and the recorder cannot drift apart.
#[test]
fn the_foxglove_layout_names_recorded_topics_and_fields() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/foxglove-layout.json");
    let layout: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
    fn strings(v: &serde_json::Value, out: &mut Vec<String>) {
        match v {
            serde_json::Value::String(s) => out.push(s.clone()),
            serde_json::Value::Array(a) => a.iter().for_each(|x| strings(x, out)),
            serde_json::Value::Object(o) => o.iter().for_each(|(k, x)| {
                out.push(k.clone());
                strings(x, out)
            }),
            _ => {}
        }
    }
    let mut all = Vec::new();
    strings(&layout, &mut all);
    let state = serde_json::to_value(harmonav_output::record::HarmonavState::default()).unwrap();
    let mut named = 0;
    for s in all.iter().filter(|s| s.starts_with('/')) {
        let (topic, field) = s
            .split_once('.')
            .map_or((s.as_str(), None), |(t, f)| (t, Some(f)));
        assert!(
            TOPICS.contains(&topic) || LIDAR_TOPICS.contains(&topic),
            "the layout names {topic}, which is not recorded"
        );
        if let Some(f) = field {
            assert!(
                topic == "/harmonav/state" && state.get(f).is_some(),
                "no field {s}"
            );
        }
        named += 1;
    }
    assert!(named >= 8, "{named} topic references");
    // A lidar run's scan and perceived shapes are drawn by default.
    for topic in LIDAR_TOPICS {
        assert!(
            all.iter().any(|s| s == topic),
            "the layout does not draw {topic}"
        );
    }
    let panels = layout["configById"].as_object().unwrap();
    assert!(
        panels.keys().any(|k| k.starts_with("3D!"))
            && panels.keys().any(|k| k.starts_with("RosOut!"))
    );
}

/// A floor plan's recording: every message decodes with its schema, one pose, transform and
/// state per state of the run, each scan on `/scan` and each event on `/perceived`, a `Θ`
/// grid at the start and at each event (finite in `[0, 1)` where the robot may be, NaN in
/// the walls), and the set written whole: `run.mcap`, `trajectory.svg`, `summary.json`.
#[test]
fn a_floor_plan_run_records_its_walls_scans_and_theta() {
    use harmonav_output::floor::FloorOutputs;
    use harmonav_scenario::floorplan::FloorScenario;
    use harmonav_sim::floor::FloorSummary;
    use harmonav_sim::physics::{Physics, simulate_floor_observed};
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/floorplans/lidar-room.toml");
    let p = FloorScenario::load(&file).unwrap();
    let dir = std::env::temp_dir().join(format!("harmonav-floor-mcap-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let start = p.starts[0];
    let mut outputs = FloorOutputs::begin(&dir, &p).unwrap();
    let model = Some(Model::Kinematic);
    let r = simulate_floor_observed(&p, model, start, Physics::Builtin, &mut |e| {
        outputs.observe(e);
    })
    .unwrap();
    let summary = FloorSummary::new(&p, model, start, &r);
    let written = outputs.finish(&summary, &r).unwrap();
    assert_eq!(written[0], dir.join("summary.json"));
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["run.mcap", "summary.json", "trajectory.svg"]);
    let bytes = std::fs::read(dir.join("run.mcap")).unwrap();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let (mut grids, mut scenes, mut last_pose) = (Vec::new(), Vec::new(), None);
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let schema = m.channel.schema.as_ref().unwrap();
        match m.channel.topic.as_str() {
            "/theta" => grids.push(Grid::decode(&m.data[..]).unwrap()),
            "/scene" => scenes.push(SceneUpdate::decode(&m.data[..]).unwrap()),
            "/robot/pose" => last_pose = PoseInFrame::decode(&m.data[..]).unwrap().pose,
            "/scan" | "/perceived" => {}
            topic => {
                decode(schema, &m.data).unwrap_or_else(|e| panic!("{topic}: {e}"));
            }
        }
        *counts.entry(m.channel.topic.clone()).or_default() += 1;
    }
    let report = r.perception.as_ref().unwrap().0.clone();
    for topic in ["/robot/pose", "/tf", "/harmonav/state"] {
        assert_eq!(counts[topic], r.commands + 1, "{topic}");
    }
    assert!(!counts.contains_key("/sensor/sector"), "no sector");
    let [scan, perceived] = LIDAR_TOPICS;
    assert_eq!(
        (counts[scan], counts[perceived]),
        (report.scans, report.events)
    );
    assert!(report.events >= 1);
    assert_eq!(grids.len(), 1 + report.events);
    // The scene: the walls (every ring of the plan), the shrunk walls, each obstacle, the goal.
    assert_eq!(scenes.len(), 1);
    let ids: Vec<&str> = scenes[0].entities.iter().map(|e| e.id.as_str()).collect();
    assert_eq!(ids[..2], ["walls", "shrunk-walls"]);
    let walls = p.floor.walls();
    assert_eq!(scenes[0].entities[0].lines.len(), 1 + walls.holes().len());
    assert_eq!(ids.len(), 3 + p.obstacles.len());
    assert!(
        ids[2..ids.len() - 1]
            .iter()
            .all(|id| id.starts_with("obstacle/")),
        "{ids:?}"
    );
    let end = last_pose.unwrap().position.unwrap();
    let x = r.positions.last().unwrap();
    assert!((end.x - x[0]).abs() < 1e-12 && (end.y - x[1]).abs() < 1e-12);
    // The last grid: Θ over the perceived shapes; NaN at a cell inside the walls' outer ring's
    // complement, finite below 1 at the cell holding the goal and smallest there.
    let g = grids.last().unwrap();
    let n = g.column_count as usize;
    let values: Vec<f32> = g
        .data
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(values.len(), n * n);
    let (corner, cell) = {
        let pose = g.pose.as_ref().unwrap().position.as_ref().unwrap();
        (
            nalgebra::Vector2::new(pose.x, pose.y),
            g.cell_size.as_ref().unwrap().x,
        )
    };
    let at = |q: nalgebra::Vector2<f64>| {
        let ij = ((q - corner) / cell).map(|c| c.floor() as usize);
        values[ij.y * n + ij.x]
    };
    let goal = nalgebra::Vector2::from(p.scenario.robot.goal);
    let finite: Vec<f32> = values.iter().copied().filter(|v| !v.is_nan()).collect();
    assert!(finite.iter().all(|v| (0.0..1.0).contains(v)));
    let least = finite.iter().copied().fold(f32::INFINITY, f32::min);
    assert!(at(goal) <= least + 1e-3, "{} {least}", at(goal));
    assert!(
        at(corner + nalgebra::Vector2::new(0.5, 0.5) * cell).is_nan(),
        "the corner cell lies outside the walls"
    );
    let nan = values.len() - finite.len();
    assert!(nan > 0 && nan < values.len(), "{nan} NaN cells");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A floor-plan set dropped before its finish (a failed or interrupted run) leaves nothing of
/// itself: the previous complete set stays as it was, and no staging folder remains.
#[test]
fn a_floor_plan_set_dropped_unfinished_leaves_the_previous_set() {
    use harmonav_output::floor::FloorOutputs;
    use harmonav_scenario::floorplan::FloorScenario;
    use harmonav_sim::floor::FloorSummary;
    use harmonav_sim::physics::{Physics, simulate_floor_observed};
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/floorplans/u-trap.toml");
    let p = FloorScenario::load(&file).unwrap();
    let dir = std::env::temp_dir().join(format!("harmonav-floor-drop-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (start, model) = (p.starts[0], Some(Model::Kinematic));
    let mut first = FloorOutputs::begin(&dir, &p).unwrap();
    let r = simulate_floor_observed(&p, model, start, Physics::Builtin, &mut |e| {
        first.observe(e);
    })
    .unwrap();
    first
        .finish(&FloorSummary::new(&p, model, start, &r), &r)
        .unwrap();
    let read = |name: &str| std::fs::read(dir.join(name)).unwrap();
    let before: Vec<Vec<u8>> = ["run.mcap", "trajectory.svg", "summary.json"]
        .iter()
        .map(|n| read(n))
        .collect();
    {
        let mut second = FloorOutputs::begin(&dir, &p).unwrap();
        simulate_floor_observed(
            &p,
            Some(Model::Dynamic),
            start,
            Physics::Builtin,
            &mut |e| {
                second.observe(e);
            },
        )
        .unwrap();
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            4,
            "the staging folder"
        );
        drop(second);
    }
    let after: Vec<Vec<u8>> = ["run.mcap", "trajectory.svg", "summary.json"]
        .iter()
        .map(|n| read(n))
        .collect();
    assert_eq!(before, after);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 3);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A scan event at `t = 0` (the table within the lidar's first fit range): the floor loop
/// hands that scan over before the first state, and `/theta` then holds the perceived world's
/// `Θ` alone, not the walls' after it at the same time.
#[test]
fn a_scan_event_at_the_start_keeps_its_theta_on_the_recording() {
    use harmonav_output::floor::FloorOutputs;
    use harmonav_scenario::floorplan::FloorScenario;
    use harmonav_sim::floor::FloorSummary;
    use harmonav_sim::physics::{Physics, simulate_floor_observed};
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/floorplans/lidar-room.toml");
    let text = std::fs::read_to_string(&file).unwrap().replace(
        "center = [2.5, 2.0]\nradius = 0.3",
        "center = [1.5, 0.8]\nradius = 0.2",
    );
    let p = FloorScenario::parse(&file, &text)
        .unwrap()
        .prepare(&file)
        .unwrap();
    assert_eq!(p.obstacles[0].centre(), nalgebra::Vector2::new(1.5, 0.8));
    let dir = std::env::temp_dir().join(format!("harmonav-floor-t0-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (start, model) = (p.starts[0], Some(Model::Kinematic));
    let mut outputs = FloorOutputs::begin(&dir, &p).unwrap();
    let (mut first_event, mut first_state) = (None, None);
    let r = simulate_floor_observed(&p, model, start, Physics::Builtin, &mut |e| {
        match &e {
            harmonav_sim::trace::Event::Scan(s) if s.perceived.is_some() => {
                first_event.get_or_insert(s.time_s);
            }
            harmonav_sim::trace::Event::State(s) => {
                first_state.get_or_insert(s.theta);
            }
            _ => {}
        }
        outputs.observe(e);
    })
    .unwrap();
    assert_eq!(first_event, Some(0.0), "the table is fitted from the start");
    outputs
        .finish(&FloorSummary::new(&p, model, start, &r), &r)
        .unwrap();
    let bytes = std::fs::read(dir.join("run.mcap")).unwrap();
    let grids: Vec<(u64, Grid)> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .filter(|m| m.channel.topic == "/theta")
        .map(|m| (m.log_time, Grid::decode(&m.data[..]).unwrap()))
        .collect();
    let events = r.perception.as_ref().unwrap().0.events;
    assert_eq!(
        grids.len(),
        events,
        "one grid per event, the first at t = 0"
    );
    // The grid at t = 0 is Θ over the perceived table: at the start's cell it is the first
    // state's Θ, to the grid's float32 and its cell's size.
    let (t0, g) = &grids[0];
    assert_eq!(*t0, 0);
    let n = g.column_count as usize;
    let corner = g.pose.as_ref().unwrap().position.as_ref().unwrap();
    let cell = g.cell_size.as_ref().unwrap().x;
    let (i, j) = (
        ((start.x - corner.x) / cell).floor() as usize,
        ((start.y - corner.y) / cell).floor() as usize,
    );
    let k = 4 * (j * n + i);
    let at_start = f32::from_le_bytes(g.data[k..k + 4].try_into().unwrap()) as f64;
    assert!(
        (at_start - first_state.unwrap()).abs() < 1e-3,
        "{at_start} {first_state:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A run with a mover (issue 54, item 4): `/movers` carries one frame every
/// `MOVER_FRAME_PERIOD` (the mover's disc and its reach, `mover/0`, at the person's true
/// position `start + v·t`), `/log` each change of the robot's mode (the person makes it
/// yield), and `trajectory.svg` the mover's track and a legend row for it; the same file
/// without its mover records no `/movers` and draws no mover.
#[test]
fn a_run_with_movers_records_and_draws_them() {
    use harmonav_output::record::MOVER_TOPICS;
    use harmonav_sim::trace::MOVER_FRAME_PERIOD;
    let prepared = scenario("movers/person-crossing.toml");
    let r = run(&prepared, None).unwrap();
    let frames = &r.mover_frames;
    assert!(frames.len() > 10, "{} frames", frames.len());
    for w in frames.windows(2) {
        assert!(
            w[1].t - w[0].t >= MOVER_FRAME_PERIOD * (1.0 - 1e-9),
            "{} {}",
            w[0].t,
            w[1].t
        );
    }
    let h = prepared
        .control_period()
        .unwrap_or(harmonav::tuning::DEFAULT_KINEMATIC_PERIOD);
    for f in frames {
        let m = f.movers[0];
        // The person walks from (0.3, −3.5) at (0, 1) m/s, reported exactly (ε = 0).
        assert!((m.position[0] - 0.3).abs() < 1e-12, "{m:?}");
        assert!(
            (m.position[1] - (-3.5 + f.t)).abs() < 1e-9,
            "{m:?} at {}",
            f.t
        );
        assert!(
            (m.reach - (0.25 + 1.0 * h)).abs() < 1e-12 && !m.reciprocal,
            "{m:?}"
        );
    }
    assert!(
        frames.iter().any(|f| f.mode == Some("yielding")),
        "the person makes it yield"
    );
    let dir = std::env::temp_dir().join(format!("harmonav-movers-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.mcap");
    write_mcap(&path, &prepared, &r).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let (mut scenes, mut modes) = (Vec::new(), 0);
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == MOVER_TOPICS[0] {
            scenes.push(SceneUpdate::decode(&m.data[..]).unwrap());
        }
        if m.channel.topic == "/log"
            && Log::decode(&m.data[..])
                .unwrap()
                .message
                .starts_with("mode ")
        {
            modes += 1;
        }
    }
    assert_eq!(scenes.len(), frames.len());
    let first = &scenes[0].entities[0];
    assert_eq!(first.id, "mover/0");
    assert_eq!(first.lines.len(), 2, "the disc and its reach");
    assert!(modes >= 2, "{modes} mode changes logged");
    let svg = harmonav_output::figures::trajectory_svg(&prepared, &r).unwrap();
    // The mover's purple (track, disc, reach) and the legend's row.
    assert!(
        svg.contains("#913CB9") && svg.contains("yielding"),
        "the mover is drawn"
    );
    // The control: the same file without its mover.
    let mut still = prepared.scenario.clone();
    still.sim.movers.clear();
    let quiet = still
        .prepare(Path::new("movers/person-crossing.toml"))
        .unwrap();
    let q = run(&quiet, None).unwrap();
    assert!(q.mover_frames.is_empty());
    write_mcap(&path, &quiet, &q).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert!(
        mcap::MessageStream::new(&bytes)
            .unwrap()
            .all(|m| m.unwrap().channel.topic != MOVER_TOPICS[0])
    );
    let svg = harmonav_output::figures::trajectory_svg(&quiet, &q).unwrap();
    assert!(!svg.contains("#913CB9") && !svg.contains("yielding"));
    std::fs::remove_dir_all(&dir).unwrap();
}
