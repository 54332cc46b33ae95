//! `harmonav run`: a scenario's run with every guarantee checked, and its outputs.

use std::path::Path;

use harmonav_output::set::Outputs;
use harmonav_scenario::Prepared;
use harmonav_sim::guarantee::Guarantee;
use harmonav_sim::physics::simulate_observed;
use harmonav_sim::summary::Summary;
use harmonav_transform::Shown;

use crate::args::{ModelArg, PhysicsArg, model};
use crate::error::CliError;
use crate::text::{out, print_json};

/// What `harmonav run` was asked.
pub struct RunArgs<'a> {
    /// The scenario file (named in errors).
    pub path: &'a Path,
    /// `--model` (alias `--controller`).
    pub controller: Option<ModelArg>,
    /// `--physics`.
    pub physics: PhysicsArg,
    /// `--out`.
    pub out: Option<&'a Path>,
    /// `--json`.
    pub json: bool,
}

/// Runs the scenario: `--out` is checked before the run (every problem of the folder is
/// found then, and nothing is run), the recording streams into its staging folder during the
/// run (memory stays flat however long it is), the summary is printed after it, and then the
/// set of outputs is completed and moved into place; if that fails the summary has been
/// printed and the error follows. `Ok(false)` when a guarantee failed.
pub fn cmd_run(prepared: &Prepared, args: &RunArgs<'_>) -> Result<bool, CliError> {
    let mut outputs = match args.out {
        Some(dir) => Some(Outputs::begin(dir, prepared).map_err(CliError::Out)?),
        None => None,
    };
    let result = simulate_observed(
        prepared,
        model(args.controller),
        args.physics.into(),
        &mut |e| {
            if let Some(o) = outputs.as_mut() {
                o.observe(e);
            }
        },
    )
    .map_err(|error| CliError::Run {
        scenario: args.path.to_path_buf(),
        error,
    })?;
    let written = args
        .out
        .zip(outputs)
        .map(|(dir, o)| o.finish(&result).map(|_| dir));
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

/// The first lines of a run's summary: `title: goal reached` (or not), the motion
/// `[time_s, final_distance, min_clearance, max_speed]` with the speed bound if any, and the
/// outcome of a run that did not arrive.
pub fn print_head(
    title: &str,
    reached: bool,
    motion: [f64; 4],
    speed_bound: Option<f64>,
    outcome: &dyn std::fmt::Display,
) {
    out!(
        "{title}: {}",
        if reached {
            "goal reached"
        } else {
            "goal NOT reached"
        }
    );
    let [time_s, final_distance, min_clearance, max_speed] = motion;
    out!(
        "  time {time_s:.3} s, final distance {final_distance:.2e} m, min clearance \
         {:.4} m, max speed {:.3} m/s{}",
        Shown(min_clearance),
        Shown(max_speed),
        speed_bound.map_or(String::new(), |b| format!(" (bound {:.3})", Shown(b)))
    );
    if !reached {
        out!("  outcome: {outcome}");
    }
}

fn print_summary(s: &Summary) {
    print_head(
        &format!("{} ({:?} model, {} physics)", s.name, s.model, s.physics),
        s.reached,
        [s.time_s, s.final_distance, s.min_clearance, s.max_speed],
        s.speed_bound,
        &s.outcome,
    );
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
    print_guarantees(&s.guarantees);
}

/// The guarantees as a table: name, `pass` or `FAIL`, what was measured.
pub fn print_guarantees(guarantees: &[Guarantee]) {
    let width = guarantees.iter().map(|g| g.name().len()).max().unwrap_or(0);
    for g in guarantees {
        out!(
            "  {:width$}  {}  {}",
            g.name(),
            if g.passed { "pass" } else { "FAIL" },
            g.detail()
        );
    }
}
