//! The motion-quality benchmark (`harmonav_sim::quality`): the plan that `cargo xtask bench`
//! and `cargo xtask verify` run, its Markdown table and its JSON figures.

use harmonav_bench::quality::{Cell, Plan, SensingKind};
use harmonav_bench::table::{CellStats, REFERENCE_SPEED, kinematic_twin, time_ratio};
use harmonav_control::{DampingPolicy, SpeedPolicy};
use harmonav_field::KPolicy;
use harmonav_scenario::Model;

/// Worlds per obstacle count in the benchmark.
pub const WORLDS: usize = 24;

/// The margin of the margin cells, m.
pub const MARGIN: f64 = 0.1;

/// The policies of the laws a plan runs: the damping policies of the dynamic law and the speed
/// policies of the kinematic law.
#[derive(Clone, Copy, Debug)]
pub struct LawPolicies<'a> {
    /// Dynamic law.
    pub dampings: &'a [DampingPolicy],
    /// Kinematic law.
    pub speeds: &'a [SpeedPolicy],
}

impl LawPolicies<'static> {
    /// The policies of the table in docs/benchmarks.md (and of
    /// `examples/experiments/quality.toml`): every speed policy, and the damping policies
    /// `"paper"`, `"shaped"`, `"auto"` and the default `"governed"`. `"fast"` (docs/maths.md §9
    /// part 4) is compared on its own with `--compare auto,fast`.
    pub const ALL: Self = Self {
        dampings: &[
            DampingPolicy::Paper,
            DampingPolicy::Shaped,
            DampingPolicy::Auto,
            DampingPolicy::Governed,
        ],
        speeds: &SpeedPolicy::ALL,
    };

    /// The default policies only.
    pub const DEFAULT: Self = Self {
        dampings: &[DampingPolicy::Governed],
        speeds: &[SpeedPolicy::Auto],
    };
}

/// The cells of the table for the laws `models`, the `k` policies `policies` and the law
/// policies `laws` (damping: dynamic law; speed: kinematic law): both sensings, and the
/// default `k` policy also with the clearance margin.
pub fn cells(models: &[Model], policies: &[KPolicy], laws: LawPolicies<'_>) -> Vec<Cell> {
    let mut cells = Vec::new();
    for &model in models {
        for sensing in SensingKind::ALL {
            for &k in policies {
                let margins: &[f64] = if k == KPolicy::default() {
                    &[0.0, MARGIN]
                } else {
                    &[0.0]
                };
                // (damping, speed) pairs: each law varies its own policy.
                let variants: Vec<(DampingPolicy, SpeedPolicy)> = match model {
                    Model::Kinematic => laws
                        .speeds
                        .iter()
                        .map(|&s| (DampingPolicy::default(), s))
                        .collect(),
                    Model::Dynamic => laws
                        .dampings
                        .iter()
                        .map(|&d| (d, SpeedPolicy::default()))
                        .collect(),
                };
                for &margin in margins {
                    for &(damping, speed) in &variants {
                        cells.push(Cell {
                            obstacles: 0,
                            sensing,
                            k,
                            model,
                            damping,
                            speed,
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
/// `models`, `policies` and `laws`, 120 s per run.
pub fn plan(models: &[Model], policies: &[KPolicy], laws: LawPolicies<'_>, worlds: usize) -> Plan {
    Plan {
        obstacle_counts: vec![6, 12, 20],
        worlds,
        cells: cells(models, policies, laws),
        max_time: 120.0,
    }
}

/// The JSON figures of `stats`: `quality.<cell key>.<figure>`.
pub fn figures(stats: &[CellStats], mut put: impl FnMut(&str, f64)) {
    for s in stats {
        let key = format!("quality.{}", s.key.figure_key());
        put(
            &format!("{key}.arrival_rate"),
            s.reached as f64 / s.runs as f64,
        );
        put(&format!("{key}.collisions"), s.collisions as f64);
        put(&format!("{key}.path_ratio_median"), s.ratio[0]);
        put(&format!("{key}.path_ratio_p90"), s.ratio[1]);
        put(&format!("{key}.path_ratio_max"), s.ratio[2]);
        put(&format!("{key}.time_median_s"), s.time[0]);
        if let (true, Some(k)) = (
            s.key.is_dynamic(),
            kinematic_twin(stats, &s.key, REFERENCE_SPEED),
        ) {
            let r = time_ratio(s, k);
            put(&format!("{key}.time_over_kinematic_median"), r[0]);
            put(&format!("{key}.time_over_kinematic_p90"), r[1]);
            put(&format!("{key}.overshoot_m"), s.overshoot);
        }
        if let (true, Some(k)) = (
            s.key.is_dynamic(),
            kinematic_twin(stats, &s.key, SpeedPolicy::Auto),
        ) {
            let r = time_ratio(s, k);
            put(
                &format!("{key}.time_over_kinematic_auto_speed_median"),
                r[0],
            );
            put(&format!("{key}.time_over_kinematic_auto_speed_p90"), r[1]);
        }
        put(&format!("{key}.min_clearance_m"), s.min_clearance);
        put(&format!("{key}.steps_median"), s.steps[0]);
    }
}

/// `cargo xtask quality [--worlds N] [--kinematic-only | --dynamic-only | --compare D1,D2…]`:
/// prints the table (an experiment runner; the figures themselves are in
/// `cargo xtask bench --json`). `--compare` runs the default `k` only: the dynamic law under
/// the damping policies `D1, D2, …` and the kinematic law at [`REFERENCE_SPEED`].
pub fn run(args: &[String]) -> std::process::ExitCode {
    let mut worlds = WORLDS;
    let mut models = vec![Model::Kinematic, Model::Dynamic];
    let mut compare: Option<Vec<DampingPolicy>> = None;
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
            "--compare" => match it
                .next()
                .map(|v| v.split(',').map(str::parse).collect::<Result<Vec<_>, _>>())
            {
                Some(Ok(d)) if !d.is_empty() => compare = Some(d),
                _ => {
                    eprintln!("xtask quality: --compare takes damping policies, e.g. auto,fast");
                    return std::process::ExitCode::from(2);
                }
            },
            other => {
                eprintln!("xtask quality: unknown option `{other}`");
                return std::process::ExitCode::from(2);
            }
        }
    }
    if compare.is_some() && models.len() == 1 {
        eprintln!(
            "xtask quality: --compare runs both laws (the kinematic one is the time ratios' \
             reference); leave out --kinematic-only / --dynamic-only"
        );
        return std::process::ExitCode::from(2);
    }
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    // `--compare`: the default `k` only, the dynamic law under the policies asked for and the
    // kinematic law at the reference speed (the twin of the time ratios and of verify's targets).
    let plan = match &compare {
        Some(dampings) => plan(
            &[Model::Kinematic, Model::Dynamic],
            &[KPolicy::default()],
            LawPolicies {
                dampings,
                speeds: &[REFERENCE_SPEED],
            },
            worlds,
        ),
        None => plan(&models, &KPolicy::ALL, LawPolicies::ALL, worlds),
    };
    match harmonav_bench::quality::run_cells(&plan, threads) {
        Ok(stats) => {
            print!("{}", harmonav_bench::table::table(&stats));
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("xtask quality: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
