//! A floor-plan run's outputs (issue 25): `trajectory.svg` (the true walls, the certified
//! region's outer edge, the obstacles, the level sets of `Θ` the robot knew at the end, the
//! path) and `summary.json` ([`harmonav_sim::floor::FloorSummary`]), written as one set like a
//! star world's ([`crate::set`]; a floor-plan run writes no recording yet, so a stale
//! `run.mcap`, `speed.svg` or `energy.svg` in the folder is removed).

use std::path::{Path, PathBuf};

use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_sim::floor::{FloorRun, FloorSummary, navigator};
use nalgebra::Vector2;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::atomic::{OutputError, StagedDir};
use crate::drawing::xy;
use crate::figures::{
    FONT, GOAL, PATH, draw_level_lines, draw_obstacle, draw_path, drawable, err, place_labels,
    plane,
};
use crate::levels::ThetaGrid;
use crate::set::{OUTPUT_FILES, check_output_dir};

/// Cells per side of the grid the level sets are traced on. Each `Θ` on a floor plan is an
/// `O(N)` sum over the boundary elements (≈ 50 µs at N = 1 000), so the grid is coarser than a
/// star world's: 160² cells take about a second.
const FLOOR_LEVEL_CELLS: usize = 160;

const WALL_FILL: RGBColor = RGBColor(120, 120, 120);
const EDGE: RGBColor = RGBColor(150, 150, 150);

/// A closed ring as plotters points.
fn ring(points: &[Vector2<f64>]) -> Vec<(f64, f64)> {
    points
        .iter()
        .chain(points.first())
        .map(|&p| xy(p))
        .collect()
}

/// `trajectory.svg` of a floor-plan run: `summary` and `run` from the same run of `prepared`.
///
/// # Errors
/// A drawing error, or a navigator that cannot be rebuilt for the level sets, as text.
pub fn floor_trajectory_svg(
    prepared: &FloorPrepared,
    summary: &FloorSummary,
    run: &FloorRun,
) -> Result<String, String> {
    let floor = &prepared.floor;
    let walls = floor.walls();
    let (lo, hi) = walls.bounding_box();
    let c = 0.5 * (lo + hi);
    let half = 0.52 * (hi - lo).max();
    // Θ as the robot knew it at the end: the walls and the obstacles it had sensed, grown by
    // radius + margin as the navigator grows them; NaN (no line) outside the certified region.
    let mut nav = navigator(prepared, None).map_err(|e| e.to_string())?;
    for d in &run.discoveries {
        nav.add_obstacle(prepared.obstacles[d.index].clone())
            .map_err(|e| e.to_string())?;
    }
    let grid = ThetaGrid::from_fn(c, half, FLOOR_LEVEL_CELLS, |p| nav.theta(p).ok());
    let title = format!(
        "{} — {:?} law, {} ({:.2} s)",
        summary.name,
        summary.model,
        if summary.reached {
            "goal reached"
        } else {
            "goal NOT reached"
        },
        summary.time_s
    );
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (720, 770)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (top, legend) = root.split_vertically(740);
        let mut chart = plane(&top, &title, c, half)?;
        chart
            .draw_series([Polygon::new(
                ring(walls.outer()),
                RGBColor(250, 250, 250).filled(),
            )])
            .map_err(err)?;
        draw_level_lines(&mut chart, &grid)?;
        // The certified region's outer edge: the shrunk walls ∂W_s (W_δ lies δ inside them).
        for hole in floor.domain().holes() {
            draw_path(&mut chart, ring(hole), EDGE.stroke_width(1))?;
        }
        draw_path(
            &mut chart,
            ring(floor.domain().outer()),
            EDGE.stroke_width(1),
        )?;
        for hole in walls.holes() {
            chart
                .draw_series([Polygon::new(ring(hole), WALL_FILL.filled())])
                .map_err(err)?;
        }
        draw_path(&mut chart, ring(walls.outer()), BLACK.stroke_width(2))?;
        let known: Vec<usize> = run.discoveries.iter().map(|d| d.index).collect();
        for (i, o) in prepared.obstacles.iter().enumerate() {
            draw_obstacle(&mut chart, o, known.contains(&i))?;
        }
        let path = drawable(run.positions.iter().map(|p| (p[0], p[1])), |p| {
            chart.backend_coord(p)
        });
        chart
            .draw_series(LineSeries::new(path, PATH.stroke_width(2)))
            .map_err(err)?;
        chart
            .draw_series([
                Circle::new((summary.start[0], summary.start[1]), 5, BLACK.filled()),
                Circle::new((summary.goal[0], summary.goal[1]), 6, GOAL.filled()),
            ])
            .map_err(err)?;
        // The discovered obstacles' names, each only where it overlaps no name already placed.
        let style =
            TextStyle::from((FONT, 12).into_font()).pos(Pos::new(HPos::Center, VPos::Center));
        let wanted = run.discoveries.iter().enumerate().map(|(j, d)| {
            let at = chart.backend_coord(&xy(prepared.obstacles[d.index].centre()));
            (j, crate::figures::label_box(at, &d.obstacle, 12))
        });
        for j in place_labels(wanted) {
            let d = &run.discoveries[j];
            chart
                .draw_series([Text::new(
                    d.obstacle.clone(),
                    xy(prepared.obstacles[d.index].centre()),
                    style.clone(),
                )])
                .map_err(err)?;
        }
        let note = format!(
            "walls: black, filled grey; certified region: δ = {} m inside the grey lines; \
             {} elements; Θ levels as on star worlds",
            summary.delta, summary.elements
        );
        legend
            .draw(&Text::new(
                note,
                (48, 14),
                TextStyle::from((FONT, 12).into_font()).pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(out)
}

/// Writes `trajectory.svg` and `summary.json` of a floor-plan run into `dir` as one set
/// ([`StagedDir`]: `summary.json` last; the other names of [`OUTPUT_FILES`] removed, so that
/// a folder never mixes the files of two runs). `dir` is checked first
/// ([`check_output_dir`]) and created. Returns the paths, `summary.json` first.
///
/// # Errors
/// [`OutputError`] naming the folder or file and the problem; the previous set is then
/// untouched.
pub fn write_floor_outputs(
    dir: &Path,
    prepared: &FloorPrepared,
    summary: &FloorSummary,
    run: &FloorRun,
) -> Result<Vec<PathBuf>, OutputError> {
    check_output_dir(dir)?;
    std::fs::create_dir_all(dir).map_err(|source| OutputError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let content =
        |file: &'static str| move |problem: String| OutputError::Content { file, problem };
    let svg = floor_trajectory_svg(prepared, summary, run).map_err(content("trajectory.svg"))?;
    let json = serde_json::to_string_pretty(summary)
        .map_err(|e| content("summary.json")(e.to_string()))?
        + "\n";
    let stage = StagedDir::new(dir)?;
    let names = ["trajectory.svg", "summary.json"];
    for (name, text) in names.iter().zip([svg, json]) {
        let path = stage.path().join(name);
        std::fs::write(&path, text).map_err(|source| OutputError::Io { path, source })?;
    }
    stage.commit(&names, &OUTPUT_FILES)?;
    Ok(vec![dir.join("summary.json"), dir.join("trajectory.svg")])
}
