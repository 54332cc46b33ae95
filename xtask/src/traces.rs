//! `cargo xtask traces OUT [--periods N]`: the golden command traces of issue 51
//! (`harmonav_sim::golden`) for every scenario file under `scenarios/` but the adversarial
//! cases (star worlds and floor plans alike), every start, both laws, written to
//! `OUT/<path with / as __>.<start>.<law>.trace`. Run it before and after a change that must
//! not alter any command and `diff -r BEFORE AFTER`: bit for bit, or the change is real.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use harmonav_scenario::floorplan::{FileKind, FloorScenario};
use harmonav_scenario::{Model, Scenario};
use harmonav_sim::golden;

/// The periods of the traces.
const PERIODS: usize = 2000;

/// Every `.toml` under `dir` (sorted), but the adversarial cases.
fn files(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)?
        .map(|e| e.map(|e| e.path()))
        .collect::<Result<_, _>>()?;
    entries.sort();
    for p in entries {
        if p.is_dir() && p.file_name().is_some_and(|n| n != "adversarial") {
            files(&p, out)?;
        } else if p.extension().is_some_and(|e| e == "toml") && !p.ends_with("cases.toml") {
            out.push(p);
        }
    }
    Ok(())
}

/// Runs the command.
pub fn run(args: &[String]) -> ExitCode {
    let (out, periods) = match args {
        [out] => (PathBuf::from(out), PERIODS),
        [out, flag, n] if flag == "--periods" => match n.parse() {
            Ok(n) => (PathBuf::from(out), n),
            Err(_) => return crate::usage_error(&format!("--periods: `{n}` is not a count")),
        },
        _ => return crate::usage_error("traces takes OUT [--periods N]"),
    };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios");
    let mut list = Vec::new();
    if let Err(e) = files(&root, &mut list).and_then(|()| std::fs::create_dir_all(&out)) {
        eprintln!("xtask traces: {e}");
        return ExitCode::FAILURE;
    }
    let mut written = 0;
    for path in &list {
        let rel = path.strip_prefix(&root).unwrap_or(path);
        let name = rel
            .to_string_lossy()
            .replace('/', "__")
            .replace(".toml", "");
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("xtask traces: {}: {e}", path.display());
                return ExitCode::FAILURE;
            }
        };
        for model in [Model::Kinematic, Model::Dynamic] {
            let law = match model {
                Model::Kinematic => "kinematic",
                Model::Dynamic => "dynamic",
            };
            let traces: Vec<Result<String, String>> = match FileKind::of_text(&text) {
                FileKind::Star => match Scenario::load(path) {
                    Ok(p) => vec![golden::star(&p, model, periods)],
                    Err(e) => vec![Err(e.to_string())],
                },
                FileKind::FloorPlan => match FloorScenario::load(path) {
                    Ok(p) => p
                        .starts
                        .iter()
                        .map(|&s| golden::floor(&p, model, s, periods))
                        .collect(),
                    Err(e) => vec![Err(e.to_string())],
                },
            };
            for (i, trace) in traces.into_iter().enumerate() {
                let body = trace.unwrap_or_else(|e| format!("error {e}\n"));
                let file = out.join(format!("{name}.{i}.{law}.trace"));
                if let Err(e) = std::fs::write(&file, body) {
                    eprintln!("xtask traces: {}: {e}", file.display());
                    return ExitCode::FAILURE;
                }
                written += 1;
            }
        }
    }
    println!("{written} traces in {}", out.display());
    ExitCode::SUCCESS
}
