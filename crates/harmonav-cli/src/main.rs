//! `harmonav`: run, evaluate and inspect navigation scenarios.
//!
//! Exit codes: 0 success, 1 a guarantee failed, 2 bad input (with a message on stderr), 130
//! interrupted (Ctrl-C or SIGTERM; `--out` then holds its previous outputs or the new ones,
//! complete, and no staging folder).
//!
//! One file per command, each a thin call into harmonav-sim: [`run`], [`eval`], [`census`],
//! [`sweep`] (`check` is the load alone, and with `--json` [`check`]'s one object); floor-plan files (`[floor_plan]`) go to [`floor`]
//! (`run`, `eval`, `check`) and [`sweep`] (`cmd_sweep_floor`); the options they share and the
//! loading of the scenario in [`args`], the errors in [`error`], the terminal output (control
//! characters escaped) in [`text`].

mod args;
mod census;
mod check;
mod error;
mod eval;
mod floor;
mod run;
mod sweep;
mod text;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use harmonav_scenario::floorplan::FileKind;
use harmonav_sim::sweep::SweepError;

use crate::args::{DampingArg, KArg, ModelArg, PhysicsArg, load};
use crate::error::CliError;
use crate::text::{escape, escape_lines, out};

#[derive(Parser)]
#[command(
    name = "harmonav",
    version,
    about = "Provably correct navigation with harmonic navigation functions"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario and check every guarantee.
    Run {
        scenario: PathBuf,
        /// Override the scenario's robot model (the file's `[expect]` then does not apply).
        #[arg(long = "model", visible_alias = "controller")]
        controller: Option<ModelArg>,
        /// The integrator: the built-in one or the rapier2d cross-check (star worlds and floor
        /// plans).
        #[arg(long, default_value = "builtin")]
        physics: PhysicsArg,
        /// Write summary.json, run.mcap, trajectory.svg (and speed.svg, energy.svg) here; checked
        /// before the run.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Override the scenario's `[field] k` policy.
        #[arg(long = "k", value_name = "POLICY")]
        k: Option<KArg>,
        /// Override the scenario's `[controller] damping` policy (dynamic law).
        #[arg(long, value_name = "POLICY")]
        damping: Option<DampingArg>,
        /// Print the summary as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Evaluate the navigation function (all obstacles known) at points.
    Eval {
        scenario: PathBuf,
        /// A point `X,Y` (repeatable; negative coordinates work: `--at -1.5,-0.2`).
        #[arg(
            long = "at",
            required = true,
            allow_hyphen_values = true,
            value_name = "X,Y"
        )]
        at: Vec<String>,
        /// Override the scenario's `[field] k` policy.
        #[arg(long = "k", value_name = "POLICY")]
        k: Option<KArg>,
        #[arg(long)]
        json: bool,
    },
    /// Find the critical points of Θ (all obstacles known).
    Census {
        scenario: PathBuf,
        /// Override the scenario's `[field] k` policy.
        #[arg(long = "k", value_name = "POLICY")]
        k: Option<KArg>,
        #[arg(long)]
        json: bool,
    },
    /// Follow the law from random starts (global sensing), in parallel; on a floor plan, from
    /// every start of the file (`robot.start` and its `[starts]`).
    Sweep {
        scenario: PathBuf,
        /// How many seeded random starts (required for a star world; on a floor plan it
        /// overrides `[starts] count`).
        #[arg(long)]
        starts: Option<usize>,
        /// The starts' seed (default 1; on a floor plan it overrides `[starts] seed`).
        #[arg(long)]
        seed: Option<u64>,
        #[arg(long = "model", visible_alias = "controller")]
        controller: Option<ModelArg>,
        /// Override the scenario's `[field] k` policy.
        #[arg(long = "k", value_name = "POLICY")]
        k: Option<KArg>,
        /// Override the scenario's `[controller] damping` policy (dynamic law).
        #[arg(long, value_name = "POLICY")]
        damping: Option<DampingArg>,
        #[arg(long)]
        json: bool,
    },
    /// Validate a scenario file; on a floor plan, certify c_δ and say which starts lie below
    /// it.
    Check {
        scenario: PathBuf,
        /// Print one JSON object: the map's size and set-up time, c_δ, each start's
        /// certificate and the certified fraction of the reachable free area.
        #[arg(long)]
        json: bool,
        /// With --json on a floor plan: also build a chain of certified funnels towards
        /// intermediate goals (docs/maths.md §13.10) and report the fraction their union
        /// certifies.
        #[arg(long, requires = "json")]
        funnels: bool,
    },
}

fn main() -> ExitCode {
    // clap's messages quote the arguments: escaped like every other line (--help and
    // --version go to stdout as clap writes them).
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            eprint!("{}", escape_lines(&e.render().to_string()));
            return ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2));
        }
        Err(e) => e.exit(),
    };
    // Ctrl-C or SIGTERM: wait for an output set being moved into place, remove any staging
    // folder not yet committed, and exit with 130 (128 + SIGINT). Without a handler the default
    // action would leave a staging folder behind.
    let handler = ctrlc::set_handler(|| {
        let _no_new_set = harmonav_output::atomic::abandon_staged();
        eprintln!("harmonav: interrupted; no output was changed");
        std::process::exit(130);
    });
    if let Err(e) = handler {
        eprintln!("harmonav: cannot install the interrupt handler: {e}");
    }
    match dispatch(cli.command) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("harmonav: {}", escape(&e.to_string()));
            ExitCode::from(2)
        }
    }
}

/// Runs one command: `Ok(false)` when a guarantee failed (or a start did not arrive).
fn dispatch(command: Command) -> Result<bool, CliError> {
    // A floor plan (a `[floor_plan]` table) has its own loader and loop.
    let floor_plan = |path: &std::path::Path| -> Result<bool, CliError> {
        if path == std::path::Path::new("-") {
            return Err(CliError::Stdin);
        }
        Ok(FileKind::of(path)? == FileKind::FloorPlan)
    };
    match command {
        Command::Run {
            scenario,
            controller,
            physics,
            out,
            k,
            damping,
            json,
        } => {
            let args = run::RunArgs {
                path: &scenario,
                controller,
                physics,
                out: out.as_deref(),
                json,
            };
            if floor_plan(&scenario)? {
                return floor::cmd_run_floor(&floor::load_floor(&scenario, k, damping)?, &args);
            }
            run::cmd_run(&load(&scenario, k, damping)?, &args)
        }
        Command::Eval {
            scenario,
            at,
            k,
            json,
        } => {
            if floor_plan(&scenario)? {
                let floor = floor::load_floor(&scenario, k, None)?;
                return floor::cmd_eval_floor(&floor, &at, json);
            }
            eval::cmd_eval(&load(&scenario, k, None)?, &at, json)
        }
        Command::Census { scenario, k, json } => {
            if floor_plan(&scenario)? {
                let floor = floor::load_floor(&scenario, k, None)?;
                return census::cmd_census_floor(&floor, json);
            }
            census::cmd_census(&load(&scenario, k, None)?, json)
        }
        Command::Sweep {
            scenario,
            starts,
            seed,
            controller,
            k,
            damping,
            json,
        } => {
            // A start that cannot be run names the file.
            let named = |e: CliError| match e {
                CliError::Sweep(error @ SweepError::Run { .. }) => CliError::SweepStart {
                    scenario: scenario.clone(),
                    error,
                },
                e => e,
            };
            if floor_plan(&scenario)? {
                let floor = floor::load_floor_starts(&scenario, k, damping, starts, seed)?;
                return sweep::cmd_sweep_floor(&floor, controller, json).map_err(named);
            }
            let starts = starts.ok_or(CliError::StartsRequired {
                scenario: scenario.clone(),
            })?;
            sweep::cmd_sweep(
                &load(&scenario, k, damping)?,
                starts,
                seed.unwrap_or(1),
                controller,
                json,
            )
            .map_err(named)
        }
        Command::Check {
            scenario,
            json,
            funnels,
        } => {
            if floor_plan(&scenario)? {
                let floor = floor::load_floor(&scenario, None, None)?;
                if json {
                    return check::cmd_check_floor_json(&floor, funnels);
                }
                return floor::cmd_check_floor(&floor);
            }
            let clock = std::time::Instant::now();
            let prepared = load(&scenario, None, None)?;
            if json {
                let setup_s = clock.elapsed().as_secs_f64();
                return check::cmd_check_star_json(&scenario, &prepared, setup_s);
            }
            out!("ok");
            Ok(true)
        }
    }
}
