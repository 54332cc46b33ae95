//! `harmonav census`: the critical points of `Θ` (all obstacles known), in a star world or on
//! a floor plan (its holes and every obstacle of the file sensed).

use harmonav_field::{Census, KPolicy};
use harmonav_scenario::Prepared;
use harmonav_scenario::floorplan::FloorPrepared;
use serde_json::{Value, json};

use crate::error::CliError;
use crate::text::{out, print_json};

/// Counts and lists the critical points of the scenario's `Θ`.
pub fn cmd_census(prepared: &Prepared, json: bool) -> Result<bool, CliError> {
    let field = prepared.global_field()?;
    let m = prepared.truth.workspace.obstacles().len();
    print_census(&field.census(), field.k(), field.k_policy(), m, json)
}

/// [`cmd_census`] on a floor plan: `Θ` over its holes and every obstacle of the file (grown
/// by radius + margin, as the navigator grows a sensed one), its saddles pulled back through
/// `Phi` ([`harmonav_rs::floorplan::FloorField::census`]); `M` counts the holes and obstacles.
pub fn cmd_census_floor(prepared: &FloorPrepared, json: bool) -> Result<bool, CliError> {
    let named = |error| CliError::Navigator {
        scenario: prepared.path.clone(),
        error,
    };
    let mut nav = harmonav_sim::floor::navigator(prepared, None).map_err(named)?;
    for o in &prepared.obstacles {
        nav.add_obstacle(o.clone()).map_err(named)?;
    }
    let field = nav.field();
    let m = field.transform().holes() + prepared.obstacles.len();
    let census = field.census();
    // Saddles of phi_k whose preimage is not in W_δ: in the boundary layer (or beyond).
    let outside = field.point_world().critical_points().len() + 1 - census.points.len();
    if !json {
        print_census(&census, field.k(), field.k_policy(), m, false)?;
        out!("  {outside} saddle(s) of phi_k lie outside W_δ (in the boundary layer)");
        return Ok(true);
    }
    print_json(&json!({
        "minima": census.minima, "saddles": census.saddles, "degenerate": census.degenerate,
        "k": field.k(), "k_policy": field.k_policy().as_str(), "points": points(&census),
        "outside_certified_region": outside,
    }))?;
    Ok(true)
}

/// The points of `census` as JSON objects.
fn points(census: &Census) -> Vec<Value> {
    census
        .points
        .iter()
        .map(|p| json!({ "x": p.x.x, "y": p.x.y, "kind": p.kind.as_str(), "eigenvalues": p.eigenvalues }))
        .collect()
}

fn print_census(
    census: &Census,
    k: f64,
    k_policy: KPolicy,
    m: usize,
    json: bool,
) -> Result<bool, CliError> {
    let out = json!({
        "minima": census.minima, "saddles": census.saddles, "degenerate": census.degenerate,
        "k": k, "k_policy": k_policy.as_str(), "points": points(census),
    });
    if json {
        print_json(&out)?;
    } else {
        out!(
            "{} minimum, {} saddles, {} degenerate (M = {}, k = {} from \"{}\")",
            census.minima,
            census.saddles,
            census.degenerate,
            m,
            k,
            k_policy
        );
        for p in &census.points {
            let eigenvalues = p.eigenvalues.map_or("not resolvable".into(), |[a, b]| {
                format!("[{a:.6e}, {b:.6e}]")
            });
            out!(
                "  {:>18}  ({:.5}, {:.5})  eigenvalues {eigenvalues}",
                p.kind.as_str(),
                p.x.x,
                p.x.y
            );
        }
    }
    Ok(true)
}
