//! The MCAP recording of a run (mcap crate), with JSON messages under Foxglove schema names
//! so that Foxglove's 3D and plot panels show it directly.
//!
//! | topic | schema | content |
//! |---|---|---|
//! | `/robot/pose` | `foxglove.PoseInFrame` | the robot pose at every recorded state |
//! | `/robot/trajectory` | `foxglove.PosesInFrame` | the path so far, at each discovery and at the end |
//! | `/scene` | `foxglove.SceneUpdate` | boundary, obstacles (grey: unknown, red: known), goal; at t = 0 and each discovery |
//! | `/sensor/sector` | `foxglove.SceneUpdate` | the sensing sector at every recorded state (sector sensing only) |
//! | `/state` | `harmonav.State` | t, x, ẋ, Θ, V, k, λ |
//! | `/discoveries` | `harmonav.Discovery` | obstacle name and time |

use std::collections::BTreeMap;
use std::f64::consts::TAU;
use std::io::{BufWriter, Cursor};
use std::path::Path;

use harmonav_sensing::Sensing;
use harmonav_transform::StarShape;
use mcap::records::MessageHeader;
use nalgebra::Vector2;
use serde_json::{Value, json};

use crate::run::{Run, Sample};
use crate::scenario::Prepared;

/// Topic names, in channel order.
pub const TOPICS: [&str; 6] = [
    "/robot/pose",
    "/robot/trajectory",
    "/scene",
    "/sensor/sector",
    "/state",
    "/discoveries",
];
const SCHEMAS: [&str; 6] = [
    "foxglove.PoseInFrame",
    "foxglove.PosesInFrame",
    "foxglove.SceneUpdate",
    "foxglove.SceneUpdate",
    "harmonav.State",
    "harmonav.Discovery",
];

/// The sensing sector is drawn at most once per this many seconds of simulated time (a
/// sector is ~1.5 kB of JSON; drawing it at every 0.01 s sample made a 193 s run 64 MB).
pub const SECTOR_PERIOD: f64 = 0.1;

/// Vertices of the `/robot/trajectory` paths are at least this far apart, m (every sample is
/// still on `/robot/pose` and `/state`).
pub const TRAJECTORY_SPACING: f64 = 0.01;

fn stamp(t: f64) -> Value {
    let ns = (t.max(0.0) * 1e9).round() as u64;
    json!({ "sec": ns / 1_000_000_000, "nsec": ns % 1_000_000_000 })
}

fn nanos(t: f64) -> u64 {
    (t.max(0.0) * 1e9).round() as u64
}

fn pose(p: [f64; 2], v: [f64; 2]) -> Value {
    let yaw = if v[0] == 0.0 && v[1] == 0.0 {
        0.0
    } else {
        v[1].atan2(v[0])
    };
    json!({
        "position": { "x": p[0], "y": p[1], "z": 0.0 },
        "orientation": { "x": 0.0, "y": 0.0, "z": (0.5 * yaw).sin(), "w": (0.5 * yaw).cos() }
    })
}

fn line_strip(points: impl Iterator<Item = Vector2<f64>>, color: [f64; 4]) -> Value {
    let pts: Vec<Value> = points
        .map(|p| json!({ "x": p.x, "y": p.y, "z": 0.0 }))
        .collect();
    json!({
        "type": 0, "pose": pose([0.0, 0.0], [0.0, 0.0]), "thickness": 0.02, "scale_invariant": false,
        "points": pts, "color": { "r": color[0], "g": color[1], "b": color[2], "a": color[3] }, "colors": [], "indices": []
    })
}

fn entity(t: f64, id: &str, lines: Vec<Value>, spheres: Vec<Value>) -> Value {
    json!({
        "timestamp": stamp(t), "frame_id": "world", "id": id, "lifetime": { "sec": 0, "nsec": 0 },
        "frame_locked": false, "metadata": [], "arrows": [], "cubes": [], "spheres": spheres, "cylinders": [],
        "lines": lines, "triangles": [], "texts": [], "models": []
    })
}

fn closed(shape: &StarShape) -> impl Iterator<Item = Vector2<f64>> + '_ {
    (0..=180).map(move |i| shape.boundary_point(TAU * i as f64 / 180.0))
}

/// The scene at time `t`: boundary, obstacles (known ones red), goal.
fn scene(prepared: &Prepared, run: &Run, t: f64) -> Value {
    let mut entities = vec![entity(
        t,
        "boundary",
        vec![line_strip(
            closed(&prepared.truth.boundary),
            [1.0, 1.0, 1.0, 1.0],
        )],
        vec![],
    )];
    for (i, o) in prepared.truth.obstacles.iter().enumerate() {
        let known = run
            .summary
            .discoveries
            .iter()
            .any(|d| d.index == i && d.time_s <= t);
        let color = if known {
            [0.9, 0.2, 0.2, 1.0]
        } else {
            [0.6, 0.6, 0.6, 1.0]
        };
        entities.push(entity(
            t,
            &prepared.truth.names[i],
            vec![line_strip(closed(o), color)],
            vec![],
        ));
    }
    let g = prepared.truth.workspace.destination();
    let goal = json!({ "pose": pose([g.x, g.y], [0.0, 0.0]), "size": { "x": 0.1, "y": 0.1, "z": 0.1 }, "color": { "r": 0.2, "g": 0.8, "b": 0.3, "a": 1.0 } });
    entities.push(entity(t, "goal", vec![], vec![goal]));
    json!({ "deletions": [], "entities": entities })
}

fn sector(prepared: &Prepared, s: &Sample) -> Option<Value> {
    let Sensing::Sector(sec) = prepared.truth.sensing else {
        return None;
    };
    let v = Vector2::new(s.v[0], s.v[1]);
    if v.norm() == 0.0 {
        return None;
    }
    let (pole, a0) = (Vector2::new(s.x[0], s.x[1]), v.y.atan2(v.x));
    let mut pts = vec![pole];
    for i in 0..=24 {
        let a = a0 - 0.5 * sec.aperture() + sec.aperture() * i as f64 / 24.0;
        pts.push(pole + sec.range() * Vector2::new(a.cos(), a.sin()));
    }
    pts.push(pole);
    Some(
        json!({ "deletions": [], "entities": [entity(s.t, "sector", vec![line_strip(pts.into_iter(), [0.2, 0.5, 0.9, 1.0])], vec![])] }),
    )
}

/// The recording as bytes (deterministic for a given run).
pub fn mcap_bytes(prepared: &Prepared, run: &Run) -> mcap::McapResult<Vec<u8>> {
    let mut out = Cursor::new(Vec::new());
    {
        let mut w = mcap::Writer::new(BufWriter::new(&mut out))?;
        let mut channels = [0u16; 6];
        for (i, (topic, schema)) in TOPICS.iter().zip(SCHEMAS).enumerate() {
            let schema_id = w.add_schema(schema, "jsonschema", br#"{"type":"object"}"#)?;
            channels[i] = w.add_channel(schema_id, topic, "json", &BTreeMap::new())?;
        }
        let mut sequence = [0u32; 6];
        // Messages in time order; ties keep the channel order.
        let mut messages: Vec<(u64, usize, Value)> = Vec::new();
        let frame = |poses: Vec<Value>, t: f64| json!({ "timestamp": stamp(t), "frame_id": "world", "poses": poses });
        let mut scene_times = vec![0.0];
        scene_times.extend(
            run.summary
                .discoveries
                .iter()
                .map(|d| d.time_s)
                .filter(|&t| t > 0.0),
        );
        scene_times.dedup();
        for &t in &scene_times {
            messages.push((nanos(t), 2, scene(prepared, run, t)));
        }
        let mut next_sector = 0.0;
        for s in &run.samples {
            messages.push((
                nanos(s.t),
                0,
                json!({ "timestamp": stamp(s.t), "frame_id": "world", "pose": pose(s.x, s.v) }),
            ));
            if s.t >= next_sector
                && let Some(sec) = sector(prepared, s)
            {
                messages.push((nanos(s.t), 3, sec));
                next_sector = ((s.t / SECTOR_PERIOD).floor() + 1.0) * SECTOR_PERIOD;
            }
            messages.push((nanos(s.t), 4, json!({ "t": s.t, "x": s.x, "v": s.v, "theta": s.theta, "energy": s.energy, "k": s.k, "lambda": s.lambda, "lambda_switched": s.lambda.is_some() && !s.critical })));
        }
        let mut trajectory_times: Vec<f64> =
            run.summary.discoveries.iter().map(|d| d.time_s).collect();
        trajectory_times.push(run.summary.time_s);
        // The path so far, thinned to vertices TRAJECTORY_SPACING apart (and the last one).
        let mut thinned: Vec<&Sample> = Vec::new();
        for (i, s) in run.samples.iter().enumerate() {
            let last = i + 1 == run.samples.len();
            let far = thinned.last().is_none_or(|p| {
                (Vector2::new(s.x[0] - p.x[0], s.x[1] - p.x[1])).norm() >= TRAJECTORY_SPACING
            });
            if far || last {
                thinned.push(s);
            }
        }
        for &t in &trajectory_times {
            let poses = thinned
                .iter()
                .filter(|s| s.t <= t)
                .map(|s| pose(s.x, s.v))
                .collect();
            messages.push((nanos(t), 1, frame(poses, t)));
        }
        for d in &run.summary.discoveries {
            messages.push((
                nanos(d.time_s),
                5,
                json!({ "t": d.time_s, "obstacle": d.obstacle }),
            ));
        }
        messages.sort_by_key(|m| (m.0, m.1));
        for (time, channel, body) in messages {
            let header = MessageHeader {
                channel_id: channels[channel],
                sequence: sequence[channel],
                log_time: time,
                publish_time: time,
            };
            sequence[channel] += 1;
            w.write_to_known_channel(&header, body.to_string().as_bytes())?;
        }
        // Finish explicitly: dropping would swallow errors.
        w.finish()?;
    }
    Ok(out.into_inner())
}

/// Writes `summary.json`, `run.mcap`, `trajectory.svg` and (dynamic runs) `speed.svg` into
/// `dir`, each through a temporary file and a rename.
pub fn write_outputs(
    dir: &Path,
    prepared: &Prepared,
    run: &Run,
) -> Result<Vec<std::path::PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut files = Vec::new();
    let mut put = |name: &str, bytes: Vec<u8>| -> Result<(), String> {
        let path = dir.join(name);
        crate::svg::write_atomically(&path, &bytes)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        files.push(path);
        Ok(())
    };
    let summary = serde_json::to_string_pretty(&run.summary).map_err(|e| e.to_string())?;
    put("summary.json", (summary + "\n").into_bytes())?;
    put(
        "run.mcap",
        mcap_bytes(prepared, run).map_err(|e| format!("MCAP: {e}"))?,
    )?;
    put(
        "trajectory.svg",
        crate::figures::trajectory_svg(prepared, run).into_bytes(),
    )?;
    if run.summary.speed_bound.is_some() {
        put("speed.svg", crate::figures::speed_svg(run).into_bytes())?;
    }
    Ok(files)
}
