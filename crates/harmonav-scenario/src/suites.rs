//! The scenario suites under `scenarios/`: which files `cargo xtask verify` runs as suites
//! ([`scenario_files`]), and the folders that are not suites.

use std::path::{Path, PathBuf};

use crate::floorplan::FLOORPLANS;

/// The folder of the hostile-input regression cases (`scenarios/adversarial/`): malformed and
/// extreme files with the verdict or error each must end with, listed in its `cases.toml`.
/// They are not suites (many must fail to load), so [`scenario_files`] skips the folder.
pub const ADVERSARIAL: &str = "adversarial";

/// The folder of the long runs (`scenarios/long/`): worlds whose runs record 10⁵–10⁷ states
/// (a 10 km world at `sim.dt = 0.01`). `cargo xtask verify` runs each once, with its own
/// robot model and the recording streamed to disk (`harmonav_sim::physics::simulate_observed`);
/// [`scenario_files`] skips the folder, so that the suites do not also run them with the
/// other model and rapier (hours at this size).
pub const LONG: &str = "long";

/// The folder of the mover scenarios (`scenarios/movers/`, issue 54): files with
/// `[[movers]]`, which run in the held-command loop at the control period
/// (`docs/movers.md` §8). `cargo xtask verify` flies each under both laws (`movers.*`);
/// [`scenario_files`] skips the folder.
pub const MOVERS: &str = "movers";

/// The folder of the differential-drive scenarios (`scenarios/diff/`, issue 53): star worlds
/// with `[robot] base = "diff"`, which run the kinematic law only, in the held-command loop
/// (docs/unicycle.md, "Simulator"). `cargo xtask verify` flies each built-in and in rapier
/// (`diff.*`); [`scenario_files`] skips the folder (the suites also run the other model).
pub const DIFF: &str = "diff";

/// Every scenario file (`*.toml`) below `dir`, recursively, sorted by path, except under
/// [`ADVERSARIAL`], [`LONG`], [`MOVERS`] and [`DIFF`] folders: the suites that `cargo xtask verify` runs and must
/// pass.
pub fn scenario_files(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
        for entry in std::fs::read_dir(dir)? {
            let p = entry?.path();
            // Floor plans have their own format and loop (`crate::floorplan`).
            if p.is_dir()
                && p.file_name().is_some_and(|n| {
                    n == ADVERSARIAL || n == LONG || n == MOVERS || n == DIFF || n == FLOORPLANS
                })
            {
                continue;
            } else if p.is_dir() {
                walk(&p, out)?;
            } else if p.extension().is_some_and(|e| e == "toml") {
                out.push(p);
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, &mut out)?;
    out.sort();
    Ok(out)
}
