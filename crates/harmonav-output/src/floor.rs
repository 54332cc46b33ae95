//! A floor-plan run's outputs (issue 25): `run.mcap` (the recording of [`crate::record`],
//! with the true walls, the shrunk walls `∂W_s` and the floor plan's `Θ`; a lidar's scans
//! and perceived shapes as in a star world), `trajectory.svg` (the true walls, the certified
//! region's outer edge, the obstacles, a lidar's perceived shapes over them, the level sets of
//! `Θ` the robot knew at the end, the path) and `summary.json`
//! ([`harmonav_sim::floor::FloorSummary`]), written as one set like a star world's
//! ([`crate::set`]: a stale `speed.svg` or `energy.svg` in the folder is removed).

use std::path::{Path, PathBuf};

use harmonav::FloorNavigator;
use harmonav::floorplan::Funnels;
use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_sim::floor::{FloorRun, FloorSummary, navigator};
use harmonav_sim::trace::Event;
use plotters::prelude::*;

use crate::atomic::OutputError;
use crate::canvas::{Scale, scaled_svg};
use crate::drawing::{outline, ring, xy};
use crate::figures::{
    CHART, Key, LEGEND_ROW, LEVELS, PERCEIVED, Plane, draw_legend, draw_level_lines, draw_movers,
    draw_names, draw_obstacle, draw_path, draw_robots, draw_run, err, plane, run_keys, run_title,
};
use crate::levels::ThetaGrid;
use crate::record::Stream;
use crate::set::{OUTPUT_FILES, Opened, check_output_dir};
use crate::world::{FloorTheta, floor_square};

/// Cells per side of the grid the level sets are traced on. Each `Θ` on a floor plan is an
/// `O(N)` sum over the boundary elements (≈ 50 µs at N = 1 000), so the grid is coarser than a
/// star world's: 160² cells take about a second (the level lines' vertices, moved onto the
/// level sets with a few evaluations each, add less than half of that in the rooms tried).
const FLOOR_LEVEL_CELLS: usize = 160;

const WALL_FILL: RGBColor = RGBColor(120, 120, 120);
const EDGE: RGBColor = RGBColor(150, 150, 150);
/// A chain of funnels' goals and the links to their parents (teal).
const FUNNEL: RGBColor = RGBColor(0, 140, 140);
/// The part of `W_δ` that no funnel holds (light yellow).
const UNCERTIFIED: RGBColor = RGBColor(250, 230, 140);

/// `trajectory.svg` of a floor-plan run: `summary` and `run` from the same run of `prepared`.
/// Drawn like a star world's ([`crate::figures::trajectory_svg`]: at [`Scale::FINE`], the
/// level lines on the level sets, the same path, markers, names and legend).
///
/// # Errors
/// A drawing error, or a navigator that cannot be rebuilt for the level sets, as text.
pub fn floor_trajectory_svg(
    prepared: &FloorPrepared,
    summary: &FloorSummary,
    run: &FloorRun,
) -> Result<String, String> {
    let base = navigator(prepared, None).map_err(|e| e.to_string())?;
    trajectory_with(prepared, &base, summary, run)
}

/// [`floor_trajectory_svg`] with `base`, the file's navigator knowing no obstacle, whose `Θ`
/// is drawn with the obstacles the run knew.
fn trajectory_with(
    prepared: &FloorPrepared,
    base: &FloorNavigator,
    summary: &FloorSummary,
    run: &FloorRun,
) -> Result<String, String> {
    let floor = &prepared.floor;
    let walls = floor.walls();
    let (c, half) = floor_square(prepared);
    // Θ as the robot knew it at the end: the walls and the obstacles it had sensed, grown by
    // radius + margin as the navigator grows them; NaN (no line) outside the certified region.
    // With a lidar, the shapes it perceived, grown as the navigator grows them.
    let discovered: Vec<usize> = run.discoveries.iter().map(|d| d.index).collect();
    let seen = FloorTheta::new(prepared, base, &discovered, &run.perceived)?;
    let theta = |p| seen.at(p);
    let grid = ThetaGrid::from_fn(c, half, FLOOR_LEVEL_CELLS, theta);
    let levels = grid.refined_level_lines(&LEVELS, theta);
    let title = run_title(
        &summary.name,
        summary.model,
        summary.reached,
        summary.time_s,
    );
    // Known: discovered, or (a lidar's) the true obstacles a perceived shape holds the centre of.
    let known: Vec<usize> = run
        .discoveries
        .iter()
        .map(|d| d.index)
        .chain((0..prepared.obstacles.len()).filter(|&i| {
            let c = prepared.obstacles[i].centre();
            run.perceived.iter().any(|p| p.contains(c))
        }))
        .collect();
    let funnels = prepared.funnels.as_deref();
    let note = match funnels {
        None => format!(
            "certified region: δ = {} m inside the grey lines; {} boundary elements",
            summary.delta, summary.elements
        ),
        Some(chain) => format!(
            "δ = {} m inside the grey lines; {} elements; {} funnels certify {:.1} % of the \
             reachable area",
            summary.delta,
            summary.elements,
            chain.funnels.len(),
            100.0 * chain.fraction()
        ),
    };
    let sc = Scale::FINE;
    let extra = if run.mover_frames.is_empty() && funnels.is_none() {
        0
    } else {
        LEGEND_ROW
    };
    scaled_svg((CHART.0, CHART.1 + 76 + extra), sc, |root| {
        let (top, legend) = root.split_vertically(sc.px(CHART.1 as i32));
        let mut chart = plane(&top, &title, c, half, sc)?;
        chart
            .draw_series([Polygon::new(
                ring(walls.outer()),
                RGBColor(250, 250, 250).filled(),
            )])
            .map_err(err)?;
        if let Some(chain) = funnels {
            draw_uncovered(&mut chart, chain)?;
        }
        draw_level_lines(&mut chart, &levels, sc)?;
        // The certified region's outer edge: the shrunk walls ∂W_s (W_δ lies δ inside them).
        let domain = floor.domain();
        for edge in domain
            .holes()
            .iter()
            .map(Vec::as_slice)
            .chain([domain.outer()])
        {
            draw_path(&mut chart, ring(edge), sc.stroke(EDGE, 1))?;
        }
        for hole in walls.holes() {
            chart
                .draw_series([Polygon::new(ring(hole), WALL_FILL.filled())])
                .map_err(err)?;
        }
        draw_path(&mut chart, ring(walls.outer()), sc.stroke(BLACK, 2))?;
        for (i, o) in prepared.obstacles.iter().enumerate() {
            draw_obstacle(&mut chart, o, known.contains(&i), sc)?;
        }
        for p in &run.perceived {
            draw_path(&mut chart, outline(p), sc.stroke(PERCEIVED, 2))?;
        }
        if let Some(chain) = funnels {
            draw_chain(&mut chart, chain, sc)?;
        }
        let points = run.positions.iter().map(|p| (p[0], p[1]));
        let (start, goal) = (summary.start, summary.goal);
        draw_run(
            &mut chart,
            points,
            (start[0], start[1]),
            (goal[0], goal[1]),
            sc,
        )?;
        // The discovered obstacles' names, each only where it overlaps no name already placed.
        let names: Vec<(&str, (f64, f64))> = run
            .discoveries
            .iter()
            .map(|d| {
                (
                    d.obstacle.as_str(),
                    xy(prepared.obstacles[d.index].centre()),
                )
            })
            .collect();
        draw_names(&mut chart, &names, sc)?;
        let mut keys = run_keys();
        keys.push(("walls", Key::Patch(WALL_FILL, BLACK)));
        if funnels.is_some() {
            keys.push(("funnel goals", Key::Dot(FUNNEL, 3)));
            keys.push(("not certified", Key::Patch(UNCERTIFIED, UNCERTIFIED)));
        }
        // One row holds seven keys: the perceived shapes take the certified edge's place (the
        // note below names the grey lines).
        if run.perceived.is_empty() {
            keys.push(("certified edge", Key::Line(EDGE, 1)));
        } else {
            keys.push(("perceived (lidar)", Key::Line(PERCEIVED, 2)));
        }
        // A `[[robots]]` file: the file's movers from the frames, the other robots from their
        // own trajectories.
        let scripted = run
            .fleet
            .as_ref()
            .map(|_| run.movers.as_ref().map_or(0, |m| m.movers));
        draw_movers(&mut chart, &run.mover_frames, scripted, &mut keys, sc)?;
        if let Some(fleet) = &run.fleet {
            let radius = prepared.scenario.robot.radius;
            draw_robots(&mut chart, &fleet.others, radius, &mut keys, sc)?;
        }
        draw_legend(&legend, &keys, Some(&note), sc)
    })
}

/// The samples of `W_δ` that no funnel of `chain` holds, each row's neighbouring samples drawn
/// as one rectangle of the grid's cell (a few hundred rectangles, not one per sample).
fn draw_uncovered(chart: &mut Plane<'_, '_>, chain: &Funnels) -> Result<(), String> {
    let h = 0.5 * chain.cell;
    let mut samples: Vec<(f64, f64)> = chain.uncovered.iter().map(|p| (p.y, p.x)).collect();
    samples.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    // Runs `(y, x_first, x_last)` of samples one cell apart on one row.
    let mut runs: Vec<(f64, f64, f64)> = Vec::new();
    for (y, x) in samples {
        match runs.last_mut() {
            Some((ry, _, last)) if (*ry - y).abs() < 1e-6 * h && x - *last < 3.0 * h => *last = x,
            _ => runs.push((y, x, x)),
        }
    }
    chart
        .draw_series(runs.into_iter().map(|(y, a, b)| {
            Rectangle::new([(a - h, y - h), (b + h, y + h)], UNCERTIFIED.filled())
        }))
        .map_err(err)?;
    Ok(())
}

/// The chain's goals (teal dots) and a thin line from each to its parent's goal.
fn draw_chain(chart: &mut Plane<'_, '_>, chain: &Funnels, s: Scale) -> Result<(), String> {
    for f in &chain.funnels {
        if let Some(p) = f.parent {
            let parent = chain.funnels[p].goal;
            draw_path(
                chart,
                vec![xy(f.goal), xy(parent)],
                s.stroke(FUNNEL.mix(0.7), 1),
            )?;
        }
    }
    chart
        .draw_series(
            chain
                .funnels
                .iter()
                .map(|f| Circle::new(xy(f.goal), s.px(3), FUNNEL.filled())),
        )
        .map_err(err)?;
    Ok(())
}

/// A floor-plan run's outputs being written while it goes, as a star world's
/// ([`crate::set::Outputs`]): `run.mcap` streams into a staging folder inside `dir` as the run
/// hands it its events ([`FloorOutputs::observe`], the observer of
/// `harmonav_sim::physics::simulate_floor_observed`), and [`FloorOutputs::finish`] adds
/// `trajectory.svg` and `summary.json` and moves the set into place. Dropped before, nothing
/// of it is left and the previous set is untouched.
pub struct FloorOutputs<'p> {
    set: Opened<'p>,
    prepared: &'p FloorPrepared,
}

impl<'p> FloorOutputs<'p> {
    /// Checks `dir` ([`check_output_dir`]), creates it (and its missing parents, removed again
    /// if the set is dropped unfinished: [`crate::atomic::CreatedDir`]) and its staging
    /// folder, and opens the recording ([`Stream::create_floor`]).
    ///
    /// # Errors
    /// [`OutputError`] naming the folder or file and the problem.
    pub fn begin(dir: &Path, prepared: &'p FloorPrepared) -> Result<Self, OutputError> {
        let set = Opened::open(dir, |path| Stream::create_floor(path, prepared))?;
        Ok(Self { set, prepared })
    }

    /// Logs one event of the run into the recording.
    pub fn observe(&mut self, event: Event<'_>) {
        self.set.stream.observe(event);
    }

    /// Ends the recording, draws `trajectory.svg` of `run` (the run whose events were
    /// observed, `summary` its summary), writes `summary.json` and moves the set into place:
    /// `summary.json` last, and the other names of [`OUTPUT_FILES`] removed (a floor-plan run
    /// draws no `speed.svg` or `energy.svg`), so that a folder never mixes the files of two
    /// runs. `dir` is checked again first. Returns the paths, `summary.json` first.
    ///
    /// # Errors
    /// [`OutputError`] naming the folder or file and the problem; the previous set is then
    /// untouched.
    pub fn finish(
        self,
        summary: &FloorSummary,
        run: &FloorRun,
    ) -> Result<Vec<PathBuf>, OutputError> {
        let Self { mut set, prepared } = self;
        check_output_dir(&set.dir)?;
        // A floor plan with `[[robots]]`: the other robots' own trajectories.
        if let Some(fleet) = &run.fleet {
            set.stream.robots(&fleet.others);
        }
        let content =
            |file: &'static str| move |problem: String| OutputError::Content { file, problem };
        let svg = match set.stream.floor_base() {
            Some(base) => trajectory_with(prepared, base, summary, run),
            None => floor_trajectory_svg(prepared, summary, run),
        }
        .map_err(content("trajectory.svg"))?;
        let json = serde_json::to_string_pretty(summary)
            .map_err(|e| content("summary.json")(e.to_string()))?
            + "\n";
        set.commit(
            &[("trajectory.svg", svg), ("summary.json", json)],
            &OUTPUT_FILES,
        )
    }
}
