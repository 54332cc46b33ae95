//! The motion-quality benchmark (`harmonav_sim::quality`): the plan that `cargo xtask bench`
//! and `cargo xtask verify` run, its Markdown table and its JSON figures.

use harmonav_control::DampingPolicy;
use harmonav_field::KPolicy;
use harmonav_sim::quality::{Cell, CellStats, Plan, SensingKind, time_ratio};
use harmonav_sim::scenario::Model;

/// Worlds per obstacle count in the benchmark.
pub const WORLDS: usize = 24;

/// The margin of the margin cells, m.
pub const MARGIN: f64 = 0.1;

/// The cells of the table for the laws `models`, the `k` policies `policies` and (dynamic law)
/// the damping policies `dampings`: both sensings, and the default `k` policy also with the
/// clearance margin.
pub fn cells(models: &[Model], policies: &[KPolicy], dampings: &[DampingPolicy]) -> Vec<Cell> {
    let mut cells = Vec::new();
    for &model in models {
        for sensing in SensingKind::ALL {
            for &k in policies {
                let margins: &[f64] = if k == KPolicy::default() {
                    &[0.0, MARGIN]
                } else {
                    &[0.0]
                };
                let dampings: &[DampingPolicy] = match model {
                    Model::Kinematic => &[DampingPolicy::Auto],
                    Model::Dynamic => dampings,
                };
                for &margin in margins {
                    for &damping in dampings {
                        cells.push(Cell {
                            obstacles: 0,
                            sensing,
                            k,
                            model,
                            damping,
                            margin,
                        });
                    }
                }
            }
        }
    }
    cells
}

/// The benchmark plan: 6, 12 and 20 obstacles, `worlds` worlds each, the [`cells`] of
/// `models`, `policies` and `dampings`, 120 s per run.
pub fn plan(
    models: &[Model],
    policies: &[KPolicy],
    dampings: &[DampingPolicy],
    worlds: usize,
) -> Plan {
    Plan {
        obstacle_counts: vec![6, 12, 20],
        worlds,
        cells: cells(models, policies, dampings),
        max_time: 120.0,
    }
}

fn fmt3(v: [f64; 3], digits: usize) -> String {
    format!("{:.digits$} / {:.digits$} / {:.digits$}", v[0], v[1], v[2])
}

/// The kinematic cell of the same worlds, sensing, `k` and margin as `cell`, if `stats` has it.
pub fn kinematic_twin<'a>(stats: &'a [CellStats], cell: &Cell) -> Option<&'a CellStats> {
    stats.iter().find(|s| {
        s.cell.model == Model::Kinematic
            && (s.cell.obstacles, s.cell.sensing, s.cell.k, s.cell.margin)
                == (cell.obstacles, cell.sensing, cell.k, cell.margin)
    })
}

/// Per-world time over the kinematic law's in the same world (median / p90 / max), or `—`.
fn time_ratio_text(stats: &[CellStats], s: &CellStats) -> String {
    match (s.cell.model, kinematic_twin(stats, &s.cell)) {
        (Model::Dynamic, Some(k)) => fmt3(time_ratio(s, k), 2),
        _ => "—".to_string(),
    }
}

/// The Markdown table of `stats`.
pub fn table(stats: &[CellStats]) -> String {
    let mut out = String::from(
        "| law | damping | k | sensing | margin | M | arrived | guarantees held | collisions | path/shortest median / p90 / max | time to goal median / p90 / max (s) | time / kinematic median / p90 / max | min clearance (m) | overshoot (m) | steps median / p90 / max |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for s in stats {
        let c = &s.cell;
        out.push_str(&format!(
            "| {:?} | {} | {} | {} | {} | {} | {}/{} | {}/{} | {} | {} | {} | {} | {:.4} | {:.1e} | {} |\n",
            c.model,
            if c.model == Model::Dynamic { c.damping.as_str() } else { "—" },
            c.k,
            c.sensing.as_str(),
            c.margin,
            c.obstacles,
            s.reached,
            s.runs,
            s.guarantees_held,
            s.runs,
            s.collisions,
            fmt3(s.ratio, 3),
            fmt3(s.time, 1),
            time_ratio_text(stats, s),
            s.min_clearance,
            s.overshoot,
            fmt3(s.steps, 0),
        ));
    }
    out
}

/// The JSON figures of `stats`: `quality.<cell key>.<figure>`.
pub fn figures(stats: &[CellStats], mut put: impl FnMut(&str, f64)) {
    for s in stats {
        let key = format!("quality.{}", s.cell.key());
        put(
            &format!("{key}.arrival_rate"),
            s.reached as f64 / s.runs as f64,
        );
        put(&format!("{key}.collisions"), s.collisions as f64);
        put(&format!("{key}.path_ratio_median"), s.ratio[0]);
        put(&format!("{key}.path_ratio_p90"), s.ratio[1]);
        put(&format!("{key}.path_ratio_max"), s.ratio[2]);
        put(&format!("{key}.time_median_s"), s.time[0]);
        if let (Model::Dynamic, Some(k)) = (s.cell.model, kinematic_twin(stats, &s.cell)) {
            let r = time_ratio(s, k);
            put(&format!("{key}.time_over_kinematic_median"), r[0]);
            put(&format!("{key}.time_over_kinematic_p90"), r[1]);
            put(&format!("{key}.overshoot_m"), s.overshoot);
        }
        put(&format!("{key}.min_clearance_m"), s.min_clearance);
        put(&format!("{key}.steps_median"), s.steps[0]);
    }
}

/// `cargo xtask quality [--worlds N] [--kinematic-only | --dynamic-only]`: prints the table (an experiment
/// runner; the figures themselves are in `cargo xtask bench --json`).
pub fn run(args: &[String]) -> std::process::ExitCode {
    let mut worlds = WORLDS;
    let mut models = vec![Model::Kinematic, Model::Dynamic];
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--worlds" => match it.next().and_then(|v| v.parse().ok()) {
                Some(n) if n > 0 => worlds = n,
                _ => {
                    eprintln!("xtask quality: --worlds takes a positive number");
                    return std::process::ExitCode::from(2);
                }
            },
            "--kinematic-only" => models = vec![Model::Kinematic],
            "--dynamic-only" => models = vec![Model::Dynamic],
            other => {
                eprintln!("xtask quality: unknown option `{other}`");
                return std::process::ExitCode::from(2);
            }
        }
    }
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let plan = plan(&models, &KPolicy::ALL, &DampingPolicy::ALL, worlds);
    match harmonav_sim::quality::run_plan(&plan, threads) {
        Ok(stats) => {
            print!("{}", table(&stats));
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("xtask quality: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
