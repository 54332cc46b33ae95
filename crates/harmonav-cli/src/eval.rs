//! `harmonav eval`: the navigation function (all obstacles known) at points.

use harmonav_field::{FieldError, FieldEval};
use harmonav_scenario::Prepared;
use harmonav_transform::Shown;
use nalgebra::Vector2;
use serde_json::{Value, json};

use crate::error::CliError;
use crate::text::{out, print_json};

/// `X,Y` as a point of two finite numbers.
fn parse_point(s: &str) -> Result<Vector2<f64>, CliError> {
    let bad = || CliError::Point { arg: s.to_string() };
    match s.split(',').collect::<Vec<_>>().as_slice() {
        [x, y] => match (x.trim().parse::<f64>(), y.trim().parse::<f64>()) {
            (Ok(x), Ok(y)) if x.is_finite() && y.is_finite() => Ok(Vector2::new(x, y)),
            _ => Err(bad()),
        },
        _ => Err(bad()),
    }
}

/// `X,Y` for each `--at` argument.
pub fn parse_points(at: &[String]) -> Result<Vec<Vector2<f64>>, CliError> {
    at.iter().map(|s| parse_point(s)).collect()
}

/// Evaluates `Θ` at each `--at` point; a point outside the free space is a row with an error.
pub fn cmd_eval(prepared: &Prepared, at: &[String], json: bool) -> Result<bool, CliError> {
    let points = parse_points(at)?;
    let field = prepared.global_field()?;
    let why = |err: FieldError| match err {
        FieldError::InObstacle { obstacle } => {
            format!("inside obstacle {}", prepared.truth.names[obstacle])
        }
        err => err.to_string(),
    };
    let rows: Vec<_> = points
        .iter()
        .map(|&x| (x, field.eval(x).map_err(why)))
        .collect();
    print_rows(&rows, json)
}

/// Prints the rows of `eval`: `Θ`, `phi`, `h` and `∇Θ` at each point, or why there is none.
pub fn print_rows(
    rows: &[(Vector2<f64>, Result<FieldEval, String>)],
    json: bool,
) -> Result<bool, CliError> {
    if json {
        let rows: Vec<Value> = rows
            .iter()
            .map(|(x, r)| match r {
                Ok(e) => {
                    let mut row = json!({ "x": x.x, "y": x.y, "h": [e.h.x, e.h.y], "phi": e.phi, "value": e.value, "grad": [e.gradient.x, e.gradient.y] });
                    // JSON has no −∞: `phi` is null there, and the row says why (issue 56, D21).
                    if e.phi == f64::NEG_INFINITY {
                        row["note"] = json!("phi is -inf at the goal (Θ = 0)");
                    }
                    row
                }
                Err(error) => json!({ "x": x.x, "y": x.y, "error": error }),
            })
            .collect();
        print_json(&rows)?;
        return Ok(true);
    }
    out!(
        "{:>10} {:>10}  {:>12} {:>12}  {:>12}  {:>12}  grad",
        "x",
        "y",
        "h_x",
        "h_y",
        "phi",
        "Θ"
    );
    // A coordinate of 1e308 printed in fixed point had 309 digits (issue 56, D18).
    let at = |c: f64| format!("{:.4}", Shown(c));
    for (x, r) in rows {
        match r {
            Err(error) => out!("{:>10} {:>10}  error: {error}", at(x.x), at(x.y)),
            Ok(e) => out!(
                "{:>10} {:>10}  {:>12.6} {:>12.6}  {:>12.6}  {:>12.8}  ({:.3e}, {:.3e})",
                at(x.x),
                at(x.y),
                e.h.x,
                e.h.y,
                e.phi,
                e.value,
                e.gradient.x,
                e.gradient.y
            ),
        }
    }
    Ok(true)
}
