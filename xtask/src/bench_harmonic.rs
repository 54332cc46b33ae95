//! `cargo xtask bench --only harmonic`: the cost of the floor plans' harmonic map `H` against
//! the number of elements `N` (issue 25; docs/benchmarks.md, "Harmonic map cost").
//!
//! World: a 10 × 6 m room with eight 0.6 m square pillars (the far-field tests' world), graded
//! elements, the element length chosen by bisection so that `N` ≥ 250, 500, 1 000, 2 000, 4 000
//! (the first count reached).
//! Figures for each target `n` (the actual `N` is `harmonic_elements_n{n}`):
//!
//! - `harmonic_setup_ms_n{n}`: one `HarmonicMap::new` (mesh, assembly, LU, and the far-field
//!   tree from `FAR_FIELD_MIN_ELEMENTS`), the median of a few; `harmonic_{mesh,assembly,lu}_ms_n{n}`
//!   its parts (`HarmonicMap::setup_cost` of the median run), `harmonic_tree_ms_n{n}` the tree
//!   (built for the far-field figures even below the threshold);
//! - `harmonic_eval_us_n{n}_{far,direct}`: one `HarmonicMap::eval` (`H`, `J_H`) at a free point,
//!   through the far field and by the direct sum (`eval_direct`);
//! - `harmonic_floor_ms_n{n}`: one `FloorMap::new` (the same solve, plus `r_δ` over `∂W_δ`);
//! - `harmonic_command_us_n{n}_{far,direct}`: one `FloorNavigator::command` (kinematic law, the
//!   default hold) at a free point, the floor with and without the far field.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use harmonav::floorplan::Geodesic;
use harmonav::{FloorMap, FloorNavigator, FloorOptions, Law, Options, Vector2};
use harmonav_harmonic::{Domain, HarmonicMap, MeshOptions, mesh};
use harmonav_transform::random::Rng;

use crate::bench::median_ns;

/// The target element counts.
const TARGETS: [usize; 5] = [250, 500, 1000, 2000, 4000];

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// The room's outer ring (counter-clockwise) and pillars (clockwise).
fn rings() -> (Vec<Vector2<f64>>, Vec<Vec<Vector2<f64>>>) {
    let outer = vec![v(0.0, 0.0), v(10.0, 0.0), v(10.0, 6.0), v(0.0, 6.0)];
    let pillars = (0..8)
        .map(|i| {
            let c = v(1.75 + 2.15 * (i % 4) as f64, 2.0 + 2.0 * (i / 4) as f64);
            [v(-0.3, -0.3), v(-0.3, 0.3), v(0.3, 0.3), v(0.3, -0.3)]
                .iter()
                .map(|d| c + d)
                .collect()
        })
        .collect();
    (outer, pillars)
}

/// The longest graded element length that gives at least `n` elements on `domain` (bisection
/// on the mesh's count, which falls as the length grows).
fn element_length(domain: &Domain, n: usize) -> f64 {
    let count =
        |h: f64| mesh::mesh(domain, &MeshOptions::graded(h)).map_or(usize::MAX, |m| m.len());
    let (mut lo, mut hi) = (1e-3_f64, 1.0_f64);
    for _ in 0..40 {
        let mid = (lo * hi).sqrt();
        if count(mid) >= n {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Median of `samples` runs of `f`, ms.
fn median_ms<T>(samples: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut runs: Vec<(f64, T)> = (0..samples)
        .map(|_| {
            let t = Instant::now();
            let out = f();
            (t.elapsed().as_secs_f64() * 1e3, out)
        })
        .collect();
    runs.sort_by(|a, b| a.0.total_cmp(&b.0));
    runs.swap_remove(samples / 2)
}

/// 1024 seeded points of the room at least `clear` from every wall.
fn free_points(floor: &FloorMap, clear: f64) -> Vec<Vector2<f64>> {
    let mut rng = Rng::new(25);
    let mut out = Vec::with_capacity(1024);
    while out.len() < 1024 {
        let p = v(5.0, 3.0) + rng.point(1.0).component_mul(&v(5.0, 3.0));
        if floor.signed_distance(p) >= clear {
            out.push(p);
        }
    }
    out
}

/// One `FloorNavigator::command` on `floor`, µs (the states where the command is refused, if
/// any, are dropped first).
fn command_us(floor: Arc<FloorMap>, points: &[Vector2<f64>]) -> Result<f64, String> {
    let options = Options::default().with_robot(0.005, 0.005);
    let mut nav = FloorNavigator::new(floor, v(9.3, 5.3), Law::kinematic(1.0), options)
        .map_err(|e| format!("the benchmark navigator: {e}"))?;
    let states: Vec<Vector2<f64>> = points
        .iter()
        .copied()
        .filter(|&x| nav.command(x, Vector2::zeros()).is_ok())
        .collect();
    if states.len() < points.len() / 2 {
        return Err(format!(
            "only {} of {} states command",
            states.len(),
            points.len()
        ));
    }
    Ok(median_ns(7, states.len() as f64, || {
        for &x in &states {
            let _ = black_box(nav.command(black_box(x), Vector2::zeros()));
        }
    }) / 1e3)
}

/// Every figure of this module, through `put(name, value)`.
pub fn figures(put: &mut dyn FnMut(&str, f64)) -> Result<(), String> {
    let (outer, holes) = rings();
    let domain = Domain::new(outer.clone(), holes.clone()).map_err(|e| e.to_string())?;
    for n in TARGETS {
        let h = element_length(&domain, n);
        let samples = if n >= 4000 { 3 } else { 5 };
        let (setup, map) = median_ms(samples, || {
            HarmonicMap::new(&domain, &MeshOptions::graded(h))
        });
        let map = map.map_err(|e| e.to_string())?;
        let cost = map.setup_cost();
        put(
            &format!("harmonic_elements_n{n}"),
            map.elements().len() as f64,
        );
        put(&format!("harmonic_setup_ms_n{n}"), setup);
        put(
            &format!("harmonic_mesh_ms_n{n}"),
            cost.mesh.as_secs_f64() * 1e3,
        );
        put(
            &format!("harmonic_assembly_ms_n{n}"),
            cost.assembly.as_secs_f64() * 1e3,
        );
        put(
            &format!("harmonic_lu_ms_n{n}"),
            cost.factor.as_secs_f64() * 1e3,
        );
        put(
            &format!("harmonic_tree_ms_n{n}"),
            cost.far_field.as_secs_f64() * 1e3,
        );
        let (floor_ms, floor) = median_ms(1, || {
            FloorMap::new(outer.clone(), holes.clone(), &FloorOptions::new(h, 0.01))
        });
        let floor = floor.map_err(|e| format!("the benchmark floor: {e}"))?;
        put(&format!("harmonic_floor_ms_n{n}"), floor_ms);
        // The kinematic law's nominal heading: one fast march over W_δ (docs/maths.md §13.3).
        let (geodesic_ms, geodesic) = median_ms(3, || Geodesic::new(&floor, v(9.3, 5.3)));
        put(&format!("harmonic_geodesic_ms_n{n}"), geodesic_ms);
        put(
            &format!("harmonic_geodesic_cell_mm_n{n}"),
            geodesic.cell() * 1e3,
        );
        let points = free_points(&floor, 2.0 * h);
        let direct_map = map
            .clone()
            .with_far_field(None)
            .map_err(|e| e.to_string())?;
        let far_map = map
            .with_far_field(Some(harmonav_harmonic::FAR_FIELD_TOLERANCE))
            .map_err(|e| e.to_string())?;
        // The tree's cost also below FAR_FIELD_MIN_ELEMENTS, where `new` builds none.
        put(
            &format!("harmonic_tree_ms_n{n}"),
            far_map.setup_cost().far_field.as_secs_f64() * 1e3,
        );
        for (name, m) in [("far", &far_map), ("direct", &direct_map)] {
            let ns = median_ns(7, points.len() as f64, || {
                for &x in &points {
                    let _ = black_box(m.eval(black_box(x)));
                }
            });
            put(&format!("harmonic_eval_us_n{n}_{name}"), ns / 1e3);
        }
        let direct_floor = floor
            .clone()
            .with_far_field(None)
            .map_err(|e| e.to_string())?;
        let far_floor = floor
            .with_far_field(Some(harmonav_harmonic::FAR_FIELD_TOLERANCE))
            .map_err(|e| e.to_string())?;
        put(
            &format!("harmonic_command_us_n{n}_far"),
            command_us(Arc::new(far_floor), &points)?,
        );
        put(
            &format!("harmonic_command_us_n{n}_direct"),
            command_us(Arc::new(direct_floor), &points)?,
        );
    }
    Ok(())
}
