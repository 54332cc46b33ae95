//! `run`, `eval` and `check` on a floor-plan file (a `[floor_plan]` table, issue 25): the
//! user's loop around a `FloorNavigator` (`harmonav_sim::floor`), built-in or in rapier
//! (`harmonav_sim::physics::simulate_floor_observed`), its summary and outputs
//! (`harmonav_output::floor`); and the loading that `sweep` shares. `--k` and `--damping` set the
//! file's `[field] k` and `[controller] damping`, as in a star world.

use std::path::Path;

use harmonav_field::FieldError;
use harmonav_output::floor::FloorOutputs;
use harmonav_rs::floorplan::LayerLevel;
use harmonav_scenario::floorplan::{FloorPrepared, FloorScenario, StartsSpec};
use harmonav_scenario::scenario::read_text;
use harmonav_sim::floor::{FloorSummary, navigator, obstacle_name};
use harmonav_sim::physics::simulate_floor_observed;
use harmonav_transform::Shown;

use crate::args::{DampingArg, KArg, model};
use crate::error::CliError;
use crate::eval::{parse_points, print_rows};
use crate::run::{RunArgs, print_guarantees, print_head};
use crate::text::{out, print_json};

/// Loads a floor-plan file (meshing and solving its harmonic map), with `--k` and `--damping`
/// overriding its `[field] k` and `[controller] damping` when given, as in a star world
/// ([`crate::args::load`]).
pub fn load_floor(
    path: &Path,
    k: Option<KArg>,
    damping: Option<DampingArg>,
) -> Result<FloorPrepared, CliError> {
    load_floor_starts(path, k, damping, None, None)
}

/// [`load_floor`], with `--starts` and `--seed` (`sweep`) overriding the file's `[starts]`
/// count and seed when given.
pub fn load_floor_starts(
    path: &Path,
    k: Option<KArg>,
    damping: Option<DampingArg>,
    count: Option<usize>,
    seed: Option<u64>,
) -> Result<FloorPrepared, CliError> {
    let mut scenario = FloorScenario::parse(path, &read_text(path)?)?;
    if let Some(k) = k {
        scenario.field.k = k.into();
    }
    if let Some(d) = damping {
        scenario.controller.damping = d.into();
    }
    if let Some(count) = count.filter(|&c| c > harmonav_scenario::floorplan::MAX_STARTS) {
        // The file's own cap, named as the flag that set it (issue 56, D19.4).
        return Err(CliError::FloorStarts {
            scenario: path.to_path_buf(),
            count,
        });
    }
    if count.is_some() || seed.is_some() {
        let file = scenario.starts.unwrap_or(StartsSpec { count: 0, seed: 1 });
        scenario.starts = Some(StartsSpec {
            count: count.unwrap_or(file.count),
            seed: seed.unwrap_or(file.seed),
        });
    }
    Ok(scenario.prepare(path)?)
}

/// `c_δ` over the walls and, for each start of the file, whether it lies below it
/// (`FloorPrepared::start_certificates`), its error naming the file.
pub fn certificates(prepared: &FloorPrepared) -> Result<(LayerLevel, Vec<bool>), CliError> {
    prepared
        .start_certificates()
        .map_err(|e| CliError::Navigator {
            scenario: prepared.path.clone(),
            error: harmonav_rs::NavError::Floor(e),
        })
}

/// What `check` says of `c_s` (docs/maths.md §13.9).
fn slide_line(level: &LayerLevel) -> String {
    if level.phi_slide == f64::INFINITY {
        "c_s = 1: the slide along that edge has no rest point, so convergence is certified from \
         every start of the certified region"
            .to_string()
    } else if level.phi_slide == f64::NEG_INFINITY {
        "c_s not computed (the map is too large for its covering, or a cell could not be \
         bounded): c_δ alone certifies"
            .to_string()
    } else {
        format!(
            "c_s = {:.6} (phi_k {:.4}): below it the slide along that edge cannot rest{}",
            level.slide(),
            level.phi_slide,
            level.slide_at.map_or(String::new(), |p| format!(
                "; a rest point may lie near ({:.3}, {:.3})",
                p.x, p.y
            ))
        )
    }
}

/// `harmonav check` on a floor plan: the file loads and its map is solved.
///
/// It also certifies `c_δ` and `c_s` over the walls (`FloorField::certify_level`,
/// docs/maths.md §13.5 and §13.9) and says which of the file's starts lie below one of them:
/// from those convergence is certified (the continuous law's sublevel set stays inside `W_δ`,
/// or its slide along `∂W_δ` cannot rest there); from the others the hold still keeps every
/// step clear.
pub fn cmd_check_floor(prepared: &FloorPrepared) -> Result<bool, CliError> {
    out!(
        "ok: floor plan, {} boundary elements, {} holes, δ = {} m, solved in {:.2} s",
        prepared.floor.map().elements().len(),
        prepared.floor.walls().holes().len(),
        prepared.floor.delta(),
        prepared.setup_seconds
    );
    if let Some(specks) = prepared.specks {
        match specks.largest_at {
            None => out!("specks: none dropped from the map"),
            Some(at) => out!(
                "specks: {} occupied island(s) of {} pixel(s) in all dropped from the map as \
                 noise (floor_plan.speck_pixels); the largest, {} pixel(s), at ({}, {}); a run \
                 is still judged against every pixel of the map",
                specks.count,
                specks.pixels,
                specks.largest,
                Shown(at[0]),
                Shown(at[1])
            ),
        }
    }
    let (level, below) = certificates(prepared)?;
    out!(
        "c_δ = {:.6} certified on the edge of the certified region ({}, {} cells{})",
        level.certified(),
        match (level.phi_sampled.is_finite(), level.skipped) {
            (true, 0) => format!("sampled least Θ {:.6}", level.sampled()),
            (true, n) => format!(
                "sampled least Θ {:.6}, {n} edge samples not evaluated",
                level.sampled()
            ),
            (false, n) => format!("no edge sample could be evaluated ({n} tried)"),
        },
        level.evaluations,
        if level.unresolved > 0 {
            format!(", {} at the depth limit", level.unresolved)
        } else {
            String::new()
        }
    );
    out!("{}", slide_line(&level));
    out!(
        "{} of {} starts certified (below c_δ or c_s); the others run under the hold, clear \
         at every step",
        below.iter().filter(|&&b| b).count(),
        below.len()
    );
    for (s, b) in prepared.starts.iter().zip(&below) {
        out!(
            "  start ({:.3}, {:.3}): {}",
            Shown(s.x),
            Shown(s.y),
            if *b { "certified" } else { "not certified" }
        );
    }
    if let Some(chain) = &prepared.funnels {
        let inside = prepared
            .starts
            .iter()
            .filter(|&&p| chain.entry(p).is_some())
            .count();
        out!(
            "floor_plan.funnels: a chain of {} funnel{} certifies convergence from {:.1} % of \
             the reachable free area and {inside} of {} starts (docs/maths.md §13.10)",
            chain.funnels.len(),
            if chain.funnels.len() == 1 { "" } else { "s" },
            100.0 * chain.fraction(),
            prepared.starts.len()
        );
    }
    Ok(true)
}

/// `harmonav run` on a floor plan: the file's start under its model (or `--model`), every
/// guarantee of [`FloorSummary`] judged, the summary printed (or as JSON), and with `--out`
/// the folder checked before the run, `run.mcap` streamed during it, and `trajectory.svg` and
/// `summary.json` added after it as one set ([`FloorOutputs`]). `Ok(false)` when a guarantee
/// failed.
pub fn cmd_run_floor(prepared: &FloorPrepared, args: &RunArgs<'_>) -> Result<bool, CliError> {
    let mut outputs = match args.out {
        Some(dir) => Some(FloorOutputs::begin(dir, prepared).map_err(CliError::Out)?),
        None => None,
    };
    let model = model(args.controller);
    let start = prepared.starts[0];
    let physics = args.physics.into();
    let result = simulate_floor_observed(prepared, model, start, physics, &mut |e| {
        if let Some(o) = outputs.as_mut() {
            o.observe(e);
        }
    })
    .map_err(|error| CliError::Run {
        scenario: args.path.to_path_buf(),
        error,
    })?;
    let summary = FloorSummary::new(prepared, model, start, &result);
    let written = args
        .out
        .zip(outputs)
        .map(|(dir, o)| o.finish(&summary, &result).map(|_| dir));
    if args.json {
        print_json(&summary)?;
    } else {
        print_floor_summary(&summary);
        if let Some(Ok(dir)) = written {
            out!("  outputs in {}", dir.display());
        }
    }
    if let Some(Err(e)) = written {
        return Err(CliError::Write(e));
    }
    Ok(summary.all_passed())
}

fn print_floor_summary(s: &FloorSummary) {
    print_head(
        &format!(
            "{} ({:?} model, {} physics, floor plan of {} elements, δ = {} m)",
            s.name, s.model, s.physics, s.elements, s.delta
        ),
        s.reached,
        [s.time_s, s.final_distance, s.min_clearance, s.max_speed],
        s.speed_bound,
        &s.outcome,
    );
    if let Some(e) = &s.error {
        out!("  the navigator refused: {e}");
    }
    print_guarantees(&s.guarantees);
}

/// `harmonav eval` on a floor plan: `Θ` with every obstacle known (grown by radius + margin,
/// as the navigator grows them) at each `--at` point; a point outside the certified region or
/// inside an obstacle is a row with the reason.
pub fn cmd_eval_floor(
    prepared: &FloorPrepared,
    at: &[String],
    json: bool,
) -> Result<bool, CliError> {
    let points = parse_points(at)?;
    let navigator_error = |error| CliError::Navigator {
        scenario: prepared.path.clone(),
        error,
    };
    let mut nav = navigator(prepared, None).map_err(navigator_error)?;
    for o in &prepared.obstacles {
        nav.add_obstacle(o.clone()).map_err(navigator_error)?;
    }
    let why = |x, err: FieldError| match err {
        FieldError::InObstacle { obstacle } => {
            format!("inside obstacle {}", obstacle_name(prepared, obstacle))
        }
        // Inside the room but closer than δ to a wall (issue 56, D19.1: it was called "on or
        // outside the workspace boundary").
        FieldError::Outside
            if nav.field().locate(x) == Some(harmonav_rs::floorplan::NotFree::BoundaryLayer) =>
        {
            format!(
                "in the boundary layer (closer than radius + margin to a wall, within δ = {} m \
                 of the solved region's edge): outside the certified region W_δ, where Θ is \
                 evaluated",
                Shown(nav.field().floor().delta())
            )
        }
        err => err.to_string(),
    };
    let rows: Vec<_> = points
        .iter()
        .map(|&x| (x, nav.field().eval(x).map_err(|e| why(x, e))))
        .collect();
    print_rows(&rows, json)
}
