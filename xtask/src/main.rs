//! `cargo xtask`: project automation for harmonav.
//!
//! - `cargo xtask verify` runs every named guarantee check (the paper's properties, measured)
//!   and ends with `verify: N passed, M failed` (exit code 1 if M > 0).
//! - `cargo xtask bench [--json] [--numpy] [--portable] [--only PREFIX]` re-runs itself in release mode and prints the
//!   benchmark figures (one JSON object with `--json`).
//! - `cargo xtask figures` regenerates the documentation figures in `docs/figures/`.
//! - `cargo xtask traces OUT` writes the golden command traces (a refactor's bit-for-bit check).
//! - `cargo xtask quality` and `cargo xtask scale` print experiment tables (the motion-quality
//!   benchmark; the scale suite under several damping policies).

mod bench;
mod figures;
mod quality;
mod rng;
mod traces;
mod verify;

use std::process::ExitCode;

const USAGE: &str =
    "usage: cargo xtask <verify [--only PREFIX] | bench [--json] [--numpy] [--portable] [--only PREFIX] | figures>

  verify   run the named guarantee checks; ends with `verify: N passed, M failed`
             --only P  only the checks whose names start with P (e.g. floorplan.)
  bench    measure the benchmark figures in release mode
             --json    print one JSON object instead of a table
             --numpy   also time a NumPy implementation of eq. (gradient) (needs python3 + numpy)
             --portable  compile for the baseline target instead of this machine's CPU
             --only P  only the figures whose names start with P (e.g. field_eval, quality)
  figures  regenerate the documentation figures in docs/figures/
  quality  [--worlds N] [--kinematic-only | --dynamic-only | --compare D1,D2] the motion-quality table
  scale    [--damping D1,D2 | --trace FILE MODEL DAMPING] the scale suite, dynamic/kinematic time
  traces   OUT [--periods N]  golden command traces of every scenario, start and law (raw bits)";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("verify") if args.len() == 1 => verify::run(None),
        Some("verify") if args.len() == 3 && args[1] == "--only" => verify::run(Some(&args[2])),
        Some("figures") if args.len() == 1 => figures::run(),
        Some("quality") => quality::run(&args[1..]),
        Some("traces") => traces::run(&args[1..]),
        Some("scale") => verify::scale::experiment(&args[1..]),
        Some("bench") => match bench::Options::parse(&args[1..]) {
            Ok(options) => bench::run(&options),
            Err(message) => usage_error(&message),
        },
        Some("-h" | "--help" | "help") => {
            println!("{USAGE}");
            ExitCode::SUCCESS
        }
        Some(other) => usage_error(&format!("unknown command or argument `{other}`")),
        None => usage_error("no command given"),
    }
}

pub(crate) fn usage_error(message: &str) -> ExitCode {
    eprintln!("xtask: {message}\n\n{USAGE}");
    ExitCode::from(2)
}
