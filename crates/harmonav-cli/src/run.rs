//! `harmonav run`: a scenario's run with every guarantee checked, and its outputs.

use std::path::Path;

use harmonav_sim::physics::{Physics, simulate};
use harmonav_sim::record::{check_output_dir, write_outputs};
use harmonav_sim::run::Summary;
use harmonav_sim::scenario::Prepared;

use crate::args::{Controller, PhysicsArg, model};
use crate::error::CliError;
use crate::text::{out, print_json};

/// What `harmonav run` was asked.
pub struct RunArgs<'a> {
    /// The scenario file (named in errors).
    pub path: &'a Path,
    /// `--controller`.
    pub controller: Option<Controller>,
    /// `--physics`.
    pub physics: PhysicsArg,
    /// `--out`.
    pub out: Option<&'a Path>,
    /// `--json`.
    pub json: bool,
}

/// Runs the scenario: `--out` is checked before the run (every problem of the folder is
/// found then, and nothing is run), the summary is printed after it, and then the outputs
/// are written; if that fails the summary has been printed and the error follows.
/// `Ok(false)` when a guarantee failed.
pub fn cmd_run(prepared: &Prepared, args: &RunArgs<'_>) -> Result<bool, CliError> {
    if let Some(dir) = args.out {
        check_output_dir(dir).map_err(CliError::Out)?;
    }
    let physics = match args.physics {
        PhysicsArg::Builtin => Physics::Builtin,
        PhysicsArg::Rapier => Physics::Rapier,
    };
    let result =
        simulate(prepared, model(args.controller), physics).map_err(|error| CliError::Run {
            scenario: args.path.to_path_buf(),
            error,
        })?;
    let written = args
        .out
        .map(|dir| write_outputs(dir, prepared, &result).map(|_| dir));
    if args.json {
        print_json(&result.summary)?;
    } else {
        print_summary(&result.summary);
        if let Some(Ok(dir)) = written {
            out!("  outputs in {}", dir.display());
        }
    }
    if let Some(Err(e)) = written {
        return Err(CliError::Write(e));
    }
    Ok(result.summary.all_passed())
}

fn print_summary(s: &Summary) {
    out!(
        "{} ({:?} model, {} physics): {}",
        s.name,
        s.model,
        s.physics,
        if s.reached {
            "goal reached"
        } else {
            "goal NOT reached"
        }
    );
    out!(
        "  time {:.3} s, final distance {:.2e} m, min clearance {:.4} m, max speed {:.3} m/s{}",
        s.time_s,
        s.final_distance,
        s.min_clearance,
        s.max_speed,
        s.speed_bound
            .map_or(String::new(), |b| format!(" (bound {b:.3})"))
    );
    if !s.reached {
        out!("  outcome: {}", s.outcome);
    }
    for w in &s.warnings {
        out!("  warning: {w}");
    }
    // Obstacles known at the start (global sensing, or within d_min) are counted, not listed.
    let (at_start, later): (Vec<_>, Vec<_>) = s.discoveries.iter().partition(|d| d.time_s == 0.0);
    if !s.discoveries.is_empty() {
        let mut d: Vec<String> = later
            .iter()
            .map(|d| format!("{} {:.2} s", d.obstacle, d.time_s))
            .collect();
        match at_start.as_slice() {
            [] => {}
            [one] => d.insert(0, format!("{} known at the start", one.obstacle)),
            many => d.insert(0, format!("{} known at the start", many.len())),
        }
        out!("  discoveries: {}", d.join(", "));
    }
    let width = s
        .guarantees
        .iter()
        .map(|g| g.name().len())
        .max()
        .unwrap_or(0);
    for g in &s.guarantees {
        out!(
            "  {:width$}  {}  {}",
            g.name(),
            if g.passed { "pass" } else { "FAIL" },
            g.detail()
        );
    }
}
