//! `harmonav census`: the critical points of `Θ` (all obstacles known).

use harmonav_scenario::Prepared;
use serde_json::{Value, json};

use crate::error::CliError;
use crate::text::{out, print_json};

/// Counts and lists the critical points of the scenario's `Θ`.
pub fn cmd_census(prepared: &Prepared, json: bool) -> Result<bool, CliError> {
    let field = prepared.global_field()?;
    let census = field.census();
    let points: Vec<Value> = census
        .points
        .iter()
        .map(|p| json!({ "x": p.x.x, "y": p.x.y, "kind": p.kind.as_str(), "eigenvalues": p.eigenvalues }))
        .collect();
    let out = json!({
        "minima": census.minima, "saddles": census.saddles, "degenerate": census.degenerate,
        "k": field.k(), "k_policy": field.k_policy().as_str(), "points": points,
    });
    if json {
        print_json(&out)?;
    } else {
        out!(
            "{} minimum, {} saddles, {} degenerate (M = {}, k = {} from \"{}\")",
            census.minima,
            census.saddles,
            census.degenerate,
            prepared.truth.workspace.obstacles().len(),
            field.k(),
            field.k_policy()
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
