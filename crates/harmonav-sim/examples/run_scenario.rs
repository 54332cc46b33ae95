//! Runs a scenario file and prints its summary as JSON: `cargo run -p harmonav-sim --example
//! run_scenario -- FILE [kinematic|dynamic|file] [OUT_DIR]` (the `harmonav` CLI will supersede
//! it).

use std::path::Path;
use std::process::ExitCode;

use harmonav_sim::scenario::{Model, Scenario};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(file) = args.first() else {
        eprintln!("usage: run_scenario FILE [kinematic|dynamic|file] [OUT_DIR]");
        return ExitCode::from(2);
    };
    let model = match args.get(1).map(String::as_str) {
        Some("kinematic") => Some(Model::Kinematic),
        Some("dynamic") => Some(Model::Dynamic),
        _ => None,
    };
    let prepared = match Scenario::load(Path::new(file)) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    match harmonav_sim::run::run(&prepared, model) {
        Ok(run) => {
            let written = args
                .get(2)
                .map(|dir| harmonav_sim::record::write_outputs(Path::new(dir), &prepared, &run));
            if let Some(Err(e)) = written {
                eprintln!("{e}");
                return ExitCode::from(2);
            }
            println!(
                "{}",
                serde_json::to_string_pretty(&run.summary).expect("serialisable summary")
            );
            if run.summary.all_passed() {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(1)
            }
        }
        Err(e) => {
            eprintln!("{file}: {e}");
            ExitCode::from(2)
        }
    }
}
