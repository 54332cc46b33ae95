//! `harmonav sweep`: the law from seeded random starts (global sensing), in parallel.

use harmonav_scenario::Prepared;
use harmonav_sim::sweep::{Report, check_count, random_starts, sweep};

use crate::args::{ModelArg, model};
use crate::error::CliError;
use crate::text::{out, print_json};

/// Runs `starts` seeded random starts and reports their outcomes (a start outside the free
/// space is one of them, named `starts[i]`). `Ok(false)` when a start did not arrive.
pub fn cmd_sweep(
    prepared: &Prepared,
    starts: usize,
    seed: u64,
    controller: Option<ModelArg>,
    json: bool,
) -> Result<bool, CliError> {
    check_count(starts)?;
    let points = random_starts(prepared, starts, seed)?;
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let model = model(controller).unwrap_or(prepared.scenario.robot.model);
    let outcomes = sweep(prepared, &points, model, threads)?;
    let report = Report::of(&points, &outcomes);
    if json {
        print_json(&report)?;
    } else {
        let counts = &report.counts;
        out!(
            "{} of {starts} starts reached the goal; {} collisions, {} left the workspace, {} \
             stalled, {} timed out, {} step collapses, {} invalid starts; median {:.2} s, max \
             {:.2} s",
            counts.reached,
            counts.collisions,
            counts.left_workspace,
            counts.stalled,
            counts.timed_out,
            counts.step_collapsed,
            counts.invalid_starts,
            report.median_time_s.unwrap_or(f64::NAN),
            report.max_time_s.unwrap_or(f64::NAN)
        );
        for f in &report.failures {
            out!("  {:?} : {}", f.start, f.reason);
        }
    }
    Ok(report.all_reached())
}
