//! `harmonav`: run, evaluate and inspect navigation scenarios.
//!
//! Exit codes: 0 success, 1 a guarantee failed, 2 bad input (with a message on stderr), 130
//! interrupted (Ctrl-C or SIGTERM; `--out` then holds its previous outputs or the new ones,
//! complete, and no staging folder).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use harmonav_control::DampingPolicy;
use harmonav_field::{FieldError, KPolicy};
use harmonav_sim::physics::{Physics, simulate};
use harmonav_sim::record::{check_output_dir, write_outputs};
use harmonav_sim::run::Summary;
use harmonav_sim::scenario::{Model, Prepared, Scenario};
use harmonav_sim::sweep::{Report, random_starts, sweep};
use nalgebra::Vector2;
use serde_json::{Value, json};

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

#[derive(Clone, Copy, ValueEnum)]
enum Controller {
    Kinematic,
    Dynamic,
}

/// `--k`: overrides the scenario's `[field] k`.
#[derive(Clone, Copy, ValueEnum)]
enum KArg {
    /// `k = n + 1`, exactly the paper.
    Paper,
    /// The default: `k` from the known world (docs/maths.md §8).
    Auto,
}

impl From<KArg> for KPolicy {
    fn from(k: KArg) -> Self {
        match k {
            KArg::Paper => KPolicy::Paper,
            KArg::Auto => KPolicy::Auto,
        }
    }
}

/// `--damping`: overrides the scenario's `[controller] damping`.
#[derive(Clone, Copy, ValueEnum)]
enum DampingArg {
    /// Eq. `dissipationfun` on Θ, exactly the paper.
    Paper,
    /// The default: damping critical at the goal, on the shaped potential (docs/maths.md §9).
    Auto,
}

impl From<DampingArg> for DampingPolicy {
    fn from(d: DampingArg) -> Self {
        match d {
            DampingArg::Paper => DampingPolicy::Paper,
            DampingArg::Auto => DampingPolicy::Auto,
        }
    }
}

#[derive(Clone, Copy, ValueEnum, PartialEq)]
enum PhysicsArg {
    Builtin,
    Rapier,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario and check every guarantee.
    Run {
        scenario: PathBuf,
        /// Override the scenario's robot model (the file's `[expect]` then does not apply).
        #[arg(long)]
        controller: Option<Controller>,
        /// The integrator: the built-in one or the rapier2d cross-check.
        #[arg(long, default_value = "builtin")]
        physics: PhysicsArg,
        /// Write summary.json, run.mcap, trajectory.svg (and speed.svg) here.
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
    /// Follow the law from random starts (global sensing), in parallel.
    Sweep {
        scenario: PathBuf,
        #[arg(long)]
        starts: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[arg(long)]
        controller: Option<Controller>,
        /// Override the scenario's `[field] k` policy.
        #[arg(long = "k", value_name = "POLICY")]
        k: Option<KArg>,
        /// Override the scenario's `[controller] damping` policy (dynamic law).
        #[arg(long, value_name = "POLICY")]
        damping: Option<DampingArg>,
        #[arg(long)]
        json: bool,
    },
    /// Validate a scenario file.
    Check { scenario: PathBuf },
}

/// `println!` that ends the program quietly when stdout is closed (e.g. piped into `head`)
/// instead of panicking.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout().lock(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
            eprintln!("harmonav: cannot write the output: {e}");
            std::process::exit(2);
        }
    }};
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Ctrl-C or SIGTERM: wait for an output set being moved into place, remove any staging
    // folder not yet committed, and exit with 130 (128 + SIGINT). Without a handler the default
    // action would leave a staging folder behind.
    let handler = ctrlc::set_handler(|| {
        let _no_new_set = harmonav_sim::atomic::abandon_staged();
        eprintln!("harmonav: interrupted; no output was changed");
        std::process::exit(130);
    });
    if let Err(e) = handler {
        eprintln!("harmonav: cannot install the interrupt handler: {e}");
    }
    let result = match cli.command {
        Command::Run {
            scenario,
            controller,
            physics,
            out,
            k,
            damping,
            json,
        } => load(&scenario, k, damping)
            .and_then(|p| cmd_run(&scenario, &p, controller, physics, out.as_deref(), json)),
        Command::Eval {
            scenario,
            at,
            k,
            json,
        } => load(&scenario, k, None).and_then(|p| cmd_eval(&p, &at, json)),
        Command::Census { scenario, k, json } => {
            load(&scenario, k, None).and_then(|p| cmd_census(&p, json))
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
            load(&scenario, k, damping).and_then(|p| cmd_sweep(&p, starts, seed, controller, json))
        }
        Command::Check { scenario } => load(&scenario, None, None).map(|_| {
            out!("ok");
            true
        }),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(message) => {
            eprintln!("harmonav: {message}");
            ExitCode::from(2)
        }
    }
}

/// Prints a value as pretty JSON (the `--json` output of every command).
fn print_json(value: &impl serde::Serialize) -> Result<(), String> {
    out!(
        "{}",
        serde_json::to_string_pretty(value).map_err(|e| e.to_string())?
    );
    Ok(())
}

/// Loads and validates a scenario; `k` and `damping` override its `[field] k` and
/// `[controller] damping` policies.
fn load(path: &Path, k: Option<KArg>, damping: Option<DampingArg>) -> Result<Prepared, String> {
    if path == Path::new("-") {
        return Err(
            "`-`: reading a scenario from standard input is not supported; give the file's path"
                .into(),
        );
    }
    let mut prepared = Scenario::load(path).map_err(|e| e.to_string())?;
    if let Some(k) = k {
        prepared.scenario.field.k = k.into();
    }
    if let Some(d) = damping {
        prepared.scenario.controller.damping = d.into();
    }
    Ok(prepared)
}

fn model(c: Option<Controller>) -> Option<Model> {
    c.map(|c| match c {
        Controller::Kinematic => Model::Kinematic,
        Controller::Dynamic => Model::Dynamic,
    })
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

fn cmd_run(
    path: &Path,
    prepared: &Prepared,
    controller: Option<Controller>,
    physics: PhysicsArg,
    out: Option<&Path>,
    json: bool,
) -> Result<bool, String> {
    if let Some(dir) = out {
        check_output_dir(dir)?;
    }
    let physics = match physics {
        PhysicsArg::Builtin => Physics::Builtin,
        PhysicsArg::Rapier => Physics::Rapier,
    };
    let result = simulate(prepared, model(controller), physics)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if let Some(dir) = out {
        write_outputs(dir, prepared, &result)?;
    }
    if json {
        print_json(&result.summary)?;
    } else {
        print_summary(&result.summary);
        if let Some(dir) = out {
            out!("  outputs in {}", dir.display());
        }
    }
    Ok(result.summary.all_passed())
}

fn parse_point(s: &str) -> Result<Vector2<f64>, String> {
    let parts: Vec<&str> = s.split(',').collect();
    match parts.as_slice() {
        [x, y] => match (x.trim().parse::<f64>(), y.trim().parse::<f64>()) {
            (Ok(x), Ok(y)) if x.is_finite() && y.is_finite() => Ok(Vector2::new(x, y)),
            _ => Err(format!("`--at {s}`: expected two finite numbers X,Y")),
        },
        _ => Err(format!("`--at {s}`: expected X,Y")),
    }
}

fn cmd_eval(prepared: &Prepared, at: &[String], json: bool) -> Result<bool, String> {
    let points = at
        .iter()
        .map(|s| parse_point(s))
        .collect::<Result<Vec<_>, _>>()?;
    let field = prepared.global_field().map_err(|e| e.to_string())?;
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
    if json {
        let rows: Vec<Value> = rows
            .iter()
            .map(|(x, r)| match r {
                Ok(e) => json!({ "x": x.x, "y": x.y, "h": [e.h.x, e.h.y], "phi": e.phi, "value": e.value, "grad": [e.gradient.x, e.gradient.y] }),
                Err(error) => json!({ "x": x.x, "y": x.y, "error": error }),
            })
            .collect();
        return print_json(&rows).map(|()| true);
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
    for (x, r) in &rows {
        match r {
            Err(error) => out!("{:>10.4} {:>10.4}  error: {error}", x.x, x.y),
            Ok(e) => out!(
                "{:>10.4} {:>10.4}  {:>12.6} {:>12.6}  {:>12.6}  {:>12.8}  ({:.3e}, {:.3e})",
                x.x,
                x.y,
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

fn cmd_census(prepared: &Prepared, json: bool) -> Result<bool, String> {
    let field = prepared.global_field().map_err(|e| e.to_string())?;
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

fn cmd_sweep(
    prepared: &Prepared,
    starts: usize,
    seed: u64,
    controller: Option<Controller>,
    json: bool,
) -> Result<bool, String> {
    if starts == 0 {
        return Err("`--starts` must be at least 1".into());
    }
    let points = random_starts(prepared, starts, seed).map_err(|e| e.to_string())?;
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let model = model(controller).unwrap_or(prepared.scenario.robot.model);
    let outcomes = sweep(prepared, &points, model, threads).map_err(|e| e.to_string())?;
    let report = Report::of(&points, &outcomes);
    if json {
        print_json(&report)?;
    } else {
        let counts = &report.counts;
        out!(
            "{} of {starts} starts reached the goal; {} collisions, {} left the workspace, {} \
             stalled, {} timed out, {} step collapses; median {:.2} s, max {:.2} s",
            counts.reached,
            counts.collisions,
            counts.left_workspace,
            counts.stalled,
            counts.timed_out,
            counts.step_collapsed,
            report.median_time_s.unwrap_or(f64::NAN),
            report.max_time_s.unwrap_or(f64::NAN)
        );
        for f in &report.failures {
            out!("  {:?} : {}", f.start, f.reason);
        }
    }
    Ok(report.all_reached())
}
