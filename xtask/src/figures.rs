//! `cargo xtask figures`: the documentation figures, written into `docs/figures/`.
//!
//! `nav-transform.svg`: the mixed-shape star world of the convergence study (left) and its
//! point world (right): a grid drawn in the free space and mapped through `Phi`, the obstacles
//! collapsing to their centres, and a few descent paths in both.
//!
//! `paper-kinematic.svg`, `paper-dynamic.svg` and `paper-dynamic-speed.svg`: the runs of
//! `scenarios/paper/` (the two studies of the paper, `docs/reproduction.md`), drawn by
//! harmonav-sim's own figures.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use harmonav_field::Field;
use harmonav_field::descent::{FollowOptions, follow};
use harmonav_sim::atomic::write_atomically;
use harmonav_sim::figures::{speed_svg, trajectory_svg};
use harmonav_sim::run::run as run_scenario;
use harmonav_sim::scenario::Scenario;
use harmonav_sim::svg::{Canvas, Panel};
use harmonav_transform::random::{self, Kind, Rng};
use nalgebra::Vector2;

const SIZE: f64 = 460.0;

/// A square panel of `SIZE` pixels showing `[-half, half]²`, `dx` pixels from the left.
fn panel(dx: f64, half: f64) -> Panel {
    Panel {
        left: dx,
        top: 20.0,
        size: (SIZE, SIZE),
        window: (Vector2::new(-half, -half), Vector2::new(half, half)),
    }
}

pub fn run() -> ExitCode {
    let mut code = ExitCode::SUCCESS;
    for result in [nav_transform_figure(), paper_figures()] {
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
            &trajectory_svg(&prepared, &run),
        )?);
        if study == "dynamic" {
            written.push(write_figure("paper-dynamic-speed.svg", &speed_svg(&run))?);
        }
    }
    Ok(written)
}

fn nav_transform_figure() -> Result<Vec<String>, String> {
    let mut rng = Rng::new(2);
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let ws = Arc::new(random::workspace(&mut rng, 6, &kinds, Kind::Star, 0.2));
    let field = Field::all_known(ws.clone()).map_err(|e| e.to_string())?;
    let t = field.transform();
    let (left, right) = (panel(10.0, 6.0), panel(SIZE + 40.0, 9.0));
    let mut svg = Canvas::new(2.0 * SIZE + 50.0, SIZE + 50.0);
    for p in [&left, &right] {
        svg.raw(&format!(
            r##"<rect x="{}" y="20" width="{SIZE}" height="{SIZE}" fill="none" stroke="#999"/>"##,
            p.left
        ));
    }
    svg.text(
        left.left,
        14.0,
        &format!("workspace W (k = M + 1 = {})", field.k()),
        "",
    );
    svg.text(
        right.left,
        14.0,
        "point world Phi(W): obstacles collapse to points, ∂W to infinity",
        "",
    );
    // Grid lines in the free space, and their images.
    let grid = |fixed: f64, vertical: bool| {
        (0..=400).map(move |i| {
            let s = -6.0 + 12.0 * i as f64 / 400.0;
            if vertical {
                Vector2::new(fixed, s)
            } else {
                Vector2::new(s, fixed)
            }
        })
    };
    let free = |x: Vector2<f64>| ws.check_free(x, "grid").ok().map(|_| x);
    let style = r##"fill="none" stroke="#4a7ab5" stroke-width="0.6""##;
    for j in 0..=24 {
        let fixed = -6.0 + 0.5 * j as f64;
        for vertical in [false, true] {
            svg.path(&left, grid(fixed, vertical).map(free), style);
            svg.path(
                &right,
                grid(fixed, vertical)
                    .map(|x| free(x).and_then(|x| t.nav_transform(x).ok()).map(|m| m.h)),
                style,
            );
        }
    }
    // Boundary and obstacles.
    let outline = |shape: &harmonav_transform::StarShape| {
        (0..=720)
            .map(|i| Some(shape.boundary_point(std::f64::consts::TAU * i as f64 / 720.0)))
            .collect::<Vec<_>>()
    };
    svg.path(
        &left,
        outline(ws.boundary()),
        r#"fill="none" stroke="black" stroke-width="1.5""#,
    );
    for (i, o) in ws.obstacles().iter().enumerate() {
        svg.path(
            &left,
            outline(o),
            r##"fill="#bbb" stroke="black" stroke-width="1""##,
        );
        for p in [&left, &right] {
            svg.dot(p, o.centre(), 3.0, "black");
            svg.label(p, o.centre(), (4.0, -4.0), &format!("O{}", i + 1));
        }
    }
    // Descent paths from a few starts.
    let style = r##"fill="none" stroke="#d9480f" stroke-width="1.4""##;
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
        svg.path(&left, pts.iter().map(|&p| Some(p)), style);
        svg.path(
            &right,
            pts.iter().map(|&p| t.nav_transform(p).ok().map(|m| m.h)),
            style,
        );
    }
    for p in [&left, &right] {
        svg.dot(p, ws.destination(), 5.0, "#2b8a3e");
        svg.label(p, ws.destination(), (6.0, 14.0), "goal");
    }
    Ok(vec![write_figure("nav-transform.svg", &svg.finish())?])
}
