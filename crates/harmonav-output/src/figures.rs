//! The run figures, drawn with plotters (SVG; text stays text, axes get round ticks):
//!
//! - `trajectory.svg`: the workspace, the obstacles (discovered ones red; named only where a
//!   name overlaps no other, and in worlds of more than [`LABEL_ALL_UP_TO`] only the
//!   discovered), the level sets of `Θ` for the final known world, the sector at each
//!   discovery, the path, start and goal, and a legend strip with the value of each level.
//!   Drawn at [`Scale::FINE`] ([`crate::canvas`]): the path and the level lines keep a
//!   quarter of a pixel, and the level lines' vertices lie on the level sets
//!   ([`ThetaGrid::refined_level_lines`]);
//! - `speed.svg`: `|ẋ|` against time with the bound `√(2μ/m)` and the discoveries marked;
//! - `energy.svg` (dynamic law): `V(t)` and `λ(t)`.

use std::f64::consts::TAU;

use harmonav_field::Field;
use nalgebra::Vector2;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use harmonav_scenario::{Prepared, Sensor};
use harmonav_sim::movers::FleetRobot;
use harmonav_sim::summary::Run;
use harmonav_sim::trace::{Discovery, MoverFrame, Sample};

pub use crate::canvas::err;
use crate::canvas::{Scale, scaled_svg};
use crate::drawing::{outline, xy};
use crate::levels::{LevelLine, ThetaGrid};

/// The levels of `Θ` drawn on the figures (denser towards 1, where the obstacles shape them).
pub const LEVELS: [f64; 9] = [0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 0.97, 0.99, 0.999];

/// Cells per side of the grid the level sets are traced on (their vertices are then moved
/// onto the level sets: [`ThetaGrid::refined_level_lines`]).
const LEVEL_CELLS: usize = 240;

/// The nominal size of a plane figure's chart, px (the legend strip goes below it).
pub(crate) const CHART: (u32, u32) = (720, 740);

pub(crate) const PATH: RGBColor = RGBColor(217, 72, 15);
const KNOWN: RGBColor = RGBColor(176, 32, 32);
const SECTOR: RGBColor = RGBColor(59, 125, 216);
pub(crate) const GOAL: RGBColor = RGBColor(43, 138, 62);

/// Draws the polyline `points` with `style` on `chart`.
pub fn draw_path(
    chart: &mut Plane<'_, '_>,
    points: Vec<(f64, f64)>,
    style: ShapeStyle,
) -> Result<(), String> {
    chart
        .draw_series(std::iter::once(PathElement::new(points, style)))
        .map(|_| ())
        .map_err(err)
}

/// The fill and stroke of an obstacle: red if the robot discovered it (`known`), grey if not.
fn obstacle_colors(known: bool) -> (RGBColor, RGBColor) {
    if known {
        (RGBColor(241, 192, 192), KNOWN)
    } else {
        (RGBColor(208, 208, 208), RGBColor(102, 102, 102))
    }
}

/// Draws an obstacle, filled: red if the robot discovered it (`known`), grey if not.
pub(crate) fn draw_obstacle(
    chart: &mut Plane<'_, '_>,
    shape: &harmonav_transform::StarShape,
    known: bool,
    s: Scale,
) -> Result<(), String> {
    let (fill, stroke) = obstacle_colors(known);
    chart
        .draw_series(std::iter::once(Polygon::new(outline(shape), fill.filled())))
        .map_err(err)?;
    draw_path(chart, outline(shape), s.stroke(stroke, 1))
}

/// The sector `S_{r,θ}` at `pole` along `axis` as a closed polygon.
fn sector_polygon(
    pole: Vector2<f64>,
    axis: Vector2<f64>,
    range: f64,
    aperture: f64,
) -> Vec<(f64, f64)> {
    let a0 = axis.y.atan2(axis.x);
    let mut pts = if aperture < TAU {
        vec![xy(pole)]
    } else {
        Vec::new()
    };
    for i in 0..=48 {
        let a = a0 - 0.5 * aperture + aperture * i as f64 / 48.0;
        pts.push(xy(pole + range * Vector2::new(a.cos(), a.sin())));
    }
    pts
}

/// A colour from blue (`Θ` near 0) to orange (near 1) for the level lines.
fn level_color(v: f64) -> RGBColor {
    let mix = |a: f64, b: f64| (a + (b - a) * v).round() as u8;
    RGBColor(mix(40.0, 240.0), mix(90.0, 140.0), mix(200.0, 40.0))
}

/// A square chart of the plane `[c − half, c + half]²`.
pub type Plane<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// A square chart of `[c − half, c + half]²` on `area`, with round ticks and axis titles, its
/// margins, fonts, ticks and axes `s` times their nominal size (`area` drawn at `s`).
pub fn plane<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    title: &str,
    c: Vector2<f64>,
    half: f64,
    s: Scale,
) -> Result<Plane<'a, 'b>, String> {
    let mut chart = ChartBuilder::on(area)
        .caption(title, s.font(16))
        .margin(s.px(8))
        .x_label_area_size(s.px(32))
        .y_label_area_size(s.px(40))
        .build_cartesian_2d(c.x - half..c.x + half, c.y - half..c.y + half)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(7)
        .y_labels(7)
        .x_desc("x (m)")
        .y_desc("y (m)")
        .label_style(s.font(12))
        .axis_style(s.stroke(BLACK, 1))
        .set_all_tick_mark_size(s.px(5))
        .draw()
        .map_err(err)?;
    Ok(chart)
}

/// The [`LEVELS`] of `Θ` of `field` over the square `[c − half, c + half]²`, on the level sets.
fn field_levels(field: &Field, c: Vector2<f64>, half: f64) -> Result<Vec<LevelLine>, String> {
    let grid = ThetaGrid::sample(field, c, half, LEVEL_CELLS).map_err(|e| e.to_string())?;
    Ok(grid.refined_level_lines(&LEVELS, |p| field.eval(p).ok().map(|e| e.value)))
}

/// Draws the level lines `levels` (blue near 0, orange near 1), one nominal pixel wide.
pub fn draw_level_lines(
    chart: &mut Plane<'_, '_>,
    levels: &[LevelLine],
    s: Scale,
) -> Result<(), String> {
    for level in levels {
        let style = s.stroke(level_color(level.value), 1);
        chart
            .draw_series(
                level
                    .lines
                    .iter()
                    .map(|l| PathElement::new(l.iter().map(|&p| xy(p)).collect::<Vec<_>>(), style)),
            )
            .map_err(err)?;
    }
    Ok(())
}

/// The points of a line worth drawing: the first, the last, and each one whose pixel differs
/// from the last kept one's (`to_px`: the chart's backend coordinates). The SVG backend
/// draws at whole pixels, so nothing visible is dropped, and a line over 10⁵ states becomes
/// at most a few thousand vertices.
pub(crate) fn drawable(
    points: impl IntoIterator<Item = (f64, f64)>,
    to_px: impl Fn(&(f64, f64)) -> (i32, i32),
) -> Vec<(f64, f64)> {
    let mut kept: Vec<(f64, f64)> = Vec::new();
    let mut last_px = None;
    let mut tail = None;
    for p in points {
        let px = to_px(&p);
        if last_px != Some(px) {
            kept.push(p);
            last_px = Some(px);
            tail = None;
        } else {
            tail = Some(p);
        }
    }
    kept.extend(tail);
    kept
}

/// Draws the path through `points` (one vertex per backend pixel: [`drawable`]), the start
/// and the goal.
pub(crate) fn draw_run(
    chart: &mut Plane<'_, '_>,
    points: impl IntoIterator<Item = (f64, f64)>,
    start: (f64, f64),
    goal: (f64, f64),
    s: Scale,
) -> Result<(), String> {
    let path = drawable(points, |p| chart.backend_coord(p));
    chart
        .draw_series(LineSeries::new(path, s.stroke(PATH, 2)))
        .map_err(err)?;
    chart
        .draw_series([
            Circle::new(start, s.px(5), BLACK.filled()),
            Circle::new(goal, s.px(6), GOAL.filled()),
        ])
        .map_err(err)?;
    Ok(())
}

/// The most heading ticks [`draw_headings`] draws along a path.
const HEADING_TICKS: usize = 40;

/// A differential drive's heading along its path (`[robot] base = "diff"`, the samples'
/// `yaw`): a short tick from the position along `e(θ) = (cos θ, sin θ)` at most
/// [`HEADING_TICKS`] states evenly spaced in the recording, and at the first and the last.
/// Draws nothing for a holonomic robot (no `yaw`).
pub(crate) fn draw_headings(
    chart: &mut Plane<'_, '_>,
    samples: &[Sample],
    s: Scale,
) -> Result<(), String> {
    let posed: Vec<(f64, f64, f64)> = samples
        .iter()
        .filter_map(|p| p.yaw.map(|yaw| (p.x[0], p.x[1], yaw)))
        .collect();
    let Some(&last) = posed.last() else {
        return Ok(());
    };
    let every = posed.len().div_ceil(HEADING_TICKS).max(1);
    // A tick of 12 backend pixels, in world units along the x axis of the plane.
    let (x0, _) = chart.backend_coord(&(0.0, 0.0));
    let (x1, _) = chart.backend_coord(&(1.0, 0.0));
    let per_metre = f64::from((x1 - x0).abs().max(1));
    let length = f64::from(s.px(12)) / per_metre;
    let ticks = posed
        .iter()
        .step_by(every)
        .chain([&last])
        .map(|&(x, y, yaw)| {
            PathElement::new(
                vec![(x, y), (x + length * yaw.cos(), y + length * yaw.sin())],
                s.stroke(BLACK, 1),
            )
        });
    chart.draw_series(ticks).map_err(err)?;
    Ok(())
}

/// Draws each name of `names` centred at its point, in order, where it overlaps no name
/// already drawn ([`place_labels`]).
pub(crate) fn draw_names(
    chart: &mut Plane<'_, '_>,
    names: &[(&str, (f64, f64))],
    s: Scale,
) -> Result<(), String> {
    let style = TextStyle::from(s.font(12)).pos(Pos::new(HPos::Center, VPos::Center));
    let wanted = names
        .iter()
        .enumerate()
        .map(|(k, (name, at))| (k, label_box(chart.backend_coord(at), name, s.px(12))));
    for k in place_labels(wanted, s.px(2)) {
        let (name, at) = names[k];
        chart
            .draw_series(std::iter::once(Text::new(
                name.to_string(),
                at,
                style.clone(),
            )))
            .map_err(err)?;
    }
    Ok(())
}

/// The poses at which the sector is drawn: at each discovery, with its axis.
fn sector_poses(run: &Run) -> Vec<(Vector2<f64>, Vector2<f64>)> {
    run.summary
        .discoveries
        .iter()
        .map(|d| (Vector2::from(d.position), Vector2::from(d.axis)))
        .filter(|(_, a)| a.norm() > 0.0)
        .collect()
}

/// The title of a plane figure: the run's name, law and outcome.
pub(crate) fn run_title(name: &str, model: impl std::fmt::Debug, reached: bool, t: f64) -> String {
    let outcome = if reached {
        "goal reached"
    } else {
        "goal NOT reached"
    };
    format!("{name} — {model:?} law, {outcome} ({t:.2} s)")
}

/// `trajectory.svg` of `run`.
pub fn trajectory_svg(prepared: &Prepared, run: &Run) -> Result<String, String> {
    let truth = &prepared.truth;
    let s = &run.summary;
    let b = &truth.boundary;
    let (c, half) = (b.centre(), 1.04 * b.radius_bounds().1);
    let title = run_title(&s.name, s.model, s.reached, s.time_s);
    let perceived = perceived_at_end(run);
    let known: Vec<usize> = match perceived {
        // A lidar's: the true obstacles a perceived shape holds the centre of.
        Some(p) => (0..truth.obstacles.len())
            .filter(|&i| p.iter().any(|q| q.contains(truth.obstacles[i].centre())))
            .collect(),
        None => s.discoveries.iter().map(|d| d.index).collect(),
    };
    let field = match perceived {
        Some(p) => perceived_field(prepared, p)?,
        None => Field::with_policy(
            truth.workspace.clone(),
            known.iter().copied(),
            prepared.k_policy(),
        )
        .map_err(|e| e.to_string())?,
    };
    let levels = field_levels(&field, c, half)?;
    let sectors = match truth.sensor {
        Sensor::Sector(sector) => sector_poses(run)
            .into_iter()
            .map(|(pole, axis)| sector_polygon(pole, axis, sector.range(), sector.aperture()))
            .collect(),
        _ => Vec::new(),
    };
    let sc = Scale::FINE;
    let extra = if run.mover_frames.is_empty() {
        0
    } else {
        LEGEND_ROW
    };
    scaled_svg((CHART.0, CHART.1 + 60 + extra), sc, |root| {
        let (top, legend) = root.split_vertically(sc.px(CHART.1 as i32));
        let mut chart = plane(&top, &title, c, half, sc)?;
        chart
            .draw_series(std::iter::once(Polygon::new(
                outline(b),
                RGBColor(250, 250, 250).filled(),
            )))
            .map_err(err)?;
        draw_level_lines(&mut chart, &levels, sc)?;
        draw_path(&mut chart, outline(b), sc.stroke(BLACK, 2))?;
        for poly in &sectors {
            chart
                .draw_series([Polygon::new(poly.clone(), SECTOR.mix(0.12).filled())])
                .map_err(err)?;
            draw_path(&mut chart, poly.clone(), sc.stroke(SECTOR.mix(0.6), 1))?;
        }
        for (i, o) in truth.obstacles.iter().enumerate() {
            draw_obstacle(&mut chart, o, known.contains(&i), sc)?;
        }
        for p in perceived.unwrap_or_default() {
            draw_path(&mut chart, outline(p), sc.stroke(PERCEIVED, 2))?;
        }
        let start = run.samples.first().map_or((0.0, 0.0), |p| (p.x[0], p.x[1]));
        let points = run.samples.iter().map(|p| (p.x[0], p.x[1]));
        draw_run(&mut chart, points, start, xy(truth.goal()), sc)?;
        draw_headings(&mut chart, &run.samples, sc)?;
        // The names: the discovered obstacles (every one in a world of at most
        // LABEL_ALL_UP_TO), each only where it overlaps no name already placed.
        let named: Vec<usize> = if truth.obstacles.len() <= LABEL_ALL_UP_TO {
            (0..truth.obstacles.len()).collect()
        } else {
            known.clone()
        };
        let names: Vec<(&str, (f64, f64))> = named
            .iter()
            .map(|&i| (truth.names[i].as_str(), xy(truth.obstacles[i].centre())))
            .collect();
        draw_names(&mut chart, &names, sc)?;
        let mut keys = run_keys();
        // A `[[robots]]` file: the file's movers from the frames, the other robots from their
        // own trajectories.
        let scripted = s
            .fleet
            .as_ref()
            .map(|_| s.movers.as_ref().map_or(0, |m| m.movers));
        draw_movers(&mut chart, &run.mover_frames, scripted, &mut keys, sc)?;
        if let Some(fleet) = &s.fleet {
            draw_robots(&mut chart, &fleet.others, truth.radius, &mut keys, sc)?;
        }
        if !sectors.is_empty() {
            keys.push((
                "sector at a discovery",
                Key::Patch(RGBColor(231, 239, 250), SECTOR),
            ));
        }
        if perceived.is_some() {
            keys.push(("perceived (lidar)", Key::Line(PERCEIVED, 2)));
        }
        draw_legend(&legend, &keys, None, sc)
    })
}

/// The colour of a perceived shape's outline (a lidar's, over the true obstacles).
pub const PERCEIVED: RGBColor = RGBColor(25, 190, 215);

/// The shapes a lidar's navigator perceived at the end of `run` (`None`: no lidar, or it
/// perceived nothing).
fn perceived_at_end(run: &Run) -> Option<&[harmonav_transform::StarShape]> {
    run.scan_events.last().and_then(|r| r.perceived.as_deref())
}

/// `Θ` of the `perceived` shapes, each grown by the robot's radius and margin as the navigator
/// holds it (by the growth rule of the lidar's shapes: a hull's fallback is its dilated hull,
/// where the Fourier rule's disc may cross the wall).
pub(crate) fn perceived_field(
    prepared: &Prepared,
    perceived: &[harmonav_transform::StarShape],
) -> Result<Field, String> {
    let truth = &prepared.truth;
    let form = truth
        .sensor
        .lidar()
        .map_or(harmonav::StarForm::Fourier, |l| l.scan.form);
    let grown = perceived
        .iter()
        .map(|p| harmonav::grow_perceived_as(p, truth.radius + truth.margin, form))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let ws =
        harmonav_transform::Workspace::new(truth.workspace.boundary().clone(), grown, truth.goal())
            .map_err(|e| e.to_string())?;
    Field::all_known_with(std::sync::Arc::new(ws), prepared.k_policy()).map_err(|e| e.to_string())
}

/// Worlds of at most this many obstacles name every one on `trajectory.svg`; larger ones name
/// only the discovered obstacles (a 600-disc world printed 600 names on top of one another).
pub const LABEL_ALL_UP_TO: usize = 20;

/// The pixel box `(left, top, right, bottom)` of `text` centred at `at`, at `size` px: 0.6 em
/// per character (no font metrics in an SVG-only build), one em high.
pub(crate) fn label_box(at: (i32, i32), text: &str, size: i32) -> (i32, i32, i32, i32) {
    let w = (0.6 * f64::from(size) * text.chars().count() as f64).ceil() as i32;
    (
        at.0 - w / 2,
        at.1 - size / 2,
        at.0 + w / 2 + 1,
        at.1 + size / 2 + 1,
    )
}

/// The labels to draw, in the order offered: each one whose box (with `spare` px to spare)
/// overlaps no box already placed.
pub(crate) fn place_labels(
    wanted: impl IntoIterator<Item = (usize, (i32, i32, i32, i32))>,
    spare: i32,
) -> Vec<usize> {
    let mut placed: Vec<(i32, i32, i32, i32)> = Vec::new();
    let mut kept = Vec::new();
    for (i, b) in wanted {
        let clear = |p: &(i32, i32, i32, i32)| {
            b.2 + spare <= p.0 || p.2 + spare <= b.0 || b.3 + spare <= p.1 || p.3 + spare <= b.1
        };
        if placed.iter().all(clear) {
            placed.push(b);
            kept.push(i);
        }
    }
    kept
}

/// The marker of an entry of a legend.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Key {
    /// A filled disc of this colour and radius (nominal px): the start, the goal.
    Dot(RGBColor, i32),
    /// A line of this colour and width (nominal px): the path, an edge.
    Line(RGBColor, u32),
    /// A square of this fill and outline: an obstacle, a wall, a sector.
    Patch(RGBColor, RGBColor),
}

/// The height of one more legend row (nominal px): a run with movers has one.
pub(crate) const LEGEND_ROW: u32 = 24;

/// A non-cooperative mover's colour on `trajectory.svg` (purple: the level lines take the
/// oranges).
const MOVER: RGBColor = RGBColor(145, 60, 185);

/// A reciprocal mover's colour on `trajectory.svg` (another harmonav robot: blue).
const PEER: RGBColor = RGBColor(50, 115, 230);

/// Where the robot's command was `Overwhelmed` or refused, on `trajectory.svg` (red).
const OVERWHELMED: RGBColor = RGBColor(215, 30, 30);

/// The movers of a run (issue 54, item 4): each mover's track, its disc at the last frame and,
/// faint, the disc it may reach within a control period there; the robot's positions where its
/// command was `Yielding` (orange dots) or `Overwhelmed`/refused (red). Adds their keys to
/// `keys`. Nothing without frames. `only`: the first so many marks of each frame (the file's
/// movers; the other robots of a `[[robots]]` file, which follow them, are drawn from their
/// own trajectories by [`draw_robots`]); `None`: every mark.
pub(crate) fn draw_movers(
    chart: &mut Plane<'_, '_>,
    frames: &[MoverFrame],
    only: Option<usize>,
    keys: &mut Vec<(&'static str, Key)>,
    s: Scale,
) -> Result<(), String> {
    let Some(last) = frames.last() else {
        return Ok(());
    };
    let colour = |reciprocal| if reciprocal { PEER } else { MOVER };
    let drawn = &last.movers[..only.unwrap_or(usize::MAX).min(last.movers.len())];
    for (i, m) in drawn.iter().enumerate() {
        let track: Vec<(f64, f64)> = frames
            .iter()
            .filter_map(|f| f.movers.get(i))
            .map(|m| (m.position[0], m.position[1]))
            .collect();
        let c = colour(m.reciprocal);
        draw_path(chart, track, s.stroke(c.mix(0.6), 1))?;
        let disc = |r: f64| {
            (0..=64)
                .map(|j| {
                    let a = std::f64::consts::TAU * f64::from(j) / 64.0;
                    (m.position[0] + r * a.cos(), m.position[1] + r * a.sin())
                })
                .collect::<Vec<_>>()
        };
        chart
            .draw_series([Polygon::new(disc(m.radius), c.mix(0.35).filled())])
            .map_err(err)?;
        draw_path(chart, disc(m.radius), s.stroke(c, 2))?;
        draw_path(chart, disc(m.reach), s.stroke(c.mix(0.5), 1))?;
    }
    let marks = |mode: &'static str| {
        frames
            .iter()
            .filter(move |f| f.mode == Some(mode))
            .map(|f| (f.robot[0], f.robot[1]))
    };
    chart
        .draw_series(marks("yielding").map(|p| Circle::new(p, s.px(3), MOVER.filled())))
        .map_err(err)?;
    let bad: Vec<(f64, f64)> = marks("overwhelmed").chain(marks("refused")).collect();
    chart
        .draw_series(
            bad.iter()
                .map(|&p| Circle::new(p, s.px(4), OVERWHELMED.filled())),
        )
        .map_err(err)?;
    if drawn.iter().any(|m| !m.reciprocal) {
        keys.push(("mover", Key::Patch(RGBColor(222, 200, 235), MOVER)));
    }
    if drawn.iter().any(|m| m.reciprocal) {
        keys.push(("other robot", Key::Patch(RGBColor(190, 210, 245), PEER)));
    }
    keys.push(("yielding", Key::Dot(MOVER, 3)));
    if !bad.is_empty() {
        keys.push(("overwhelmed", Key::Dot(OVERWHELMED, 4)));
    }
    Ok(())
}

/// The other robots of a `[[robots]]` file, each from its own recorded states
/// ([`FleetRobot::samples`]): its path (blue), its start (a blue dot, labelled `R1`, `R2`, …
/// just above it, in the file's order), its goal (a blue ring), its body of radius `radius` at its last state
/// and, for a differential drive, its heading ticks ([`draw_headings`]). Adds their key to
/// `keys`. Nothing without other robots.
pub(crate) fn draw_robots(
    chart: &mut Plane<'_, '_>,
    others: &[FleetRobot],
    radius: f64,
    keys: &mut Vec<(&'static str, Key)>,
    s: Scale,
) -> Result<(), String> {
    if others.is_empty() {
        return Ok(());
    }
    let mut labels = Vec::with_capacity(others.len());
    for (k, robot) in others.iter().enumerate() {
        let points = robot.samples.iter().map(|p| (p.x[0], p.x[1]));
        let path = drawable(points, |p| chart.backend_coord(p));
        chart
            .draw_series(LineSeries::new(path, s.stroke(PEER, 2)))
            .map_err(err)?;
        draw_headings(chart, &robot.samples, s)?;
        let (start, goal) = (xy_of(robot.start), xy_of(robot.goal));
        chart
            .draw_series([
                Circle::new(start, s.px(4), PEER.filled()),
                Circle::new(goal, s.px(6), s.stroke(PEER, 2)),
            ])
            .map_err(err)?;
        if let Some(last) = robot.samples.last() {
            let body: Vec<(f64, f64)> = (0..=64)
                .map(|j| {
                    let a = std::f64::consts::TAU * f64::from(j) / 64.0;
                    (last.x[0] + radius * a.cos(), last.x[1] + radius * a.sin())
                })
                .collect();
            chart
                .draw_series([Polygon::new(body.clone(), PEER.mix(0.35).filled())])
                .map_err(err)?;
            draw_path(chart, body, s.stroke(PEER, 1))?;
        }
        // Above the start, clear of its dot and body.
        labels.push((format!("R{}", k + 1), (start.0, start.1 + 3.0 * radius)));
    }
    let names: Vec<(&str, (f64, f64))> = labels
        .iter()
        .map(|(name, at)| (name.as_str(), *at))
        .collect();
    draw_names(chart, &names, s)?;
    keys.push(("other robots", Key::Line(PEER, 2)));
    Ok(())
}

/// A point of a file as the plane's coordinates.
fn xy_of(p: [f64; 2]) -> (f64, f64) {
    (p[0], p[1])
}

/// The legend's entries that every plane figure of a run has: the start, the goal, the path,
/// and the obstacles, discovered and not.
pub(crate) fn run_keys() -> Vec<(&'static str, Key)> {
    let (known, unknown) = (obstacle_colors(true), obstacle_colors(false));
    vec![
        ("start", Key::Dot(BLACK, 5)),
        ("goal", Key::Dot(GOAL, 6)),
        ("path", Key::Line(PATH, 2)),
        ("discovered", Key::Patch(known.0, known.1)),
        ("not discovered", Key::Patch(unknown.0, unknown.1)),
    ]
}

/// Draws `key`'s marker in the 16 px wide slot at `(x, y)` (nominal px, `y` its middle).
fn draw_key(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    key: Key,
    (x, y): (i32, i32),
    s: Scale,
) -> Result<(), String> {
    let at = |dx: i32, dy: i32| (s.px(x + dx), s.px(y + dy));
    match key {
        Key::Dot(color, r) => area.draw(&Circle::new(at(8, 0), s.px(r), color.filled())),
        Key::Line(color, w) => area.draw(&PathElement::new(
            vec![at(0, 0), at(16, 0)],
            s.stroke(color, w),
        )),
        Key::Patch(fill, stroke) => {
            let corners = [at(2, -6), at(14, 6)];
            area.draw(&Rectangle::new(corners, fill.filled()))
                .and_then(|()| area.draw(&Rectangle::new(corners, s.stroke(stroke, 1))))
        }
    }
    .map_err(err)
}

/// The legend strip under a plane figure's chart, laid out left to right at fixed widths so
/// that no text overlaps another: `keys` on the first row, the colour of each level of `Θ`
/// with its value on the second, and `note` (if any) on the third.
pub(crate) fn draw_legend(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    keys: &[(&str, Key)],
    note: Option<&str>,
    s: Scale,
) -> Result<(), String> {
    let style = TextStyle::from(s.font(12)).pos(Pos::new(HPos::Left, VPos::Center));
    let text = |t: &str, x: i32, y: i32| {
        area.draw(&Text::new(t.to_string(), (s.px(x), s.px(y)), style.clone()))
            .map_err(err)
    };
    let width = |t: &str| (0.6 * 12.0 * t.chars().count() as f64).ceil() as i32;
    let mut x = 48;
    // Keys that would run past the chart's width go on a row of their own (a run with movers
    // has a few more).
    let mut rest = Vec::new();
    for &(label, key) in keys {
        let wide = 20 + width(label) + 18;
        if x + wide > CHART.0 as i32 || !rest.is_empty() {
            rest.push((label, key));
            continue;
        }
        draw_key(area, key, (x, 14), s)?;
        text(label, x + 20, 14)?;
        x += wide;
    }
    // The level sets: a coloured bar and its value each.
    text("Θ levels:", 48, 38)?;
    x = 128;
    for v in LEVELS {
        draw_key(area, Key::Line(level_color(v), 3), (x, 38), s)?;
        let label = format!("{v}");
        text(&label, x + 20, 38)?;
        x += 20 + width(&label) + 12;
    }
    // Their own row, below the note's (the figure is [`LEGEND_ROW`] taller for them).
    let y = if note.is_some() {
        62 + LEGEND_ROW as i32
    } else {
        62
    };
    x = 48;
    for (label, key) in rest {
        draw_key(area, key, (x, y), s)?;
        text(label, x + 20, y)?;
        x += 20 + width(label) + 18;
    }
    match note {
        Some(note) => text(note, 48, 62),
        None => Ok(()),
    }
}

/// Discovery labels for a time axis: discoveries at the same time share one label, and labels
/// closer than their width in pixels go to the next row, so none overlaps another.
fn discovery_labels(discoveries: &[Discovery]) -> Vec<(f64, String)> {
    let mut groups: Vec<(f64, Vec<&str>)> = Vec::new();
    for d in discoveries {
        match groups.last_mut() {
            Some((t, names)) if *t == d.time_s => names.push(&d.obstacle),
            _ => groups.push((d.time_s, vec![&d.obstacle])),
        }
    }
    groups
        .into_iter()
        .map(|(t, names)| {
            let label = if names.len() > 3 {
                format!("{}…{} ({})", names[0], names[names.len() - 1], names.len())
            } else {
                names.join(", ")
            };
            (t, label)
        })
        .collect()
}

/// Estimated width of `text` at 11 px (no font metrics in an SVG-only build).
fn text_width(text: &str) -> i32 {
    7 * text.chars().count() as i32 + 6
}

/// A named, coloured time series `(t, value)`.
type Series<'a> = (&'a str, RGBColor, Vec<(f64, f64)>);

/// A time series chart on `area` (drawn at `s`) with discovery markers.
fn time_chart(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    title: &str,
    y_desc: &str,
    series: &[Series<'_>],
    discoveries: &[Discovery],
    s: Scale,
) -> Result<(), String> {
    let t_end = series
        .iter()
        .flat_map(|(_, _, s)| s.last().map(|p| p.0))
        .fold(0.0, f64::max)
        .max(1e-3);
    let y_max = series
        .iter()
        .flat_map(|(_, _, s)| s.iter().map(|p| p.1))
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max)
        .max(1e-9)
        * 1.25;
    let mut chart = ChartBuilder::on(area)
        .caption(title, s.font(16))
        .margin(s.size(8))
        .x_label_area_size(s.size(32))
        .y_label_area_size(s.size(50))
        .build_cartesian_2d(0.0..t_end, 0.0..y_max)
        .map_err(err)?;
    chart
        .configure_mesh()
        .light_line_style(s.stroke(WHITE, 1))
        .bold_line_style(s.stroke(BLACK.mix(0.2), 1))
        .disable_x_mesh()
        .x_labels(8)
        .y_labels(6)
        .x_desc("t (s)")
        .y_desc(y_desc)
        .label_style(s.font(12))
        .axis_style(s.stroke(BLACK, 1))
        .set_all_tick_mark_size(s.px(5))
        .draw()
        .map_err(err)?;
    // Discovery markers, labels on rows so that none overlaps another.
    let mut rows: Vec<i32> = Vec::new(); // the right end of the last label in each row, px
    for (t, label) in discovery_labels(discoveries) {
        draw_path(
            &mut chart,
            vec![(t, 0.0), (t, y_max)],
            s.stroke(RGBColor(150, 150, 150), 1),
        )?;
        let (px, _) = chart.backend_coord(&(t, y_max));
        let w = s.px(text_width(&label));
        let row = match rows.iter().position(|&right| px > right + s.px(4)) {
            Some(r) => r,
            None => {
                rows.push(i32::MIN);
                rows.len() - 1
            }
        };
        rows[row] = px + w;
        let y = y_max * (0.97 - 0.06 * row as f64);
        chart
            .draw_series(std::iter::once(Text::new(
                label,
                (t, y),
                s.font(11).color(&RGBColor(90, 90, 90)),
            )))
            .map_err(err)?;
    }
    for (name, color, points) in series {
        let color = *color;
        let points = drawable(points.iter().copied(), |p| chart.backend_coord(p));
        chart
            .draw_series(LineSeries::new(points, s.stroke(color, 2)))
            .map_err(err)?
            .label(*name)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + s.px(18), y)], s.stroke(color, 2))
            });
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::MiddleLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(s.stroke(RGBColor(180, 180, 180), 1))
        .margin(s.size(10))
        .legend_area_size(s.size(30))
        .label_font(s.font(12))
        .draw()
        .map_err(err)?;
    Ok(())
}

/// `speed.svg`: `|ẋ|` against time, with the bound `√(2μ/m)` (corollary `boundedvel`) when
/// there is one, and the discoveries marked.
pub fn speed_svg(run: &Run) -> Result<String, String> {
    let speed: Vec<(f64, f64)> = run
        .samples
        .iter()
        .map(|s| (s.t, s.v[0].hypot(s.v[1])))
        .collect();
    let mut series = vec![("|ẋ|", PATH, speed)];
    let t_end = run.summary.time_s;
    if let Some(bound) = run.summary.speed_bound {
        series.push(("√(2μ/m)", KNOWN, vec![(0.0, bound), (t_end, bound)]));
    }
    let title = format!("{}: speed", run.summary.name);
    scaled_svg((760, 360), Scale::FINE, |root| {
        time_chart(
            root,
            &title,
            "speed (m/s)",
            &series,
            &run.summary.discoveries,
            Scale::FINE,
        )
    })
}

/// `energy.svg` (dynamic law): `V(t) = μΘ + ½m|ẋ|²` (eq. `totalenergy`) and the damping
/// `λ(t)` in force, with the discoveries marked.
pub fn energy_svg(run: &Run) -> Result<String, String> {
    let energy: Vec<(f64, f64)> = run
        .samples
        .iter()
        .filter_map(|s| s.energy.map(|e| (s.t, e)))
        .collect();
    let lambda: Vec<(f64, f64)> = run
        .samples
        .iter()
        .filter_map(|s| s.lambda.map(|l| (s.t, l)))
        .collect();
    let s = Scale::FINE;
    scaled_svg((760, 620), s, |root| {
        let (top, bottom) = root.split_vertically(s.px(310));
        let d = &run.summary.discoveries;
        time_chart(
            &top,
            &format!("{}: energy", run.summary.name),
            "V (J)",
            &[("V", PATH, energy)],
            d,
            s,
        )?;
        time_chart(
            &bottom,
            &format!("{}: damping", run.summary.name),
            "λ (kg/s)",
            &[("λ", SECTOR, lambda)],
            d,
            s,
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_that_would_overlap_are_left_out_in_order() {
        // Three names in a row, the middle one crowding both: the first and the last stay.
        let wanted = [
            (0, label_box((100, 100), "O1", 12)),
            (1, label_box((112, 102), "O2", 12)),
            (2, label_box((130, 100), "O3", 12)),
            (3, label_box((100, 200), "O4", 12)),
        ];
        assert_eq!(place_labels(wanted, 2), vec![0, 2, 3]);
        // 600 names on one spot: one is drawn.
        let crowd = (0..600).map(|i| (i, label_box((300, 300), &format!("O{i}"), 12)));
        assert_eq!(place_labels(crowd, 2).len(), 1);
    }

    /// The field of a lidar run's perceived shapes grows them by the lidar's own rule. A bow
    /// tie near the wall, whose offset is not star-shaped: the Fourier rule's fallback disc
    /// crosses the wall and the field cannot be built (the figures of a 5 m benchmark world
    /// were refused so); the hull rule's dilated hull stays inside.
    #[test]
    fn perceived_shapes_are_grown_by_the_lidars_rule() {
        let text = r#"
name = "tie"

[workspace]
type = "circle"
center = [0.0, 0.0]
radius = 2.0

[[obstacles]]
type = "circle"
center = [-1.0, 0.0]
radius = 0.2

[robot]
model = "kinematic"
start = [0.0, 1.0]
goal = [0.0, -1.0]
radius = 0.05

[sensor]
type = "lidar"
range = 1.5
"#;
        let path = std::path::Path::new("tie.toml");
        let mut prepared = harmonav_scenario::Scenario::parse(path, text)
            .unwrap()
            .prepare(path)
            .unwrap();
        let tie = harmonav_transform::StarShape::fourier_star(
            nalgebra::Vector2::new(1.45, 0.0),
            0.3,
            &[(2, -0.25, 0.0)],
        )
        .unwrap();
        assert!(tie.offset(0.05).is_err(), "the offset must fall back");
        assert!(perceived_field(&prepared, std::slice::from_ref(&tie)).is_ok());
        let harmonav_scenario::Sensor::Lidar(l) = &mut prepared.truth.sensor else {
            panic!("a lidar")
        };
        l.scan.form = harmonav::StarForm::Fourier;
        assert!(perceived_field(&prepared, std::slice::from_ref(&tie)).is_err());
    }

    #[test]
    fn drawable_keeps_one_point_per_pixel_and_both_ends() {
        // 10⁵ points along a line of 100 px: at most two per pixel, the ends exact, and
        // every pixel of the line still visited.
        let points: Vec<(f64, f64)> = (0..=100_000).map(|i| (i as f64 * 1e-3, 0.0)).collect();
        let px = |p: &(f64, f64)| (p.0.floor() as i32, p.1.floor() as i32);
        let kept = drawable(points.iter().copied(), px);
        assert_eq!(kept.first(), Some(&(0.0, 0.0)));
        assert_eq!(kept.last(), Some(&(100.0, 0.0)));
        assert!(kept.len() <= 102, "{}", kept.len());
        let pixels: std::collections::BTreeSet<_> = kept.iter().map(px).collect();
        assert_eq!(pixels.len(), 101);
    }

    /// The vertices of the polylines of `svg` stroked in `color` (`#RRGGBB`), in nominal px.
    fn polylines(svg: &str, color: &str, s: Scale) -> Vec<Vec<(f64, f64)>> {
        let stroke = format!("stroke=\"{color}\"");
        svg.split("<polyline")
            .skip(1)
            .filter(|e| e.contains(&stroke))
            .map(|e| {
                let points = e.split("points=\"").nth(1).unwrap().split('"').next();
                let scale = f64::from(s.0);
                points
                    .unwrap()
                    .split_whitespace()
                    .map(|xy| {
                        let (x, y) = xy.split_once(',').unwrap();
                        (
                            x.parse::<f64>().unwrap() / scale,
                            y.parse::<f64>().unwrap() / scale,
                        )
                    })
                    .collect()
            })
            .collect()
    }

    /// The largest distance of `points` from their least-squares line `y = a + b x`.
    fn off_line(points: &[(f64, f64)]) -> f64 {
        let n = points.len() as f64;
        let (mx, my) = points
            .iter()
            .fold((0.0, 0.0), |(x, y), p| (x + p.0 / n, y + p.1 / n));
        let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(xy, xx), p| {
            (xy + (p.0 - mx) * (p.1 - my), xx + (p.0 - mx).powi(2))
        });
        let b = sxy / sxx;
        points
            .iter()
            .map(|p| ((p.1 - my) - b * (p.0 - mx)).abs() / b.hypot(1.0))
            .fold(0.0, f64::max)
    }

    /// A straight path across a plane figure, drawn at [`Scale::FINE`]: its vertices have
    /// sub-pixel coordinates, all within a fifth of a pixel of one line. Drawn at one backend
    /// pixel per pixel (plotters' own drawing), they stair-step up to half a pixel off it.
    #[test]
    fn a_straight_path_is_drawn_without_stair_steps() {
        let path = |s: Scale| {
            let svg = scaled_svg((400, 400), s, |root| {
                let mut chart = plane(root, "a line", Vector2::zeros(), 5.0, s)?;
                let line = (0..=10_000).map(|k| {
                    let t = f64::from(k) * 1e-4;
                    (-4.0 + 8.0 * t, -3.0 + 6.3 * t)
                });
                draw_run(&mut chart, line, (-4.0, -3.0), (4.0, 3.3), s)
            })
            .unwrap();
            assert!(svg.starts_with(r#"<svg width="400" height="400""#), "{svg}");
            let lines = polylines(&svg, "#D9480F", s);
            assert_eq!(lines.len(), 1);
            lines[0].clone()
        };
        let fine = path(Scale::FINE);
        assert!(fine.len() > 300, "{} vertices", fine.len());
        assert!(
            fine.iter()
                .any(|p| p.0.fract() != 0.0 && p.1.fract() != 0.0)
        );
        assert!(off_line(&fine) < 0.2, "{} px off the line", off_line(&fine));
        assert!(off_line(&path(Scale::ONE)) > 0.3, "plotters' own drawing");
    }
}
