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
//! - `harmonic_setup_iterative_ms_n{n}`, `harmonic_iterations_n{n}`: the same map by the
//!   iterative solve (`Solver::Iterative`; median of 3) and its GMRES iterations, both
//!   components: where it overtakes the dense LU (docs/maths/13-harmonic-scaling.md);
//! - `harmonic_eval_us_n{n}_{far,direct}`: one `HarmonicMap::eval` (`H`, `J_H`) at a free point,
//!   through the far field and by the direct sum (`eval_direct`);
//! - `harmonic_floor_ms_n{n}`: one `FloorMap::new` (the same solve, plus `r_δ` over `∂W_δ`);
//! - `harmonic_command_us_n{n}_{far,direct}`: one `FloorNavigator::command` (kinematic law, the
//!   default hold) at a free point, the floor with and without the far field.
//!
//! A building floor (issue 52, route 2; docs/maths/13-harmonic-scaling.md): [`building_pgm`], a
//! seeded synthetic 60 × 60 m floor at 0.05 m/px (1 200 × 1 200 pixels: corridors, rooms behind
//! doors, furniture against the walls and free-standing, pillars, and one-pixel wall noise as a
//! lidar map has), a ROS map with the defaults (`max_element` 0.2 m, clearance 0.25 m).
//! Figures `harmonic_floor60_*`: of `H` alone on the map's free space (`RosMap::free_space`)
//! at `max_element` 0.2 m: `vertices`, `holes`, `elements`, `solve_s` (one `HarmonicMap::new`,
//! the iterative solve), its parts `mesh_s`, `assembly_s` (multipole tree, near matrix,
//! preconditioner), `gmres_s`, `iterations`, `far_field_s`, `solve_residual`, and `peak_mb`
//! (the process's peak resident memory during it, after a reset; target ≤ 1 024); of the whole
//! load (`RosMap::load` + `to_floor_map`): `setup_s` (target ≤ 10 s), `defaults_load` (1 when
//! it loads with the defaults; else 0 and the load is timed at `max_element` = clearance =
//! 0.25 m, where the free space is not shrunk), `setup_elements`; `command_us` (one
//! `FloorNavigator::command`, kinematic law; target ≤ 20).
//! `--only harmonic_floor60` measures these alone.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use harmonav::floorplan::Geodesic;
use harmonav::{FloorMap, FloorNavigator, FloorOptions, Law, Options, Vector2};
use harmonav_harmonic::{Domain, HarmonicMap, MeshOptions, Solver, mesh};
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

/// A seeded synthetic building floor as an 8-bit grey image (row 0 at the top, `0` occupied,
/// `254` free), `side × side` pixels at 0.05 m: a 0.25 m outer wall; two corridors each way
/// (2.4 m wide, a 0.4 m pillar every 6 m); the nine blocks between them cut into
/// rooms of 3.5–7 m by 0.15 m walls, with a 0.9–1.2 m door to a corridor or a neighbour;
/// desks and cabinets, against a wall or free-standing; and one-pixel noise along every
/// wall (each wall pixel next to free space freed with probability 0.12, each free pixel next
/// to a wall filled with 0.08), as a lidar map's walls are ragged.
pub fn building_pgm(seed: u64, side: usize) -> Vec<u8> {
    let mut rng = Rng::new(seed);
    // grid[y][x], y up (row side − 1 − y of the image); true = occupied.
    let mut occ = vec![true; side * side];
    let at = |x: usize, y: usize| y * side + x;
    let px = |m: f64| (m / 0.05).round() as usize;
    let fill = |occ: &mut Vec<bool>, x0: usize, y0: usize, x1: usize, y1: usize, v: bool| {
        for y in y0.min(side)..y1.min(side) {
            for x in x0.min(side)..x1.min(side) {
                occ[y * side + x] = v;
            }
        }
    };
    let wall = px(0.25);
    fill(&mut occ, wall, wall, side - wall, side - wall, false);
    // Corridors at a third and two thirds, 2.4 m wide; blocks between them.
    let w = px(2.4);
    let c1 = side / 3 - w / 2;
    let c2 = 2 * side / 3 - w / 2;
    let cuts = [wall, c1, c1 + w, c2, c2 + w, side - wall];
    let spans = [(cuts[0], cuts[1]), (cuts[2], cuts[3]), (cuts[4], cuts[5])];
    let inner = px(0.15);
    for &(x0, x1) in &spans {
        for &(y0, y1) in &spans {
            // Room boundaries along each axis of the block.
            let split = |rng: &mut Rng, a: usize, b: usize| -> Vec<usize> {
                let mut v = vec![a];
                let mut t = a;
                loop {
                    let step = px(rng.uniform(3.5, 7.0));
                    if t + step + px(3.0) >= b {
                        break;
                    }
                    t += step;
                    v.push(t);
                }
                v.push(b);
                v
            };
            let xs = split(&mut rng, x0, x1);
            let ys = split(&mut rng, y0, y1);
            // Walls: the block's own edges (facing corridors) and between rooms.
            for &x in &xs {
                fill(
                    &mut occ,
                    x.saturating_sub(inner / 2),
                    y0,
                    x + inner - inner / 2,
                    y1,
                    true,
                );
            }
            for &y in &ys {
                fill(
                    &mut occ,
                    x0,
                    y.saturating_sub(inner / 2),
                    x1,
                    y + inner - inner / 2,
                    true,
                );
            }
            // Doors: in each wall segment between rooms with probability 0.6 (in the vertical
            // walls' lowest segments always).
            for &x in &xs {
                for j in 0..ys.len() - 1 {
                    if j == 0 || rng.uniform(0.0, 1.0) < 0.6 {
                        let d = px(rng.uniform(0.9, 1.2));
                        let (ya, yb) = (ys[j] + inner + 2, ys[j + 1].saturating_sub(inner + 2));
                        if yb > ya + d {
                            let y = ya + rng.below(yb - ya - d);
                            fill(
                                &mut occ,
                                x.saturating_sub(inner),
                                y,
                                x + inner,
                                y + d,
                                false,
                            );
                        }
                    }
                }
            }
            for &y in &ys {
                for i in 0..xs.len() - 1 {
                    if rng.uniform(0.0, 1.0) < 0.6 {
                        let d = px(rng.uniform(0.9, 1.2));
                        let (xa, xb) = (xs[i] + inner + 2, xs[i + 1].saturating_sub(inner + 2));
                        if xb > xa + d {
                            let x = xa + rng.below(xb - xa - d);
                            fill(
                                &mut occ,
                                x,
                                y.saturating_sub(inner),
                                x + d,
                                y + inner,
                                false,
                            );
                        }
                    }
                }
            }
            // Furniture: up to three pieces per room, half against a wall.
            for i in 0..xs.len() - 1 {
                for j in 0..ys.len() - 1 {
                    let (rx0, rx1) = (xs[i] + inner, xs[i + 1].saturating_sub(inner));
                    let (ry0, ry1) = (ys[j] + inner, ys[j + 1].saturating_sub(inner));
                    for _ in 0..rng.below(4) {
                        let (fw, fh) = if rng.below(2) == 0 {
                            (px(1.4), px(0.7))
                        } else {
                            (px(0.5), px(1.0))
                        };
                        let margin = px(1.2);
                        if rx1 <= rx0 + fw + 2 * margin || ry1 <= ry0 + fh + 2 * margin {
                            continue;
                        }
                        let against = rng.below(2) == 0;
                        let x = if against && rng.below(2) == 0 {
                            rx0
                        } else {
                            rx0 + margin + rng.below(rx1 - rx0 - fw - 2 * margin)
                        };
                        let y = if against && x != rx0 {
                            ry1 - fh
                        } else {
                            ry0 + margin + rng.below(ry1 - ry0 - fh - 2 * margin)
                        };
                        fill(&mut occ, x, y, x + fw, y + fh, true);
                    }
                }
            }
        }
    }
    // The corridors are free; pillars every 6 m along their middles.
    for &c in &[c1, c2] {
        fill(&mut occ, wall, c, side - wall, c + w, false);
        fill(&mut occ, c, wall, c + w, side - wall, false);
    }
    let pillar = px(0.4);
    for &c in &[c1, c2] {
        let mut t = px(3.0);
        while t + pillar < side - wall {
            let mid = c + w / 2 - pillar / 2;
            let crossing = |t: usize| [c1, c2].iter().any(|&d| t + pillar > d && t < d + w);
            if !crossing(t) {
                fill(&mut occ, t, mid, t + pillar, mid + pillar, true);
                fill(&mut occ, mid, t, mid + pillar, t + pillar, true);
            }
            t += px(6.0);
        }
    }
    // One-pixel noise along the walls.
    let before = occ.clone();
    for y in 1..side - 1 {
        for x in 1..side - 1 {
            let next = [at(x + 1, y), at(x - 1, y), at(x, y + 1), at(x, y - 1)];
            let here = before[at(x, y)];
            if next.iter().any(|&k| before[k] != here) {
                let p = if here { 0.12 } else { 0.08 };
                if rng.uniform(0.0, 1.0) < p {
                    occ[at(x, y)] = !here;
                }
            }
        }
    }
    let mut image = Vec::with_capacity(side * side);
    for row in 0..side {
        let y = side - 1 - row;
        image.extend((0..side).map(|x| if occ[at(x, y)] { 0u8 } else { 254u8 }));
    }
    image
}

/// The process's peak resident memory (`VmHWM`), MB; `None` where `/proc` has none.
fn peak_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// The `harmonic_floor60_*` figures of the module docs.
fn building_figures(put: &mut dyn FnMut(&str, f64)) -> Result<(), String> {
    use harmonav::floorplan::{MapOptions, RosMap};
    let side = 1200;
    let dir = std::env::temp_dir().join(format!("harmonav-bench-floor60-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let mut pgm = format!("P5\n{side} {side}\n255\n").into_bytes();
    pgm.extend(building_pgm(52, side));
    std::fs::write(dir.join("floor60.pgm"), pgm).map_err(|e| e.to_string())?;
    let yaml = dir.join("floor60.yaml");
    std::fs::write(
        &yaml,
        "image: floor60.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n\
         occupied_thresh: 0.65\nfree_thresh: 0.196\n",
    )
    .map_err(|e| e.to_string())?;
    // The corridors' middles (y = 20 m and 40 m), between pillars.
    let (start, goal) = (v(4.6, 20.0), v(55.4, 40.0));
    let options = MapOptions::new(FloorOptions::new(0.2, 0.25));
    let map = RosMap::load(&yaml).map_err(|e| e.to_string())?;
    // H alone on the map's free space at the default element length (0.2 m): what the solve
    // costs, whatever the rest of the pipeline does.
    let space = map
        .free_space(start, goal, &options)
        .map_err(|e| format!("the 60 m floor's free space: {e}"))?;
    let ccw = |ring: &[Vector2<f64>]| {
        let n = ring.len();
        (0..n)
            .map(|i| ring[i].perp(&ring[(i + 1) % n]))
            .sum::<f64>()
            > 0.0
    };
    let oriented = |mut ring: Vec<Vector2<f64>>, outer: bool| {
        if ccw(&ring) != outer {
            ring.reverse();
        }
        ring
    };
    let domain = Domain::new(
        oriented(space.outer, true),
        space
            .holes
            .into_iter()
            .map(|r| oriented(r, false))
            .collect(),
    )
    .map_err(|e| format!("the 60 m floor's domain: {e}"))?;
    let vertices = domain.outer().len() + domain.holes().iter().map(Vec::len).sum::<usize>();
    put("harmonic_floor60_vertices", vertices as f64);
    put("harmonic_floor60_holes", domain.holes().len() as f64);
    // Reset the peak (Linux: `5` to clear_refs resets VmHWM) so that it is this solve's.
    let _ = std::fs::write("/proc/self/clear_refs", "5");
    let clock = Instant::now();
    let h = HarmonicMap::new(&domain, &MeshOptions::graded(0.2))
        .map_err(|e| format!("the 60 m floor's harmonic map: {e}"))?;
    put("harmonic_floor60_solve_s", clock.elapsed().as_secs_f64());
    if let Some(mb) = peak_mb() {
        put("harmonic_floor60_peak_mb", mb);
    }
    let cost = h.setup_cost();
    put("harmonic_floor60_elements", h.elements().len() as f64);
    put("harmonic_floor60_mesh_s", cost.mesh.as_secs_f64());
    put("harmonic_floor60_assembly_s", cost.assembly.as_secs_f64());
    put("harmonic_floor60_gmres_s", cost.factor.as_secs_f64());
    put("harmonic_floor60_iterations", cost.iterations as f64);
    put("harmonic_floor60_far_field_s", cost.far_field.as_secs_f64());
    put("harmonic_floor60_solve_residual", h.solve_residual());
    drop(h);
    // The whole load with the defaults; where the pipeline refuses it (the shrink by
    // clearance − δ can make holes touch, issue 52), with δ = clearance = 0.25 m (no shrink).
    let clock = Instant::now();
    let (floor, defaults) = match RosMap::load(&yaml)
        .map_err(|e| e.to_string())?
        .to_floor_map(start, goal, &options)
    {
        Ok(floor) => (floor, true),
        Err(e) => {
            eprintln!("xtask bench: the 60 m floor with the defaults: {e}");
            let options = MapOptions::new(FloorOptions::new(0.25, 0.25));
            let floor = RosMap::load(&yaml)
                .map_err(|e| e.to_string())?
                .to_floor_map(start, goal, &options)
                .map_err(|e| format!("the 60 m floor at max_element = 0.25: {e}"))?;
            (floor, false)
        }
    };
    put("harmonic_floor60_setup_s", clock.elapsed().as_secs_f64());
    put(
        "harmonic_floor60_defaults_load",
        f64::from(u8::from(defaults)),
    );
    put(
        "harmonic_floor60_setup_elements",
        floor.map().elements().len() as f64,
    );
    let floor = Arc::new(floor);
    let options = Options::default().with_robot(0.2, 0.05);
    let mut nav = FloorNavigator::new(floor.clone(), goal, Law::kinematic(0.5), options)
        .map_err(|e| format!("the 60 m floor's navigator: {e}"))?;
    let mut rng = Rng::new(52);
    let mut states = Vec::new();
    while states.len() < 256 {
        let p = v(rng.uniform(1.0, 59.0), rng.uniform(1.0, 59.0));
        if floor.signed_distance(p) >= 0.5 && nav.command(p, Vector2::zeros()).is_ok() {
            states.push(p);
        }
    }
    put(
        "harmonic_floor60_command_us",
        median_ns(7, states.len() as f64, || {
            for &x in &states {
                let _ = black_box(nav.command(black_box(x), Vector2::zeros()));
            }
        }) / 1e3,
    );
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

/// Every figure of this module, through `put(name, value)`.
pub fn figures(put: &mut dyn FnMut(&str, f64)) -> Result<(), String> {
    // `--only harmonic_floor60…` skips the element sweep below (minutes).
    let only = std::env::args()
        .skip_while(|a| a != "--only")
        .nth(1)
        .unwrap_or_default();
    if only.is_empty()
        || "harmonic_floor60".starts_with(&only)
        || only.starts_with("harmonic_floor60")
    {
        building_figures(put)?;
    }
    if only.starts_with("harmonic_floor60") {
        return Ok(());
    }
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
        // The same map by the iterative solve, whatever N: the crossover with the dense LU.
        let (iterative, it_map) = median_ms(3, || {
            HarmonicMap::new_with(&domain, &MeshOptions::graded(h), Solver::Iterative)
        });
        let it_map = it_map.map_err(|e| e.to_string())?;
        put(&format!("harmonic_setup_iterative_ms_n{n}"), iterative);
        put(
            &format!("harmonic_iterations_n{n}"),
            it_map.setup_cost().iterations as f64,
        );
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
