//! The map's own obstacles, whatever the pipeline did to them: the distance from a point to the
//! nearest non-free pixel (issue 56, D1). A run on a map is judged against these pixels, not
//! against the outline the floor plan was built on, which dropped specks, was simplified and
//! cuts the corners of occupied pixels (marching squares, [`super::outline::trace`]).

use nalgebra::{Matrix2, Vector2};
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::query::PointQuery;
use parry2d_f64::shape::Polyline;

use super::{Cell, RosMap};

/// The non-free pixels of a map ([`RosMap::occupied_pixels`]): occupied and unknown pixels,
/// and everything outside the image, as closed squares.
///
/// ```text
/// d(x) = min over non-free pixels P of dist(x, P)        x in a free pixel
/// d(x) = −dist(x, the free pixels' squares) ≤ 0          otherwise
/// ```
///
/// The nearest point of the non-free set from a free point lies on a pixel edge between a
/// free and a non-free pixel (or on the image's edge next to a free pixel), so `d` is the
/// distance to those edges, which parry's polyline answers through its BVH in `O(log n)`.
#[derive(Clone)]
pub struct OccupiedPixels {
    origin: Vector2<f64>,
    rotation: Matrix2<f64>,
    resolution: f64,
    width: usize,
    height: usize,
    free: Vec<bool>,
    /// The free/non-free pixel edges in the map frame, collinear runs merged; `None` when no
    /// pixel is free.
    edges: Option<Polyline>,
}

impl std::fmt::Debug for OccupiedPixels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OccupiedPixels")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("resolution", &self.resolution)
            .field(
                "edges",
                &self.edges.as_ref().map_or(0, |p| p.num_segments()),
            )
            .finish_non_exhaustive()
    }
}

/// The runs of `true` in `flags`, as `[start, end)` index pairs.
fn runs(flags: impl Iterator<Item = bool>) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut open = None;
    let mut n = 0;
    for (i, f) in flags.enumerate() {
        match (f, open) {
            (true, None) => open = Some(i),
            (false, Some(s)) => {
                out.push((s, i));
                open = None;
            }
            _ => {}
        }
        n = i + 1;
    }
    if let Some(s) = open {
        out.push((s, n));
    }
    out
}

impl OccupiedPixels {
    pub(crate) fn new(map: &RosMap) -> Self {
        let (width, height) = map.size();
        let free: Vec<bool> = map.cells.iter().map(|&c| c == Cell::Free).collect();
        // Free pixel (column c, row r from the top); outside the image is not free.
        let at = |c: isize, r: isize| {
            c >= 0
                && r >= 0
                && (c as usize) < width
                && (r as usize) < height
                && free[r as usize * width + c as usize]
        };
        let res = map.resolution();
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let mut push = |a: [f64; 2], b: [f64; 2]| {
            let i = vertices.len() as u32;
            vertices.push(PVector::new(a[0] * res, a[1] * res));
            vertices.push(PVector::new(b[0] * res, b[1] * res));
            indices.push([i, i + 1]);
        };
        #[allow(clippy::cast_possible_wrap, clippy::cast_precision_loss)] // sides ≤ MAX_SIDE
        {
            // Horizontal grid lines: line j (from the bottom, map frame y = j·res) lies between
            // row H − j (below) and row H − j − 1 (above).
            for j in 0..=height {
                let below = height as isize - j as isize;
                let above = below - 1;
                let edge = (0..width).map(|c| at(c as isize, below) != at(c as isize, above));
                for (c0, c1) in runs(edge) {
                    push([c0 as f64, j as f64], [c1 as f64, j as f64]);
                }
            }
            // Vertical grid lines: line i (x = i·res) lies between columns i − 1 and i; the
            // run along rows goes downward, row r spanning y ∈ [H − r − 1, H − r].
            for i in 0..=width {
                let edge = (0..height)
                    .map(|r| at(i as isize - 1, r as isize) != at(i as isize, r as isize));
                for (r0, r1) in runs(edge) {
                    push(
                        [i as f64, (height - r0) as f64],
                        [i as f64, (height - r1) as f64],
                    );
                }
            }
        }
        let edges = (!indices.is_empty()).then(|| Polyline::new(vertices, Some(indices)));
        let o = map.origin();
        Self {
            origin: Vector2::new(o[0], o[1]),
            rotation: map.rotation(),
            resolution: res,
            width,
            height,
            free,
            edges,
        }
    }

    /// The signed distance from the world point `x` to the nearest non-free pixel (m): the
    /// equation of [`OccupiedPixels`]; positive in a free pixel, `≤ 0` in an occupied or
    /// unknown pixel, on a pixel edge between free and non-free, or outside the image. NaN
    /// for a non-finite point.
    #[must_use]
    pub fn signed_distance(&self, x: Vector2<f64>) -> f64 {
        if !(x.x.is_finite() && x.y.is_finite()) {
            return f64::NAN;
        }
        let l = self.rotation.transpose() * (x - self.origin);
        let p = l / self.resolution;
        #[allow(clippy::cast_precision_loss)] // sides ≤ MAX_SIDE
        let (w, h) = (self.width as f64, self.height as f64);
        let (cx, cy) = (p.x.floor(), p.y.floor());
        if !(cx >= 0.0 && cy >= 0.0 && cx < w && cy < h) {
            // Outside the image, all non-free: minus the distance to the image (the depth is at
            // least that; `hypot` does not overflow far away).
            let dx = (-l.x).max(l.x - w * self.resolution).max(0.0);
            let dy = (-l.y).max(l.y - h * self.resolution).max(0.0);
            return -dx.hypot(dy);
        }
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // in [0, side)
        let (c, r) = (cx as usize, self.height - 1 - cy as usize);
        let Some(edges) = &self.edges else {
            return f64::NEG_INFINITY;
        };
        let d = edges.distance_to_local_point(PVector::new(l.x, l.y), true);
        if self.free[r * self.width + c] { d } else { -d }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ros_map::MapMode;
    use std::path::PathBuf;

    /// A small seeded map of free and non-free cells, turned and moved.
    fn map(width: usize, height: usize, seed: u64) -> RosMap {
        let mut state = seed;
        let cells = (0..width * height)
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1);
                match state >> 61 {
                    0 => Cell::Occupied,
                    1 => Cell::Unknown,
                    _ => Cell::Free,
                }
            })
            .collect();
        RosMap {
            yaml_path: PathBuf::new(),
            image_path: PathBuf::new(),
            resolution: 0.1,
            origin: [0.3, -0.2, 0.4],
            negate: false,
            occupied_thresh: 0.65,
            free_thresh: 0.196,
            mode: MapMode::Trinary,
            width,
            height,
            cells,
        }
    }

    /// The distance from `p` (map frame, m) to the closed square of pixel (c, r).
    fn to_square(p: Vector2<f64>, c: usize, r: usize, height: usize, res: f64) -> f64 {
        let (x0, y0) = (c as f64 * res, (height - 1 - r) as f64 * res);
        let dx = (x0 - p.x).max(p.x - x0 - res).max(0.0);
        let dy = (y0 - p.y).max(p.y - y0 - res).max(0.0);
        dx.hypot(dy)
    }

    /// The signed distance against a brute force over every pixel square (and, for a point in
    /// a free pixel, the outside of the image): the same to rounding, at points inside the
    /// image, on pixel edges and outside it.
    #[test]
    fn the_signed_distance_is_the_brute_force_over_every_pixel() {
        for seed in 1..4 {
            let m = map(13, 9, seed);
            let pixels = OccupiedPixels::new(&m);
            let (w, h, res) = (m.width, m.height, m.resolution);
            let mut state = seed;
            let mut uniform = |lo: f64, hi: f64| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1);
                lo + (hi - lo) * ((state >> 11) as f64 / (1u64 << 53) as f64)
            };
            for k in 0..600 {
                let mut l = Vector2::new(uniform(-0.05, 1.35), uniform(-0.05, 0.95));
                if k % 5 == 0 {
                    l.x = (l.x / res).round() * res; // on a vertical pixel edge
                }
                let x = m.to_world(l);
                let got = pixels.signed_distance(x);
                let border =
                    l.x.min(l.y)
                        .min(w as f64 * res - l.x)
                        .min(h as f64 * res - l.y);
                if border.abs() < 1e-9 {
                    // On the image's edge (to the frames' rounding): outside is not free.
                    assert!(got <= 1e-9, "{got} on the image's edge");
                    continue;
                }
                let inside =
                    l.x >= 0.0 && l.y >= 0.0 && l.x < w as f64 * res && l.y < h as f64 * res;
                let free_here = m
                    .pixel_at(x)
                    .is_some_and(|[c, r]| m.cells[r * w + c] == Cell::Free);
                let want = if free_here {
                    let wall = (0..w * h)
                        .filter(|&i| m.cells[i] != Cell::Free)
                        .map(|i| to_square(l, i % w, i / w, h, res))
                        .fold(f64::INFINITY, f64::min);
                    let border =
                        l.x.min(l.y)
                            .min(w as f64 * res - l.x)
                            .min(h as f64 * res - l.y);
                    wall.min(border)
                } else if inside {
                    -(0..w * h)
                        .filter(|&i| m.cells[i] == Cell::Free)
                        .map(|i| to_square(l, i % w, i / w, h, res))
                        .fold(f64::INFINITY, f64::min)
                } else {
                    assert!(got <= 0.0, "{got} outside the image");
                    continue;
                };
                assert!(
                    (got - want).abs() < 1e-9,
                    "seed {seed} at {l:?}: {got} against {want}"
                );
            }
        }
    }

    #[test]
    fn runs_are_half_open_and_close_at_the_end() {
        let f = [true, true, false, true, false, false, true];
        assert_eq!(runs(f.into_iter()), vec![(0, 2), (3, 4), (6, 7)]);
        assert!(runs([false, false].into_iter()).is_empty());
    }
}
