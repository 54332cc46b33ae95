//! `harmonav sweep`: the law from seeded random starts (global sensing), in parallel; on a
//! floor plan, from every start of the file. Both print the same [`Report`].

use harmonav_scenario::Prepared;
use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_sim::sweep::{Report, check_count, random_starts, sweep, sweep_floor};

use crate::args::{ModelArg, model};
use crate::error::CliError;
use crate::text::{out, print_json};

/// The threads a command may use: the machine's cores (2 when unknown).
pub fn threads() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get())
}

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
    let model = model(controller).unwrap_or(prepared.scenario.robot.model);
    let outcomes = sweep(prepared, &points, model, threads())?;
    print_report(&Report::of(&points, &outcomes), json)
}

/// Runs every start of a floor plan (its `robot.start`, then its seeded `[starts]`) by the
/// built-in floor loop and reports their outcomes as [`cmd_sweep`] does. `Ok(false)` when a
/// start did not arrive.
pub fn cmd_sweep_floor(
    prepared: &FloorPrepared,
    controller: Option<ModelArg>,
    json: bool,
) -> Result<bool, CliError> {
    let model = model(controller).unwrap_or(prepared.scenario.robot.model);
    let outcomes = sweep_floor(prepared, model, threads())?;
    print_report(&Report::of(&prepared.starts, &outcomes), json)
}

/// The report as JSON, or its counts on one line and a line per start that did not arrive.
fn print_report(report: &Report, json: bool) -> Result<bool, CliError> {
    if json {
        print_json(report)?;
    } else {
        let counts = &report.counts;
        let refused = match counts.command_refused {
            0 => String::new(),
            n => format!(", {n} commands refused"),
        };
        out!(
            "{} of {} starts reached the goal; {} collisions, {} left the workspace, {} \
             stalled, {} timed out, {} step collapses{refused}, {} invalid starts; median \
             {:.2} s, max {:.2} s",
            counts.reached,
            report.starts,
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
