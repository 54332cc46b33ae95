//! The run figures: the trajectory (like the paper's figures) and, for dynamic runs, the
//! speed against time with the bound `√(2μ/m)`.

use std::f64::consts::TAU;

use harmonav_sensing::Sensing;
use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::run::Run;
use crate::scenario::Prepared;
use crate::svg::{Canvas, Panel};

fn outline(shape: &StarShape) -> impl Iterator<Item = Vector2<f64>> + '_ {
    (0..360).map(move |i| shape.boundary_point(TAU * i as f64 / 360.0))
}

/// The sector `S_{r,θ}` at `pole` along `axis` as a closed polygon.
fn sector_polygon(
    pole: Vector2<f64>,
    axis: Vector2<f64>,
    range: f64,
    aperture: f64,
) -> Vec<Vector2<f64>> {
    let a0 = axis.y.atan2(axis.x);
    let mut pts = if aperture < TAU {
        vec![pole]
    } else {
        Vec::new()
    };
    for i in 0..=48 {
        let a = a0 - 0.5 * aperture + aperture * i as f64 / 48.0;
        pts.push(pole + range * Vector2::new(a.cos(), a.sin()));
    }
    pts
}

/// `trajectory.svg`: boundary, obstacles labelled (grey until discovered, then red outline),
/// the path, the sector at the start, at each discovery and at the end, start and goal.
pub fn trajectory_svg(prepared: &Prepared, run: &Run) -> String {
    let b = &prepared.truth.boundary;
    let (_, r) = b.radius_bounds();
    let c = b.centre();
    let margin = 0.05 * r;
    let window = (
        c - Vector2::new(r + margin, r + margin),
        c + Vector2::new(r + margin, r + margin),
    );
    let panel = Panel {
        left: 10.0,
        top: 30.0,
        size: (620.0, 620.0),
        window,
    };
    let mut svg = Canvas::new(640.0, 660.0);
    let s = &run.summary;
    svg.text(
        10.0,
        18.0,
        &format!(
            "{} — {:?} model, {} ({:.2} s)",
            s.name,
            s.model,
            if s.reached {
                "goal reached"
            } else {
                "goal NOT reached"
            },
            s.time_s
        ),
        "font-weight=\"bold\"",
    );
    svg.polygon(
        &panel,
        outline(b),
        r##"fill="#fafafa" stroke="black" stroke-width="1.5""##,
    );
    for (i, o) in prepared.truth.obstacles.iter().enumerate() {
        let discovered = s.discoveries.iter().any(|d| d.index == i);
        let style = if discovered {
            r##"fill="#f1c0c0" stroke="#b02020" stroke-width="1.2""##
        } else {
            r##"fill="#d0d0d0" stroke="#666" stroke-width="1""##
        };
        svg.polygon(&panel, outline(o), style);
        svg.label(&panel, o.centre(), (-6.0, 4.0), &prepared.truth.names[i]);
    }
    if let Sensing::Sector(sector) = prepared.truth.sensing {
        let style = r##"fill="#3b7dd8" fill-opacity="0.15" stroke="#3b7dd8" stroke-width="0.8""##;
        let mut poses: Vec<(Vector2<f64>, Vector2<f64>)> = Vec::new();
        // At the start: along the initial motion.
        if let Some(w) = run.samples.windows(2).find(|w| w[0].x != w[1].x) {
            let (a, b2) = (
                Vector2::new(w[0].x[0], w[0].x[1]),
                Vector2::new(w[1].x[0], w[1].x[1]),
            );
            poses.push((
                Vector2::new(run.samples[0].x[0], run.samples[0].x[1]),
                (b2 - a).normalize(),
            ));
        }
        for d in &s.discoveries {
            let a = Vector2::new(d.axis[0], d.axis[1]);
            if a.norm() > 0.0 {
                poses.push((Vector2::new(d.position[0], d.position[1]), a));
            }
        }
        if let [.., p, q] = run.samples.as_slice() {
            let (a, b2) = (Vector2::new(p.x[0], p.x[1]), Vector2::new(q.x[0], q.x[1]));
            if (b2 - a).norm() > 0.0 {
                poses.push((b2, (b2 - a).normalize()));
            }
        }
        for (pole, axis) in poses {
            svg.polygon(
                &panel,
                sector_polygon(pole, axis, sector.range(), sector.aperture()),
                style,
            );
        }
    }
    svg.path(
        &panel,
        run.samples
            .iter()
            .map(|s| Some(Vector2::new(s.x[0], s.x[1]))),
        r##"fill="none" stroke="#d9480f" stroke-width="1.8""##,
    );
    let start = Vector2::new(
        prepared.scenario.robot.start[0],
        prepared.scenario.robot.start[1],
    );
    svg.dot(&panel, start, 4.0, "#1c7ed6");
    svg.label(&panel, start, (6.0, -6.0), "start");
    let goal = prepared.truth.workspace.destination();
    svg.dot(&panel, goal, 5.0, "#2b8a3e");
    svg.label(&panel, goal, (6.0, 14.0), "goal");
    for d in &s.discoveries {
        let p = Vector2::new(d.position[0], d.position[1]);
        svg.dot(&panel, p, 2.5, "#b02020");
    }
    svg.finish()
}

/// `speed.svg` (dynamic runs): `|ẋ|` against time with the bound `√(2μ/m)`, the discovery
/// instants, and shaded the intervals in which a discovery lifted `V` to `μ` and the damping
/// switched to `(m/d_min)|ẋ(T_n)|` (eq. `dissipationfun`).
pub fn speed_svg(run: &Run) -> String {
    let s = &run.summary;
    let bound = s.speed_bound.unwrap_or(1.0);
    let t_max = run.samples.last().map_or(1.0, |s| s.t).max(1e-9);
    let top = 1.1 * bound;
    let panel = Panel {
        left: 60.0,
        top: 30.0,
        size: (560.0, 300.0),
        window: (Vector2::new(0.0, 0.0), Vector2::new(t_max, top)),
    };
    let mut svg = Canvas::new(640.0, 370.0);
    svg.text(
        60.0,
        18.0,
        &format!(
            "speed of {} — max {:.3} m/s, bound √(2μ/m) = {:.3} m/s",
            s.name, s.max_speed, bound
        ),
        "font-weight=\"bold\"",
    );
    svg.raw(r##"<rect x="60" y="30" width="560" height="300" fill="none" stroke="#999"/>"##);
    let bound_line = [
        Some(Vector2::new(0.0, bound)),
        Some(Vector2::new(t_max, bound)),
    ];
    svg.path(
        &panel,
        bound_line,
        r##"fill="none" stroke="#c92a2a" stroke-dasharray="6 4" stroke-width="1.2""##,
    );
    svg.label(
        &panel,
        Vector2::new(0.0, bound),
        (4.0, -4.0),
        "bound √(2μ/m)",
    );
    // The switched intervals: from each recorded sample with λ switched to the next sample.
    let mut labelled = false;
    for w in run.samples.windows(2) {
        if w[0].lambda.is_none() || w[0].critical {
            continue;
        }
        let (x0, _) = panel.px(Vector2::new(w[0].t, top));
        // At least 2 px wide: the switch often lasts a few milliseconds.
        let x1 = panel.px(Vector2::new(w[1].t, top)).0.max(x0 + 2.0);
        svg.raw(&format!(
            r##"<rect x="{x0:.2}" y="30" width="{:.2}" height="300" fill="#f59f00" fill-opacity="0.35"/>"##,
            x1 - x0
        ));
        if !labelled {
            svg.text(x1 + 3.0, 326.0, "λ switched (V ≥ μ)", r##"fill="#e67700""##);
            labelled = true;
        }
    }
    // Labels of discoveries closer than 30 px to the previous one drop a line.
    let mut previous: Option<(f64, f64)> = None;
    for d in &s.discoveries {
        let x = panel.px(Vector2::new(d.time_s, top)).0;
        let dy = match previous {
            Some((px, pdy)) if x - px < 30.0 => pdy + 12.0,
            _ => 12.0,
        };
        previous = Some((x, dy));
        svg.path(
            &panel,
            [
                Some(Vector2::new(d.time_s, 0.0)),
                Some(Vector2::new(d.time_s, top)),
            ],
            r##"stroke="#aaa" stroke-width="0.8""##,
        );
        svg.label(&panel, Vector2::new(d.time_s, top), (2.0, dy), &d.obstacle);
    }
    svg.path(
        &panel,
        run.samples
            .iter()
            .map(|s| Some(Vector2::new(s.t, Vector2::new(s.v[0], s.v[1]).norm()))),
        r##"fill="none" stroke="#1c7ed6" stroke-width="1.5""##,
    );
    for i in 0..=4 {
        let v = top * i as f64 / 4.0;
        let (x, y) = panel.px(Vector2::new(0.0, v));
        svg.text(x - 50.0, y + 4.0, &format!("{v:.2}"), "");
        let t = t_max * i as f64 / 4.0;
        let (x, y) = panel.px(Vector2::new(t, 0.0));
        let anchor = match i {
            0 => "start",
            4 => "end",
            _ => "middle",
        };
        svg.text(
            x,
            y + 16.0,
            &format!("{t:.1} s"),
            &format!("text-anchor=\"{anchor}\""),
        );
    }
    svg.finish()
}
