//! The motion-quality benchmark's targets (`docs/benchmarks.md`):
//!
//! - kinematic law, one check per `k` policy: every run arrives with every guarantee held;
//!   under the default policy the path is near-shortest (median ≤ 1.05, p90 ≤ 1.15 of the
//!   shortest path, per obstacle count and sensing) and the margin cells keep their clearance;
//! - dynamic law under the default policies: every run arrives with every guarantee held (no
//!   overshoot, `V` never rises, the speed bound, no collision), path median ≤ 1.15, time to
//!   goal over the kinematic law's (under the paper's speed `K√(2Θ)`, the reference of these
//!   targets: `harmonav_bench::table::REFERENCE_SPEED`) in the same world median ≤ 1.5 and p90 ≤ 2.5.

use harmonav_bench::quality::run_cells;
use harmonav_bench::table::{CellStats, REFERENCE_SPEED, kinematic_twin, time_ratio};
use harmonav_field::KPolicy;
use harmonav_scenario::Model;
use harmonav_sim::MARGIN_TOLERANCE;

use super::{Check, Outcome, outcome};
use crate::quality::{LawPolicies, WORLDS, plan};
use harmonav_control::DampingPolicy;

/// Path / shortest targets of the default policy: median and 90th percentile.
const MEDIAN: f64 = 1.05;
const P90: f64 = 1.15;

/// Dynamic law, path / shortest median target (issue 12).
const DYNAMIC_MEDIAN: f64 = 1.15;
/// Dynamic law, time over the kinematic law's in the same world: median target (issue 12).
const TIME_MEDIAN: f64 = 1.5;
/// The same ratio, 90th percentile (issue 12).
const TIME_P90: f64 = 2.5;

pub fn checks() -> Vec<Check> {
    let mut checks: Vec<Check> = KPolicy::ALL
        .into_iter()
        .map(|policy| {
            Check::new(format!("quality.kinematic.{policy}"), move || {
                quality(policy)
            })
            .early()
        })
        .collect();
    checks.push(
        Check::new(
            format!("quality.dynamic.{}", DampingPolicy::default()),
            dynamic,
        )
        .early(),
    );
    checks
}

/// The dynamic law under the default `k` and damping policies against the targets above.
fn dynamic() -> Outcome {
    let stats = run_cells(
        &plan(
            &[Model::Kinematic, Model::Dynamic],
            &[KPolicy::default()],
            LawPolicies {
                dampings: &[DampingPolicy::default()],
                speeds: &[REFERENCE_SPEED],
            },
            WORLDS,
        ),
        1,
    )?;
    let mut failures = Vec::new();
    let (mut worst_median, mut worst_p90, mut worst_path) = (0.0f64, 0.0f64, 0.0f64);
    for s in stats.iter().filter(|s| s.key.is_dynamic()) {
        let key = s.key.figure_key();
        if s.reached < s.runs || s.guarantees_held < s.runs || s.collisions > 0 {
            failures.push(format!(
                "{key}: {}/{} arrived, {}/{} held every guarantee, {} collisions",
                s.reached, s.runs, s.guarantees_held, s.runs, s.collisions
            ));
        }
        let twin =
            kinematic_twin(&stats, &s.key, REFERENCE_SPEED).ok_or("no kinematic twin cell")?;
        let ratio = time_ratio(s, twin);
        worst_median = worst_median.max(ratio[0]);
        worst_p90 = worst_p90.max(ratio[1]);
        worst_path = worst_path.max(s.ratio[0]);
        if s.ratio[0] > DYNAMIC_MEDIAN || ratio[0] > TIME_MEDIAN || ratio[1] > TIME_P90 {
            failures.push(format!(
                "{key}: path/shortest median {:.3} (target {DYNAMIC_MEDIAN}), time/kinematic \
                 median {:.2} (target {TIME_MEDIAN}), p90 {:.2} (target {TIME_P90})",
                s.ratio[0], ratio[0], ratio[1]
            ));
        }
        if s.min_clearance < s.key.margin.unwrap_or(0.0) - MARGIN_TOLERANCE {
            failures.push(format!(
                "{key}: clearance {:.4} m below the margin",
                s.min_clearance
            ));
        }
    }
    outcome(
        failures.is_empty(),
        format!(
            "{} dynamic cells × {WORLDS} worlds: path/shortest median ≤ {worst_path:.3}; \
             time/kinematic median ≤ {worst_median:.2}, p90 ≤ {worst_p90:.2}{}",
            stats.len() / 2,
            if failures.is_empty() {
                String::new()
            } else {
                format!("; FAILED {}", failures.join("; "))
            }
        ),
    )
}

fn quality(policy: KPolicy) -> Outcome {
    let stats = run_cells(
        &plan(&[Model::Kinematic], &[policy], LawPolicies::DEFAULT, WORLDS),
        1,
    )?;
    let mut failures = Vec::new();
    for s in &stats {
        let key = s.key.figure_key();
        if s.reached < s.runs || s.guarantees_held < s.runs || s.collisions > 0 {
            failures.push(format!(
                "{key}: {}/{} arrived, {}/{} held every guarantee, {} collisions",
                s.reached, s.runs, s.guarantees_held, s.runs, s.collisions
            ));
        }
        if s.min_clearance < s.key.margin.unwrap_or(0.0) - MARGIN_TOLERANCE {
            failures.push(format!(
                "{key}: clearance {:.4} m below the margin",
                s.min_clearance
            ));
        }
        let near_shortest = s.ratio[0] <= MEDIAN && s.ratio[1] <= P90;
        if policy == KPolicy::default() && !near_shortest {
            failures.push(format!(
                "{key}: path/shortest median {:.3}, p90 {:.3} (targets {MEDIAN}, {P90})",
                s.ratio[0], s.ratio[1]
            ));
        }
    }
    let worst = |f: fn(&CellStats) -> f64| stats.iter().map(f).fold(0.0, f64::max);
    outcome(
        failures.is_empty(),
        format!(
            "{} cells × {WORLDS} worlds: path/shortest median ≤ {:.3}, p90 ≤ {:.3}, max {:.3}; \
             min clearance {:.4} m{}",
            stats.len(),
            worst(|s| s.ratio[0]),
            worst(|s| s.ratio[1]),
            worst(|s| s.ratio[2]),
            stats
                .iter()
                .map(|s| s.min_clearance)
                .fold(f64::INFINITY, f64::min),
            if failures.is_empty() {
                String::new()
            } else {
                format!("; FAILED {}", failures.join("; "))
            }
        ),
    )
}
