//! The Foxglove messages a recording is made of, built from harmonav's values: times,
//! poses, coloured lines, scene entities, `Θ` grids and log lines.

use foxglove::messages::{
    Color, Grid, LinePrimitive, Log, PackedElementField, Point3, Pose, Quaternion, SceneEntity,
    Timestamp, Vector2 as FVector2, Vector3, line_primitive, log,
    packed_element_field::NumericType,
};
use nalgebra::Vector2;

use crate::levels::ThetaGrid;

/// `t` s as nanoseconds, the log time of a message (a negative `t` as 0).
pub(crate) fn nanos(t: f64) -> u64 {
    (t.max(0.0) * 1e9).round() as u64
}

/// `t` s as a message's timestamp.
pub(crate) fn stamp(t: f64) -> Option<Timestamp> {
    let ns = nanos(t);
    Some(Timestamp::new(
        (ns / 1_000_000_000) as u32,
        (ns % 1_000_000_000) as u32,
    ))
}

/// `p` in the plane `z = 0`.
pub(crate) fn point(p: Vector2<f64>) -> Point3 {
    Point3 {
        x: p.x,
        y: p.y,
        z: 0.0,
    }
}

/// An RGBA colour, each channel in `[0, 1]`.
pub(crate) fn color([r, g, b, a]: [f64; 4]) -> Option<Color> {
    Some(Color { r, g, b, a })
}

/// The pose at `p` heading along `yaw`.
pub(crate) fn pose(p: Vector2<f64>, yaw: f64) -> Pose {
    Pose {
        position: Some(Vector3 {
            x: p.x,
            y: p.y,
            z: 0.0,
        }),
        orientation: Some(yaw_quaternion(yaw)),
    }
}

/// The rotation by `yaw` about `z`.
pub(crate) fn yaw_quaternion(yaw: f64) -> Quaternion {
    Quaternion {
        x: 0.0,
        y: 0.0,
        z: (0.5 * yaw).sin(),
        w: (0.5 * yaw).cos(),
    }
}

/// The colour of a perceived shape (cyan).
pub(crate) const PERCEIVED: [f64; 4] = [0.1, 0.75, 0.85, 1.0];

/// A line strip through `points` (m, in its entity's frame).
pub(crate) fn line(
    points: impl Iterator<Item = Vector2<f64>>,
    rgba: [f64; 4],
    thickness: f64,
) -> LinePrimitive {
    LinePrimitive {
        r#type: line_primitive::Type::LineStrip as i32,
        pose: Some(pose(Vector2::zeros(), 0.0)),
        thickness,
        scale_invariant: false,
        points: points.map(point).collect(),
        color: color(rgba),
        ..Default::default()
    }
}

/// A scene entity of `lines` at `t` in `frame` (locked to it unless it is `world`).
pub(crate) fn entity(t: f64, frame: &str, id: &str, lines: Vec<LinePrimitive>) -> SceneEntity {
    SceneEntity {
        timestamp: stamp(t),
        frame_id: frame.into(),
        id: id.into(),
        frame_locked: frame != "world",
        lines,
        ..Default::default()
    }
}

/// A log line of harmonav's at `t`.
pub(crate) fn log_message(t: f64, level: log::Level, message: String) -> Log {
    Log {
        timestamp: stamp(t),
        level: level as i32,
        message,
        name: "harmonav".into(),
        ..Default::default()
    }
}

/// `grid` as a `foxglove.Grid` at `t` in the `world` frame: one field `theta`, little-endian
/// float32 (NaN outside the free space), row by row from the lower-left corner.
pub(crate) fn grid_message(grid: &ThetaGrid, t: f64) -> Grid {
    let n = grid.n as u32;
    let data: Vec<u8> = grid
        .values
        .iter()
        .flat_map(|&v| (v as f32).to_le_bytes())
        .collect();
    Grid {
        timestamp: stamp(t),
        frame_id: "world".into(),
        pose: Some(pose(grid.corner, 0.0)),
        column_count: n,
        cell_size: Some(FVector2 {
            x: grid.cell,
            y: grid.cell,
        }),
        row_stride: 4 * n,
        cell_stride: 4,
        fields: vec![PackedElementField {
            name: "theta".into(),
            offset: 0,
            r#type: NumericType::Float32 as i32,
        }],
        data: data.into(),
    }
}
