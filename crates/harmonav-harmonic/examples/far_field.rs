//! The far field of docs/maths.md §11: its agreement with the direct sum on dense samples of
//! the test worlds (grid and points within half an element of the walls), and the cost of one
//! evaluation both ways against `N`.
//!
//! `cargo run --release -p harmonav-harmonic --example far_field`

#[path = "../tests/common/mod.rs"]
mod common;

use common::*;
use harmonav_harmonic::{Domain, FAR_FIELD_TOLERANCE, HarmonicMap, MeshOptions};
use std::hint::black_box;
use std::time::Instant;

/// `max |ΔH|` and `max |ΔJ_H|·D` (normalised units) between the far field and the direct sum.
fn agreement(map: &HarmonicMap, points: &[nalgebra::Vector2<f64>]) -> (f64, f64, f64) {
    let (lo, hi) = map.domain().bounding_box();
    let scale = (hi - lo).norm();
    let (mut dh, mut dj, mut jmax) = (0.0_f64, 0.0_f64, 0.0_f64);
    for &x in points {
        let (Ok(a), Ok(b)) = (map.eval(x), map.eval_direct(x)) else {
            continue;
        };
        dh = dh.max((a.value - b.value).amax());
        dj = dj.max((a.jacobian - b.jacobian).amax() * scale);
        jmax = jmax.max(b.jacobian.amax() * scale);
    }
    (dh, dj, jmax)
}

fn per_point_us(points: &[nalgebra::Vector2<f64>], f: impl Fn(nalgebra::Vector2<f64>)) -> f64 {
    let t = Instant::now();
    for &x in points {
        f(black_box(x));
    }
    t.elapsed().as_secs_f64() * 1e6 / points.len() as f64
}

fn main() {
    let worlds: Vec<(&str, Domain, f64)> = vec![
        ("square+hole", square_with_hole(), 0.01),
        ("U", u_world(), 0.03),
        ("L", l_world(), 0.02),
        ("two rooms", two_rooms(), 0.03),
        ("pillars", pillared_room(), 0.028),
    ];
    println!("tolerance {FAR_FIELD_TOLERANCE:e}");
    for (name, d, h) in worlds {
        let map = HarmonicMap::new(&d, &MeshOptions::graded(h))
            .unwrap()
            .with_far_field(Some(FAR_FIELD_TOLERANCE))
            .unwrap();
        let n = map.elements().len();
        let points = dense_samples(&map, h * 2.0, 1);
        let (dh, dj, jmax) = agreement(&map, &points);
        let c = map.setup_cost();
        let grid_points = grid(map.domain(), h * 3.0, h);
        let fast = per_point_us(&grid_points, |x| {
            let _ = black_box(map.eval(x));
        });
        let direct = per_point_us(&grid_points, |x| {
            let _ = black_box(map.eval_direct(x));
        });
        println!(
            "{name:12} N {n:5} (p, L) {:?}  samples {:6}  max|ΔH| {dh:.1e}  max|ΔJ|·D {dj:.1e} (max|J|·D {jmax:.1e})  bound {:.1e}  \
             mesh {:.3}s assembly {:.3}s LU {:.3}s tree {:.3}s  eval fast {fast:.2}us direct {direct:.2}us",
            map.far_field_levels().unwrap_or_default(),
            points.len(),
            map.far_field_bound().unwrap_or(f64::NAN),
            c.mesh.as_secs_f64(),
            c.assembly.as_secs_f64(),
            c.factor.as_secs_f64(),
            c.far_field.as_secs_f64(),
        );
    }
}
