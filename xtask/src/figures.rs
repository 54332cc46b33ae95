//! `cargo xtask figures`: the documentation figures, written into `docs/figures/`.
//!
//! `nav-transform.svg`: the mixed-shape star world of the convergence study (left) and its
//! point world (right): a grid drawn in the free space and mapped through `Phi`, the obstacles
//! collapsing to their centres, and a few descent paths in both.

use std::fmt::Write as _;
use std::process::ExitCode;
use std::sync::Arc;

use harmonav_field::Field;
use harmonav_field::descent::{FollowOptions, follow};
use harmonav_transform::random::{self, Kind, Rng};
use nalgebra::Vector2;

const SIZE: f64 = 460.0;

/// A panel mapping the square `[-half, half]²` to `SIZE × SIZE` pixels at offset `dx`.
struct Panel {
    dx: f64,
    half: f64,
}

impl Panel {
    fn px(&self, p: Vector2<f64>) -> (f64, f64) {
        let s = SIZE / (2.0 * self.half);
        (
            self.dx + (p.x + self.half) * s,
            (self.half - p.y) * s + 20.0,
        )
    }

    fn inside(&self, p: Vector2<f64>) -> bool {
        p.x.abs() < self.half && p.y.abs() < self.half
    }

    /// Polylines through `points`, broken where a point is `None` or outside the panel.
    fn path(
        &self,
        svg: &mut String,
        points: impl Iterator<Item = Option<Vector2<f64>>>,
        style: &str,
    ) {
        let mut d = String::new();
        let mut pen = false;
        for p in points {
            match p.filter(|p| self.inside(*p)) {
                Some(p) => {
                    let (x, y) = self.px(p);
                    let _ = write!(d, "{}{x:.1},{y:.1} ", if pen { "L" } else { "M" });
                    pen = true;
                }
                None => pen = false,
            }
        }
        if !d.is_empty() {
            let _ = writeln!(svg, r#"<path d="{d}" {style}/>"#);
        }
    }
}

pub fn run() -> ExitCode {
    match nav_transform_figure() {
        Ok(path) => {
            println!("wrote {path}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("xtask figures: {e}");
            ExitCode::FAILURE
        }
    }
}

fn nav_transform_figure() -> Result<String, String> {
    let mut rng = Rng::new(2);
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let ws = Arc::new(random::workspace(&mut rng, 6, &kinds, Kind::Star, 0.2));
    let field = Field::all_known(ws.clone()).map_err(|e| e.to_string())?;
    let t = field.transform();
    let left = Panel {
        dx: 10.0,
        half: 6.0,
    };
    let right = Panel {
        dx: SIZE + 40.0,
        half: 9.0,
    };
    let mut svg = String::new();
    let width = 2.0 * SIZE + 50.0;
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{}" font-family="sans-serif" font-size="13">"#,
        SIZE + 50.0
    );
    let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
    for panel in [&left, &right] {
        let _ = writeln!(
            svg,
            r##"<rect x="{}" y="20" width="{SIZE}" height="{SIZE}" fill="none" stroke="#999"/>"##,
            panel.dx
        );
    }
    let _ = writeln!(
        svg,
        r#"<text x="{}" y="14">workspace W (k = M + 1 = {})</text>"#,
        left.dx,
        field.k()
    );
    let _ = writeln!(
        svg,
        r#"<text x="{}" y="14">point world Phi(W): obstacles collapse to points, ∂W to infinity</text>"#,
        right.dx
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
    for j in 0..=24 {
        let fixed = -6.0 + 0.5 * j as f64;
        for vertical in [false, true] {
            let style = r##"fill="none" stroke="#4a7ab5" stroke-width="0.6""##;
            left.path(&mut svg, grid(fixed, vertical).map(free), style);
            right.path(
                &mut svg,
                grid(fixed, vertical)
                    .map(|x| free(x).and_then(|x| t.nav_transform(x).ok()).map(|m| m.h)),
                style,
            );
        }
    }
    // Boundary and obstacles.
    let outline = |f: &dyn Fn(f64) -> Vector2<f64>| {
        (0..=720)
            .map(move |i| Some(f(std::f64::consts::TAU * i as f64 / 720.0)))
            .collect::<Vec<_>>()
    };
    left.path(
        &mut svg,
        outline(&|th| ws.boundary().boundary_point(th)).into_iter(),
        r#"fill="none" stroke="black" stroke-width="1.5""#,
    );
    for (i, o) in ws.obstacles().iter().enumerate() {
        left.path(
            &mut svg,
            outline(&|th| o.boundary_point(th)).into_iter(),
            r##"fill="#bbb" stroke="black" stroke-width="1""##,
        );
        for (panel, p) in [(&left, o.centre()), (&right, o.centre())] {
            let (x, y) = panel.px(p);
            let _ = writeln!(
                svg,
                r#"<circle cx="{x:.1}" cy="{y:.1}" r="3" fill="black"/><text x="{:.1}" y="{:.1}">O{}</text>"#,
                x + 4.0,
                y - 4.0,
                i + 1
            );
        }
    }
    // Descent paths from a few starts.
    for s in 0..6 {
        let start = random::free_point(&mut Rng::new(100 + s), &ws, 0.05);
        let mut pts = vec![start];
        let mut x = start;
        let options = FollowOptions {
            max_step: 0.02,
            ..FollowOptions::default()
        };
        for _ in 0..2000 {
            let d = follow(
                &field,
                x,
                &FollowOptions {
                    max_time: 0.05,
                    ..options
                },
            );
            x = d.end;
            pts.push(x);
            if (x - ws.destination()).norm() < 1e-2 {
                break;
            }
        }
        let style = r##"fill="none" stroke="#d9480f" stroke-width="1.4""##;
        left.path(&mut svg, pts.iter().map(|&p| Some(p)), style);
        right.path(
            &mut svg,
            pts.iter().map(|&p| t.nav_transform(p).ok().map(|m| m.h)),
            style,
        );
    }
    for panel in [&left, &right] {
        let (x, y) = panel.px(ws.destination());
        let _ = writeln!(
            svg,
            r##"<circle cx="{x:.1}" cy="{y:.1}" r="5" fill="#2b8a3e"/><text x="{:.1}" y="{:.1}">goal</text>"##,
            x + 6.0,
            y + 14.0
        );
    }
    let _ = writeln!(svg, "</svg>");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/figures");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let path = dir.join("nav-transform.svg");
    // Write to a temporary file first so that a failure never leaves half a figure.
    let tmp = path.with_extension("svg.tmp");
    std::fs::write(&tmp, svg).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, &path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok("docs/figures/nav-transform.svg".to_string())
}
