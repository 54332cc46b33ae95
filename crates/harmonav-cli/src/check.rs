//! `harmonav check FILE --json`: one JSON object ([`CheckReport`]) for either kind of file,
//! the interface that outside checks read (issue 52): the map's size and set-up time, the
//! certified level `c_δ`, each start's certificate, and the fraction of the robot's reachable
//! free area from which convergence is certified.
//!
//! Everything is computed before anything is printed: an error leaves stdout empty.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use harmonav_rs::floorplan::{FloorField, FunnelOptions, MAX_AREA_SAMPLES};
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

/// What `check --json` prints: the keys of both kinds of file, then a floor plan's own.
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
    /// The fraction of the robot's reachable free area (centres at least radius + margin from
    /// the walls and from the file's obstacles, joined to `robot.start`) from which
    /// convergence is certified, in `[0, 1]`.
    pub certified_fraction: f64,
    /// How `certified_fraction` was found: `"grid"` (floor plan: samples below `c_δ` or `c_s`
    /// over the reachable samples), `"funnels"` (a floor plan whose navigator follows a chain
    /// of funnels, `floor_plan.funnels`: the samples in their union) or `"theorem"` (star
    /// world: 1).
    pub basis: &'static str,
    /// Star world: the obstacles of the file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub obstacles: Option<usize>,
    /// Floor plan: its own keys, at the same level.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub floor: Option<FloorReport>,
    /// `robot.start`, then the file's `[starts]` (floor plan).
    pub starts: Vec<StartReport>,
}

/// The keys of `check --json` that only a floor plan has.
#[derive(Serialize)]
pub struct FloorReport {
    /// The holes of the walls.
    pub holes: usize,
    /// `δ`, the uncertified layer's width, m.
    pub delta: f64,
    /// `c_δ`, the certified lower bound of `Θ` on the edge of `W_δ`.
    pub level: f64,
    /// The least `Θ` sampled on that edge (an upper bound of the true least); `None` when no
    /// sample could be evaluated.
    pub level_sampled: Option<f64>,
    /// `c_s`, the certified least `Θ` where the slide along that edge may rest
    /// (docs/maths.md §13.9): 1 when it cannot rest anywhere, 0 when not computed. A start is
    /// certified below `c_δ` or `c_s`.
    pub slide_level: f64,
    /// Where a rest point of the slide may lie (the cell that set `c_s`), if anywhere.
    pub slide_rest_at: Option<[f64; 2]>,
    /// Seconds to certify `c_δ`.
    pub level_s: f64,
    /// The grid's cell, m.
    pub certified_grid_m: f64,
    /// The samples of the reachable free area.
    pub reachable_samples: usize,
    /// The reachable free area, m² (samples × cell²).
    pub reachable_area_m2: f64,
    /// The uncertified part in the layer, where `Θ` is not defined (between radius + margin
    /// and `δ` from the walls), as a fraction of the reachable area.
    pub uncertified_layer: f64,
    /// The uncertified part in `W_δ`, at or above both `c_δ` and `c_s` (or where `Θ` could
    /// not be evaluated), as a fraction of the reachable area.
    pub uncertified_above_level: f64,
    /// Seconds to sample the certified fraction.
    pub fraction_s: f64,
    /// With `--funnels`: the chain of certified funnels (docs/maths.md §13.10).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub funnels: Option<FunnelReport>,
}

/// What `check --json --funnels` reports of the chain of funnels (`FloorField::funnels`).
#[derive(Serialize)]
pub struct FunnelReport {
    /// Funnels in the chain, the file's goal's included.
    pub count: usize,
    /// The fraction of the reachable free area in their union, on the same grid as
    /// `certified_fraction`.
    pub certified_fraction: f64,
    /// The most switches from a funnel to the file's goal.
    pub deepest: usize,
    /// Each funnel's goal, `[x, y]`, and its parent's index (`null` for the file's goal).
    pub goals: Vec<([f64; 2], Option<usize>)>,
    /// For each start of `starts`: whether it lies in a funnel.
    pub starts: Vec<bool>,
    /// Seconds to build the chain (`None` when the file's own was built at load).
    pub seconds: Option<f64>,
    /// Whether the navigator follows it (`floor_plan.funnels = true`): then
    /// `certified_fraction` and `starts[].certified` are the chain's.
    pub followed: bool,
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
pub fn cmd_check_floor_json(prepared: &FloorPrepared, funnels: bool) -> Result<bool, CliError> {
    let clock = Instant::now();
    let (level, below) = certificates(prepared)?;
    let level_s = clock.elapsed().as_secs_f64();
    let r = &prepared.scenario.robot;
    let goal = Vector2::new(r.goal[0], r.goal[1]);
    let field =
        FloorField::new(prepared.floor.clone(), goal, prepared.scenario.field.k).map_err(|e| {
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
    // The chain of funnels: the file's (`floor_plan.funnels`, which the navigator follows),
    // or built here for `--funnels`.
    let chain = match &prepared.funnels {
        Some(chain) => Some((chain.clone(), None)),
        None if funnels => {
            let clock = Instant::now();
            let options = FunnelOptions {
                threads: threads(),
                ..FunnelOptions::default()
            };
            let chain = field.funnels(
                Some(level),
                prepared.starts[0],
                r.radius + r.margin,
                &prepared.obstacles,
                &options,
            );
            Some((Arc::new(chain), Some(clock.elapsed().as_secs_f64())))
        }
        None => None,
    };
    let funnels = chain.as_ref().map(|(chain, seconds)| FunnelReport {
        count: chain.funnels.len(),
        certified_fraction: chain.fraction(),
        deepest: chain.deepest(),
        goals: chain
            .funnels
            .iter()
            .map(|f| ([f.goal.x, f.goal.y], f.parent))
            .collect(),
        starts: prepared
            .starts
            .iter()
            .map(|&p| chain.entry(p).is_some())
            .collect(),
        seconds: *seconds,
        followed: prepared.funnels.is_some(),
    });
    // What the navigator certifies: the chain's union when it follows one.
    let followed = funnels.as_ref().filter(|f| f.followed);
    let (certified_fraction, basis) = match followed {
        Some(f) => (f.certified_fraction, "funnels"),
        None => (area.fraction(), "grid"),
    };
    let below: Vec<bool> = match followed {
        Some(f) => f.starts.clone(),
        None => below,
    };
    let floor = &prepared.floor;
    let report = CheckReport {
        file: prepared.path.display().to_string(),
        kind: "floor_plan",
        elements: floor.map().elements().len(),
        setup_s: prepared.setup_seconds,
        certified_fraction,
        basis,
        obstacles: None,
        floor: Some(FloorReport {
            holes: floor.walls().holes().len(),
            delta: floor.delta(),
            level: level.certified(),
            level_sampled: level.phi_sampled.is_finite().then(|| level.sampled()),
            slide_level: level.slide(),
            slide_rest_at: level.slide_at.map(|p| [p.x, p.y]),
            level_s,
            certified_grid_m: area.cell,
            reachable_samples: area.reachable,
            reachable_area_m2: area.reachable_area(),
            uncertified_layer: area.layer_fraction(),
            uncertified_above_level: area.above_level_fraction(),
            fraction_s,
            funnels,
        }),
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
        certified_fraction: 1.0,
        basis: "theorem",
        obstacles: Some(prepared.scenario.obstacles.len()),
        floor: None,
        starts: vec![start(Vector2::new(r.start[0], r.start[1]), true)],
    };
    print_json(&report)?;
    Ok(true)
}
