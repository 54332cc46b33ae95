//! The shapes as drawn and recorded: their outlines as closed polylines, shared by the
//! figures ([`crate::figures`]) and the recording ([`crate::record`]).

use harmonav_transform::StarShape;
use nalgebra::Vector2;

/// A point as plotters wants it.
pub fn xy(p: Vector2<f64>) -> (f64, f64) {
    (p.x, p.y)
}

/// The outline of `shape`, closed: the vertices it answers distance queries with (evenly
/// spaced in arc length, [`StarShape::outline`]), then the first again.
pub fn closed_outline(shape: &StarShape) -> impl Iterator<Item = Vector2<f64>> + '_ {
    shape.outline().chain(shape.outline().take(1))
}

/// [`closed_outline`] as plotters points.
pub fn outline(shape: &StarShape) -> Vec<(f64, f64)> {
    closed_outline(shape).map(xy).collect()
}

/// A closed ring (a polygon's vertices, its first vertex again at the end) as plotters points.
pub fn ring(points: &[Vector2<f64>]) -> Vec<(f64, f64)> {
    points
        .iter()
        .chain(points.first())
        .map(|&p| xy(p))
        .collect()
}
