//! `cargo xtask figures`: the documentation figures, written into `docs/figures/`.
//!
//! `nav-transform.svg`: the mixed-shape star world of the convergence study (left) and its
//! point world (right): a grid drawn in the free space and mapped through `Phi`, the obstacles
//! collapsing to their centres, and a few descent paths in both.
//!
//! `nav-transform-levels.svg`: the same world with the level sets of `Θ` (left) and of
//! `sigma∘phi_k` in the point world (right): `Phi` maps the one onto the other.
//!
//! `harmonic-map.svg`: the U-trap floor plan (`scenarios/floorplans/u-trap.toml`) and its image
//! under the harmonic map `H` in the unit disk (docs/maths.md §11, §13): a grid drawn in the
//! certified region `W_δ`, the U collapsing to its puncture, and the kinematic robot's path
//! from the file's start under both headings (§13.3), the walls only.
//!
//! `paper-kinematic.svg`, `paper-dynamic.svg`, `paper-dynamic-speed.svg` and
//! `paper-dynamic-energy.svg`: the runs of `scenarios/paper/` (the two studies of the paper,
//! `docs/reproduction.md`), drawn by harmonav-sim's own figures.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use harmonav_field::Field;
use harmonav_field::descent::{FollowOptions, follow};
use harmonav_output::atomic::write_atomically;
use harmonav_output::canvas::Scale;
use harmonav_output::drawing::{outline, ring, xy};
use harmonav_output::figures::{
    LEVELS, Plane, draw_level_lines, draw_path, energy_svg, err, plane, speed_svg, trajectory_svg,
};
use harmonav_output::levels::ThetaGrid;
use harmonav_scenario::Scenario;
use harmonav_sim::run::run as run_scenario;
use harmonav_transform::Workspace;
use harmonav_transform::random::{self, Kind, Rng};
use nalgebra::Vector2;
use plotters::prelude::*;

pub fn run() -> ExitCode {
    let mut code = ExitCode::SUCCESS;
    for result in [
        nav_transform_figures(),
        harmonic_map_figure(),
        paper_figures(),
    ] {
        match result {
            Ok(paths) => paths.iter().for_each(|p| println!("wrote {p}")),
            Err(e) => {
                eprintln!("xtask figures: {e}");
                code = ExitCode::FAILURE;
            }
        }
    }
    code
}

fn figures_dir() -> Result<PathBuf, String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/figures");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    Ok(dir)
}

/// Writes `docs/figures/NAME` and returns the path as shown to the user.
fn write_figure(name: &str, svg: &str) -> Result<String, String> {
    let path = figures_dir()?.join(name);
    write_atomically(&path, svg.as_bytes()).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(format!("docs/figures/{name}"))
}

/// The trajectories of the two paper studies and the speed of the dynamic one.
fn paper_figures() -> Result<Vec<String>, String> {
    let mut written = Vec::new();
    for study in ["kinematic", "dynamic"] {
        let file =
            Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenarios/paper/{study}.toml"));
        let prepared = Scenario::load(&file).map_err(|e| e.to_string())?;
        let run = run_scenario(&prepared, None).map_err(|e| format!("{}: {e}", file.display()))?;
        written.push(write_figure(
            &format!("paper-{study}.svg"),
            &trajectory_svg(&prepared, &run)?,
        )?);
        if study == "dynamic" {
            written.push(write_figure("paper-dynamic-speed.svg", &speed_svg(&run)?)?);
            written.push(write_figure(
                "paper-dynamic-energy.svg",
                &energy_svg(&run)?,
            )?);
        }
    }
    Ok(written)
}

/// The world of the figures: six mixed obstacles in a star-shaped workspace (seed 2).
fn figure_world() -> Result<(Arc<Workspace>, Field), String> {
    let mut rng = Rng::new(2);
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let ws = Arc::new(random::workspace(&mut rng, 6, &kinds, Kind::Star, 0.2));
    let field = Field::all_known(ws.clone()).map_err(|e| e.to_string())?;
    Ok((ws, field))
}

/// Two square panels side by side: the workspace `[−6, 6]²` and the point world `[−9, 9]²`.
fn two_panels(
    out: &mut String,
    titles: [&str; 2],
    draw: impl FnOnce(&mut Plane<'_, '_>, &mut Plane<'_, '_>) -> Result<(), String>,
) -> Result<(), String> {
    let root = SVGBackend::with_string(out, (1000, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let (l, r) = root.split_horizontally(500);
    let mut left = plane(&l, titles[0], Vector2::zeros(), 6.0, Scale::ONE)?;
    let mut right = plane(&r, titles[1], Vector2::zeros(), 9.0, Scale::ONE)?;
    draw(&mut left, &mut right)?;
    root.present().map_err(err)
}

/// The obstacle points (labelled) and the goal.
fn mark_points(panel: &mut Plane<'_, '_>, ws: &Workspace) -> Result<(), String> {
    for (i, o) in ws.obstacles().iter().enumerate() {
        let c = o.centre();
        panel
            .draw_series([Circle::new(xy(c), 3, BLACK.filled())])
            .map_err(err)?;
        panel
            .draw_series(std::iter::once(Text::new(
                format!("O{}", i + 1),
                (c.x + 0.25, c.y + 0.25),
                ("sans-serif", 12),
            )))
            .map_err(err)?;
    }
    panel
        .draw_series([Circle::new(
            xy(ws.destination()),
            5,
            RGBColor(43, 138, 62).filled(),
        )])
        .map_err(err)?;
    Ok(())
}

/// The boundary and the obstacles (filled) in the workspace panel, the points in both.
fn draw_world(
    left: &mut Plane<'_, '_>,
    right: &mut Plane<'_, '_>,
    ws: &Workspace,
) -> Result<(), String> {
    draw_path(left, outline(ws.boundary()), BLACK.stroke_width(2))?;
    for o in ws.obstacles() {
        left.draw_series(std::iter::once(Polygon::new(
            outline(o),
            RGBColor(187, 187, 187).filled(),
        )))
        .map_err(err)?;
        draw_path(left, outline(o), BLACK.stroke_width(1))?;
    }
    mark_points(left, ws)?;
    mark_points(right, ws)
}

/// Appends to `out` the runs of at least two consecutive points of `line` where `free` holds
/// (a grid line cut by the obstacles).
fn free_runs(
    line: impl Iterator<Item = Vector2<f64>>,
    free: impl Fn(Vector2<f64>) -> bool,
    out: &mut Vec<Vec<Vector2<f64>>>,
) {
    let mut run: Vec<Vector2<f64>> = Vec::new();
    for x in line {
        if free(x) {
            run.push(x);
        } else if run.len() > 1 {
            out.push(std::mem::take(&mut run));
        } else {
            run.clear();
        }
    }
    if run.len() > 1 {
        out.push(run);
    }
}

fn nav_transform_figures() -> Result<Vec<String>, String> {
    let (ws, field) = figure_world()?;
    let t = field.transform();
    let blue = RGBColor(74, 122, 181);
    let orange = RGBColor(217, 72, 15);
    // Grid lines in the free space, as runs of consecutive free points.
    let free = |x: Vector2<f64>| ws.check_free(x, "grid").is_ok();
    let mut grid_lines: Vec<Vec<Vector2<f64>>> = Vec::new();
    for j in 0..=24 {
        let fixed = -6.0 + 0.5 * j as f64;
        for vertical in [false, true] {
            let line = (0..=400).map(|i| {
                let s = -6.0 + 12.0 * i as f64 / 400.0;
                if vertical {
                    Vector2::new(fixed, s)
                } else {
                    Vector2::new(s, fixed)
                }
            });
            free_runs(line, free, &mut grid_lines);
        }
    }
    let image = |pts: &[Vector2<f64>]| -> Vec<(f64, f64)> {
        pts.iter()
            .filter_map(|&x| t.nav_transform(x).ok())
            .map(|m| xy(m.h))
            .collect()
    };
    // Descent paths from a few starts.
    let mut paths: Vec<Vec<Vector2<f64>>> = Vec::new();
    for s in 0..6 {
        let start = random::free_point(&mut Rng::new(100 + s), &ws, 0.05);
        let mut pts = vec![start];
        let mut x = start;
        let options = FollowOptions {
            max_step: 0.02,
            max_time: 0.05,
            ..FollowOptions::default()
        };
        for _ in 0..2000 {
            x = follow(&field, x, &options).end;
            pts.push(x);
            if (x - ws.destination()).norm() < 1e-2 {
                break;
            }
        }
        paths.push(pts);
    }
    let mut grid_svg = String::new();
    let titles = [
        format!("workspace W (k = {})", field.k()),
        "point world Φ(W): obstacles collapse to points".to_string(),
    ];
    two_panels(&mut grid_svg, [&titles[0], &titles[1]], |left, right| {
        for l in &grid_lines {
            draw_path(
                left,
                l.iter().map(|&p| xy(p)).collect::<Vec<_>>(),
                blue.stroke_width(1),
            )?;
            draw_path(right, image(l), blue.stroke_width(1))?;
        }
        draw_world(left, right, &ws)?;
        for p in &paths {
            draw_path(
                left,
                p.iter().map(|&x| xy(x)).collect::<Vec<_>>(),
                orange.stroke_width(2),
            )?;
            draw_path(right, image(p), orange.stroke_width(2))?;
        }
        Ok(())
    })?;
    // The level sets of Θ, and of sigma∘phi_k in the point world.
    let theta = ThetaGrid::sample(&field, Vector2::zeros(), 6.0, 300).map_err(|e| e.to_string())?;
    let world = field.point_world();
    let varphi = ThetaGrid::from_fn(Vector2::zeros(), 9.0, 300, |h| Some(world.varphi(h)));
    let mut levels_svg = String::new();
    two_panels(
        &mut levels_svg,
        [
            "level sets of Θ in W",
            "level sets of σ∘φ_k in the point world",
        ],
        |left, right| {
            draw_level_lines(left, &theta.level_lines(&LEVELS), Scale::ONE)?;
            draw_level_lines(right, &varphi.level_lines(&LEVELS), Scale::ONE)?;
            draw_world(left, right, &ws)
        },
    )?;
    Ok(vec![
        write_figure("nav-transform.svg", &grid_svg)?,
        write_figure("nav-transform-levels.svg", &levels_svg)?,
    ])
}

/// The kinematic robot's path on `floor` from `start` to `goal` at 100 Hz under `heading`
/// (walls only), at most 60 s.
fn floor_path(
    floor: &Arc<harmonav::FloorMap>,
    start: Vector2<f64>,
    goal: Vector2<f64>,
    (radius, margin): (f64, f64),
    heading: harmonav::HeadingPolicy,
) -> Result<Vec<Vector2<f64>>, String> {
    let options = harmonav::Options::default()
        .with_robot(radius, margin)
        .with_heading(heading);
    let mut nav =
        harmonav::FloorNavigator::new(floor.clone(), goal, harmonav::Law::kinematic(1.0), options)
            .map_err(|e| format!("the figure's navigator: {e}"))?;
    let (mut x, mut path) = (start, vec![start]);
    for _ in 0..6000 {
        if (x - goal).norm() < 0.01 {
            break;
        }
        let u = nav
            .command(x, Vector2::zeros())
            .map_err(|e| format!("the figure's path at {x:?}: {e}"))?
            .value;
        x += 0.01 * u;
        path.push(x);
    }
    Ok(path)
}

/// `harmonic-map.svg` (module docs).
fn harmonic_map_figure() -> Result<Vec<String>, String> {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios/floorplans/u-trap.toml");
    let prepared =
        harmonav_scenario::floorplan::FloorScenario::load(&file).map_err(|e| e.to_string())?;
    let floor = prepared.floor.clone();
    let map = floor.map();
    let r = &prepared.scenario.robot;
    let (start, goal) = (Vector2::from(r.start), Vector2::from(r.goal));
    let blue = RGBColor(74, 122, 181);
    let orange = RGBColor(217, 72, 15);
    let purple = RGBColor(112, 72, 160);
    let green = RGBColor(43, 138, 62);
    // Grid lines in W_δ every 0.25 m, as runs of consecutive certified points.
    let (lo, hi) = floor.walls().bounding_box();
    let mut lines: Vec<Vec<Vector2<f64>>> = Vec::new();
    for vertical in [false, true] {
        let (a, b) = if vertical { (lo.x, hi.x) } else { (lo.y, hi.y) };
        let (c, d) = if vertical { (lo.y, hi.y) } else { (lo.x, hi.x) };
        let mut fixed = a + 0.125;
        while fixed < b {
            let line = (0..=600).map(|i| {
                let t = c + (d - c) * f64::from(i) / 600.0;
                if vertical {
                    Vector2::new(fixed, t)
                } else {
                    Vector2::new(t, fixed)
                }
            });
            free_runs(line, |x| floor.clearance(x) >= 0.0, &mut lines);
            fixed += 0.25;
        }
    }
    let image = |pts: &[Vector2<f64>]| -> Vec<(f64, f64)> {
        pts.iter()
            .filter_map(|&x| map.eval(x).ok())
            .map(|m| xy(m.value))
            .collect()
    };
    let radii = (r.radius, r.margin);
    let auto = floor_path(&floor, start, goal, radii, harmonav::HeadingPolicy::Auto)?;
    let paper = floor_path(&floor, start, goal, radii, harmonav::HeadingPolicy::Paper)?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1100, 520)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (l, rt) = root.split_horizontally(600);
        let centre = 0.5 * (lo + hi);
        let half = 0.5 * (hi - lo).max() + 0.2;
        let mut left = plane(
            &l,
            "U-trap: W_δ's grid; start ○, goal ●; heading auto (orange), paper (purple)",
            centre,
            half,
            Scale::ONE,
        )?;
        let mut right = plane(
            &rt,
            "H(W_δ) in the unit disk: the U collapses to a point",
            Vector2::zeros(),
            1.1,
            Scale::ONE,
        )?;
        for line in &lines {
            let pts: Vec<(f64, f64)> = line.iter().map(|&p| xy(p)).collect();
            draw_path(&mut left, pts, blue.stroke_width(1))?;
            draw_path(&mut right, image(line), blue.stroke_width(1))?;
        }
        let walls = floor.walls();
        draw_path(&mut left, ring(walls.outer()), BLACK.stroke_width(2))?;
        for hole in walls.holes() {
            left.draw_series(std::iter::once(Polygon::new(
                ring(hole),
                RGBColor(187, 187, 187).filled(),
            )))
            .map_err(err)?;
            draw_path(&mut left, ring(hole), BLACK.stroke_width(1))?;
        }
        let circle: Vec<(f64, f64)> = (0..=360)
            .map(|i| {
                let a = f64::from(i).to_radians();
                (a.cos(), a.sin())
            })
            .collect();
        draw_path(&mut right, circle, BLACK.stroke_width(2))?;
        for (path, colour) in [(&paper, purple), (&auto, orange)] {
            let pts: Vec<(f64, f64)> = path.iter().map(|&p| xy(p)).collect();
            draw_path(&mut left, pts, colour.stroke_width(2))?;
            draw_path(&mut right, image(path), colour.stroke_width(2))?;
        }
        for (i, &p) in map.punctures().iter().enumerate() {
            right
                .draw_series([Circle::new(xy(p), 4, BLACK.filled())])
                .map_err(err)?;
            right
                .draw_series(std::iter::once(Text::new(
                    format!("hole {}", i + 1),
                    (p.x + 0.04, p.y + 0.04),
                    ("sans-serif", 12),
                )))
                .map_err(err)?;
        }
        let image_of = |x: Vector2<f64>| map.eval(x).map(|m| m.value).map_err(|e| e.to_string());
        let (start_image, goal_image) = (image_of(start)?, image_of(goal)?);
        for (panel, s, g) in [
            (&mut left, start, goal),
            (&mut right, start_image, goal_image),
        ] {
            panel
                .draw_series([Circle::new(xy(s), 5, BLACK.stroke_width(2))])
                .map_err(err)?;
            panel
                .draw_series([Circle::new(xy(g), 5, green.filled())])
                .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok(vec![write_figure("harmonic-map.svg", &svg)?])
}
