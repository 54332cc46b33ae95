//! `harmonav check FILE --json`: one JSON object ([`CheckReport`]) for either kind of file,
//! the interface that outside checks read (issue 52): the map's size and set-up time, the
//! certified level `c_δ`, each start's certificate, and the fraction of the robot's reachable
//! free area from which convergence is certified.
//!
//! Everything is computed before anything is printed: an error leaves stdout empty.

use std::path::Path;
use std::time::Instant;

use harmonav_rs::KPolicy;
use harmonav_rs::floorplan::{FloorField, MAX_AREA_SAMPLES};
use harmonav_scenario::Prepared;
use harmonav_scenario::floorplan::FloorPrepared;
use nalgebra::Vector2;
use serde::Serialize;

use crate::error::CliError;
use crate::floor::certificates;
use crate::sweep::threads;
use crate::text::print_json;

/// One start of the file and whether convergence from it is certified.
#[derive(Serialize)]
pub struct StartReport {
    /// `[x, y]`, m.
    pub position: [f64; 2],
    /// Floor plan: `Θ(x₀) < c_δ`. Star world: by the theorem (a valid start).
    pub certified: bool,
}

/// What `check --json` prints. `None` fields are left out (those of the other kind of file).
#[derive(Serialize)]
pub struct CheckReport {
    /// The file, as given.
    pub file: String,
    /// `"floor_plan"` or `"star_world"`.
    pub kind: &'static str,
    /// Boundary elements of the harmonic map (0 for a star world, which has none).
    pub elements: usize,
    /// Seconds to set up: meshing and solving the harmonic map (floor plan), loading and
    /// validating the file (star world).
    pub setup_s: f64,
    /// Floor plan: the holes of the walls.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub holes: Option<usize>,
    /// Star world: the obstacles of the file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub obstacles: Option<usize>,
    /// Floor plan: `δ`, the uncertified layer's width, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delta: Option<f64>,
    /// Floor plan: `c_δ`, the certified lower bound of `Θ` on the edge of `W_δ`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub level: Option<f64>,
    /// Floor plan: the least `Θ` sampled on that edge (an upper bound of the true least).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub level_sampled: Option<f64>,
    /// Floor plan: seconds to certify `c_δ`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub level_s: Option<f64>,
    /// The fraction of the robot's reachable free area (centres at least radius + margin from
    /// the walls and from the file's obstacles, joined to `robot.start`) from which
    /// convergence is certified, in `[0, 1]`.
    pub certified_fraction: f64,
    /// How `certified_fraction` was found: `"grid"` (floor plan: samples below `c_δ` over the
    /// reachable samples) or `"theorem"` (star world: 1, docs/floorplans.md).
    pub basis: &'static str,
    /// Floor plan: the grid's cell, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub certified_grid_m: Option<f64>,
    /// Floor plan: the samples of the reachable free area.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reachable_samples: Option<usize>,
    /// Floor plan: the reachable free area, m² (samples × cell²).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reachable_area_m2: Option<f64>,
    /// Floor plan: the uncertified part in the layer, where `Θ` is not defined (between
    /// radius + margin and `δ` from the walls), as a fraction of the reachable area.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub uncertified_layer: Option<f64>,
    /// Floor plan: the uncertified part in `W_δ`, at or above `c_δ` (or where `Θ` could not
    /// be evaluated), as a fraction of the reachable area.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub uncertified_above_level: Option<f64>,
    /// Floor plan: seconds to sample the certified fraction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fraction_s: Option<f64>,
    /// `robot.start`, then the file's `[starts]` (floor plan).
    pub starts: Vec<StartReport>,
}

fn start(p: Vector2<f64>, certified: bool) -> StartReport {
    StartReport {
        position: [p.x, p.y],
        certified,
    }
}

/// `check --json` on a floor plan: `c_δ` and the starts as the text `check` finds them
/// (`FloorPrepared::start_certificates`), and the certified fraction on a grid
/// (`FloorField::certified_area` of the walls' `Θ`, before any obstacle is sensed, as for the
/// starts).
pub fn cmd_check_floor_json(prepared: &FloorPrepared) -> Result<bool, CliError> {
    let clock = Instant::now();
    let (level, below) = certificates(prepared)?;
    let level_s = clock.elapsed().as_secs_f64();
    let r = &prepared.scenario.robot;
    let goal = Vector2::new(r.goal[0], r.goal[1]);
    let field = FloorField::new(prepared.floor.clone(), goal, KPolicy::default()).map_err(|e| {
        CliError::Navigator {
            scenario: prepared.path.clone(),
            error: harmonav_rs::NavError::Floor(e),
        }
    })?;
    let clock = Instant::now();
    let area = field.certified_area(
        &level,
        prepared.starts[0],
        r.radius + r.margin,
        &prepared.obstacles,
        MAX_AREA_SAMPLES,
        threads(),
    );
    let fraction_s = clock.elapsed().as_secs_f64();
    let of_reachable = |n: usize| {
        if area.reachable == 0 {
            0.0
        } else {
            n as f64 / area.reachable as f64
        }
    };
    let floor = &prepared.floor;
    let report = CheckReport {
        file: prepared.path.display().to_string(),
        kind: "floor_plan",
        elements: floor.map().elements().len(),
        setup_s: prepared.setup_seconds,
        holes: Some(floor.walls().holes().len()),
        obstacles: None,
        delta: Some(floor.delta()),
        level: Some(level.certified()),
        level_sampled: level.phi_sampled.is_finite().then(|| level.sampled()),
        level_s: Some(level_s),
        certified_fraction: area.fraction(),
        basis: "grid",
        certified_grid_m: Some(area.cell),
        reachable_samples: Some(area.reachable),
        reachable_area_m2: Some(area.reachable_area()),
        uncertified_layer: Some(of_reachable(area.reachable - area.in_region)),
        uncertified_above_level: Some(of_reachable(area.in_region - area.certified)),
        fraction_s: Some(fraction_s),
        starts: prepared
            .starts
            .iter()
            .zip(&below)
            .map(|(&p, &b)| start(p, b))
            .collect(),
    };
    print_json(&report)?;
    Ok(true)
}

/// `check --json` on a star world: the file loads (`setup_s` the time it took); `Θ = σ∘φ_k∘T`
/// with `T` exact and `k > M` is a navigation function on the whole free space (the paper's
/// theorem, every obstacle known), so convergence is certified from every start but a set of
/// measure zero (the saddles' stable manifolds): `certified_fraction` 1 by `"theorem"`, and
/// `robot.start` (checked free on loading) certified.
pub fn cmd_check_star_json(
    path: &Path,
    prepared: &Prepared,
    setup_s: f64,
) -> Result<bool, CliError> {
    let r = &prepared.scenario.robot;
    let report = CheckReport {
        file: path.display().to_string(),
        kind: "star_world",
        elements: 0,
        setup_s,
        holes: None,
        obstacles: Some(prepared.scenario.obstacles.len()),
        delta: None,
        level: None,
        level_sampled: None,
        level_s: None,
        certified_fraction: 1.0,
        basis: "theorem",
        certified_grid_m: None,
        reachable_samples: None,
        reachable_area_m2: None,
        uncertified_layer: None,
        uncertified_above_level: None,
        fraction_s: None,
        starts: vec![start(Vector2::new(r.start[0], r.start[1]), true)],
    };
    print_json(&report)?;
    Ok(true)
}
