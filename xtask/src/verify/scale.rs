//! The dynamic law across world sizes (issue 27, item 1): one world of six discs and a sector,
//! scaled by `α` (outer radius 5α m; the discs, the start, the goal, the sensor's range and
//! `rho_min`, the goal tolerance and the recording interval all scaled by `α`).
//!
//! Under the damping `"auto"` the potential is free of the world's scale
//! (`Dynamic::scale_shift`, docs/maths.md §9), so the run at `α` is the run at 1 with lengths
//! and times scaled by `α`: `T(α)/α` must equal `T(1)`, and every guarantee must hold. The
//! negative control is `"shaped"`, the default until 2026-12, whose `Θ` saturates in the larger
//! worlds: its `T(α)/α` must grow, or the check would not see the defect it guards against.
//! The default `"governed"` descends the same `Ψ` with a pull that grows with the world,
//! `4μ·max(1, ρ/5 m)`, under a governor at `0.9·√(2μ/m)`: its `T(α)/α` must not grow with `α`
//! (within 2 %), its time over the kinematic law's must meet issue 27's p90 target (≤ 2.0) at
//! every scale (one world per scale: its median and p90 are that ratio), and its top speed must
//! stay below `0.9·√(2μ/m)` (with the integrator's 1 %).
//!
//! `scale.dynamic-over-kinematic` flies every file of `scenarios/scale/` (20–100 m worlds, up to
//! 1 000 obstacles) under both laws (built-in integrator, default policies) and measures the
//! dynamic law's time over the kinematic law's, against issue 27's targets (median ≤ 1.5,
//! p90 ≤ 2.0). Every run must arrive with every guarantee, and the worst ratio must stay below
//! [`RATIO_GUARD`]; a target not met is reported as such ([`super::Verdict::Target`]).

use std::path::{Path, PathBuf};

use harmonav_bench::table::quantiles;
use harmonav_control::DampingPolicy;
use harmonav_scenario::{Model, Scenario};
use harmonav_sim::physics::{Physics, simulate};
use harmonav_sim::run::run;
use harmonav_sim::summary::Summary;

use super::{Check, Outcome, Verdict, outcome};

pub fn checks() -> Vec<Check> {
    vec![
        Check::new("dynamic.scale-free", scale_free).early(),
        Check::new("scale.dynamic-over-kinematic", dynamic_over_kinematic).early(),
    ]
}

/// Issue 27's targets for the dynamic law's time over the kinematic law's, in the same world and
/// sensing: the median and the 90th percentile over the scale suite.
const RATIO_TARGETS: (f64, f64) = (1.5, 2.0);

/// A regression guard: the worst ratio of the suite was 4.0 under `"auto"` when the check was
/// written (`many-1000-sector`, 2026-12-02), 2.34 under `"governed"` with the pull `4μ`, and is
/// 1.26 under the default `"governed"` with the pull grown with the world (2026-12-03); past
/// this bound the check fails (between the p90 target and it, it reports a target not met).
const RATIO_GUARD: f64 = 2.5;

/// One file of the scale suite flown under both laws: the kinematic time and, per damping
/// policy, the dynamic time (`None`: the file's own policy).
pub struct SuiteRow {
    /// The file's stem.
    pub name: String,
    /// The kinematic law's time to goal, s.
    pub kinematic: f64,
    /// The dynamic law's time to goal under each policy asked for, s, or why the run failed
    /// (not arrived, or a guarantee broken).
    pub dynamic: Vec<Result<f64, String>>,
}

/// Flies every file of `scenarios/scale/` under the kinematic law (the file's policies) and
/// under the dynamic law with each of `dampings` (`None`: the file's own). Every kinematic run
/// must arrive with every guarantee held; a dynamic run that does not is reported in its row.
pub fn suite(dampings: &[Option<DampingPolicy>]) -> Result<Vec<SuiteRow>, String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios/scale");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(format!("no scenario in {}", dir.display()));
    }
    let mut rows = Vec::new();
    for file in &files {
        let name = file
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let prepared = Scenario::load(file).map_err(|e| e.to_string())?;
        let fly = |prepared: &harmonav_scenario::Prepared, model| {
            let s = simulate(prepared, Some(model), Physics::Builtin)
                .map_err(|e| format!("{name}: {e}"))?
                .summary;
            if s.reached && s.all_passed() {
                Ok(s.time_s)
            } else {
                Err(format!("{name}, {model:?}: {}", s.outcome))
            }
        };
        let kinematic = fly(&prepared, Model::Kinematic)?;
        let mut dynamic = Vec::new();
        for &damping in dampings {
            let mut p = prepared.clone();
            if let Some(d) = damping {
                p.scenario.controller.damping = d;
            }
            dynamic.push(fly(&p, Model::Dynamic));
        }
        rows.push(SuiteRow {
            name,
            kinematic,
            dynamic,
        });
    }
    Ok(rows)
}

fn dynamic_over_kinematic() -> Outcome {
    let rows = suite(&[None])?;
    let mut ratios = Vec::new();
    for r in &rows {
        ratios.push(r.dynamic[0].clone()? / r.kinematic);
    }
    let report: Vec<String> = rows
        .iter()
        .zip(&ratios)
        .map(|(r, ratio)| format!("{} {ratio:.2}", r.name))
        .collect();
    let [median, p90, worst] = quantiles(&ratios);
    let detail = format!(
        "{} worlds, both laws arrive with every guarantee; dynamic/kinematic time: {}; median \
         {median:.2} (target ≤ {}), p90 {p90:.2} (target ≤ {}), worst {worst:.2} (guard < \
         {RATIO_GUARD})",
        ratios.len(),
        report.join(", "),
        RATIO_TARGETS.0,
        RATIO_TARGETS.1,
    );
    if worst >= RATIO_GUARD {
        return Err(format!("{detail}: past the regression guard"));
    }
    if median <= RATIO_TARGETS.0 && p90 <= RATIO_TARGETS.1 {
        Ok(Verdict::Held(detail))
    } else {
        Ok(Verdict::Target(format!(
            "{detail}; issue 27's targets not met"
        )))
    }
}

/// `cargo xtask scale [--damping NAME,NAME…]`: the scale suite under both laws, one column of
/// dynamic/kinematic time ratios per damping policy (default: every policy but `"paper"`),
/// with their median and p90 (an experiment runner; the check is
/// `scale.dynamic-over-kinematic`).
pub fn experiment(args: &[String]) -> std::process::ExitCode {
    let mut dampings = vec![
        DampingPolicy::Shaped,
        DampingPolicy::Auto,
        DampingPolicy::Fast,
    ];
    match args {
        [] => {}
        [flag, file, model, damping] if flag == "--trace" => {
            return trace(Path::new(file), model, damping);
        }
        [flag, names] if flag == "--damping" => {
            match names
                .split(',')
                .map(str::parse)
                .collect::<Result<Vec<_>, _>>()
            {
                Ok(d) => dampings = d,
                Err(e) => {
                    eprintln!("xtask scale: {e}");
                    return std::process::ExitCode::from(2);
                }
            }
        }
        _ => {
            eprintln!("xtask scale: usage: cargo xtask scale [--damping NAME,NAME…]");
            return std::process::ExitCode::from(2);
        }
    }
    let asked: Vec<Option<DampingPolicy>> = dampings.iter().copied().map(Some).collect();
    let rows = match suite(&asked) {
        Ok(rows) => rows,
        Err(e) => {
            eprintln!("xtask scale: {e}");
            return std::process::ExitCode::FAILURE;
        }
    };
    let mut head = String::from("| world | kinematic (s) |");
    for d in &dampings {
        head += &format!(" {} (s) | ratio |", d.as_str());
    }
    println!("{head}\n|---|---|{}", "---|---|".repeat(dampings.len()));
    for r in &rows {
        let mut line = format!("| {} | {:.1} |", r.name, r.kinematic);
        for t in &r.dynamic {
            match t {
                Ok(t) => line += &format!(" {t:.1} | {:.2} |", t / r.kinematic),
                Err(e) => line += &format!(" {e} | — |"),
            }
        }
        println!("{line}");
    }
    let mut median = String::from("| median | |");
    let mut p90 = String::from("| p90 | |");
    for i in 0..dampings.len() {
        // A run that failed counts as an infinite ratio.
        let ratios: Vec<f64> = rows
            .iter()
            .map(|r| {
                r.dynamic[i]
                    .as_ref()
                    .map_or(f64::INFINITY, |t| t / r.kinematic)
            })
            .collect();
        let [m, p, _] = quantiles(&ratios);
        median += &format!(" | {m:.2} |");
        p90 += &format!(" | {p:.2} |");
    }
    println!("{median}\n{p90}");
    std::process::ExitCode::SUCCESS
}

/// The six discs `(x, y, r)` of the world at `α = 1` (a seeded world of the benchmark's kind).
const DISCS: [(f64, f64, f64); 6] = [
    (-3.0259, -1.1930, 0.6167),
    (1.4381, 0.9658, 0.8551),
    (1.1085, -2.8181, 0.3635),
    (-0.9622, -0.8543, 0.7577),
    (-2.8842, 1.1308, 0.6248),
    (-0.6124, 1.4084, 0.7955),
];

/// The scales of the check: outer radii of 5, 20, 50 and 100 m (issue 27's world sizes).
const SCALES: [f64; 4] = [1.0, 4.0, 10.0, 20.0];

/// Runs the world at scale `alpha` with `model` and (dynamic law) `damping`.
fn fly(alpha: f64, model: &str, damping: &str) -> Result<Summary, String> {
    let mut text = format!(
        "name = \"scale-{alpha}\"\n[workspace]\ntype = \"circle\"\ncenter = [0.0, 0.0]\n\
         radius = {}\n",
        5.0 * alpha
    );
    for (x, y, r) in DISCS {
        text += &format!(
            "[[obstacles]]\ntype = \"circle\"\ncenter = [{}, {}]\nradius = {}\n",
            x * alpha,
            y * alpha,
            r * alpha
        );
    }
    text += &format!(
        "[robot]\nmodel = \"{model}\"\nstart = [{}, {}]\ngoal = [{}, 0.0]\n\
         [sensor]\nrange = {}\naperture_deg = 120.0\nrho_min = {}\n\
         [controller]\ndamping = \"{damping}\"\n\
         [sim]\ndt = {}\nmax_time = {}\ngoal_tolerance = {}\n",
        -4.0 * alpha,
        0.065 * alpha,
        4.0 * alpha,
        3.0 * alpha,
        0.05 * alpha,
        0.01 * alpha,
        400.0 * alpha,
        0.01 * alpha,
    );
    let path = Path::new("scale.toml");
    let prepared = Scenario::parse(path, &text)
        .and_then(|s| s.prepare(path))
        .map_err(|e| e.to_string())?;
    Ok(run(&prepared, None).map_err(|e| e.to_string())?.summary)
}

fn scale_free() -> Outcome {
    let mut report = Vec::new();
    let (mut worst, mut control) = (0.0f64, f64::INFINITY);
    let (mut governed_growth, mut governed_ratio, mut governed_speed) = (0.0f64, 0.0f64, 0.0f64);
    let (mut base, mut shaped_base) = (f64::NAN, f64::NAN);
    let mut governed_last = f64::INFINITY;
    for alpha in SCALES {
        let auto = fly(alpha, "dynamic", "auto")?;
        let shaped = fly(alpha, "dynamic", "shaped")?;
        let governed = fly(alpha, "dynamic", "governed")?;
        let kinematic = fly(alpha, "kinematic", "auto")?;
        for s in [&auto, &shaped, &governed, &kinematic] {
            if !(s.reached && s.all_passed()) {
                let failed: Vec<String> = s
                    .guarantees
                    .iter()
                    .filter(|g| !g.passed)
                    .map(|g| format!("{}: {}", g.name(), g.detail()))
                    .collect();
                return Err(format!(
                    "α = {alpha}, {:?} ({:?}): {}; {}",
                    s.model,
                    s.damping,
                    s.outcome,
                    failed.join("; ")
                ));
            }
        }
        let (t, ts, tg) = (
            auto.time_s / alpha,
            shaped.time_s / alpha,
            governed.time_s / alpha,
        );
        if alpha == 1.0 {
            (base, shaped_base) = (t, ts);
        }
        worst = worst.max((t / base - 1.0).abs());
        if alpha > 1.0 {
            control = control.min(ts / shaped_base - 1.0);
        }
        governed_growth = governed_growth.max(tg / governed_last - 1.0);
        governed_last = tg;
        governed_ratio = governed_ratio.max(governed.time_s / kinematic.time_s);
        governed_speed =
            governed_speed.max(governed.max_speed / governed.speed_bound.unwrap_or(f64::NAN));
        report.push(format!(
            "R = {:.0} m: T/α {t:.2} s (shaped {ts:.2} s, governed {tg:.2} s), dynamic/kinematic \
             {:.2} (governed {:.2}, top speed {:.2} of √(2μ/m))",
            5.0 * alpha,
            auto.time_s / kinematic.time_s,
            governed.time_s / kinematic.time_s,
            governed.max_speed / governed.speed_bound.unwrap_or(f64::NAN),
        ));
    }
    let governor = harmonav_control::GOVERNOR_BAND.1 * 1.01;
    outcome(
        worst < 0.02
            && control > 0.2
            && governed_growth < 0.02
            && governed_ratio <= RATIO_TARGETS.1
            && governed_speed < governor,
        format!(
            "{}; T/α of auto within {:.1} % of R = 5 m's (≤ 2 %), shaped slower by ≥ {:.0} % \
             (negative control, > 20 %); governed: T/α grows by at most {:.1} % from one scale \
             to the next (< 2 %), dynamic/kinematic ≤ {governed_ratio:.2} (≤ {}), top speed \
             ≤ {governed_speed:.3} of √(2μ/m) (< {governor:.3})",
            report.join("; "),
            100.0 * worst,
            100.0 * control,
            100.0 * governed_growth,
            RATIO_TARGETS.1,
        ),
    )
}

/// `cargo xtask scale --trace FILE MODEL DAMPING`: every recorded state about every 0.25 s of
/// one run (time, distance to the goal, speed, `Θ`, `V`, `λ`), to see where a law spends its
/// time.
fn trace(file: &Path, model: &str, damping: &str) -> std::process::ExitCode {
    let go = || -> Result<(), String> {
        let mut prepared = Scenario::load(file).map_err(|e| e.to_string())?;
        prepared.scenario.controller.damping = damping.parse().map_err(|e| format!("{e}"))?;
        let model = match model {
            "dynamic" => Model::Dynamic,
            "kinematic" => Model::Kinematic,
            other => {
                return Err(format!(
                    "MODEL: unknown model \"{other}\": expected \"kinematic\" or \"dynamic\""
                ));
            }
        };
        let run = simulate(&prepared, Some(model), Physics::Builtin).map_err(|e| e.to_string())?;
        let goal = prepared.scenario.robot.goal;
        let mut next = 0.0;
        println!("t dist speed theta V lambda");
        for s in &run.samples {
            if s.t >= next {
                next = s.t + 0.25;
                let d = ((s.x[0] - goal[0]).powi(2) + (s.x[1] - goal[1]).powi(2)).sqrt();
                println!(
                    "{:.2} {d:.3} {:.3} {:.4} {:.4} {:.3}",
                    s.t,
                    s.v[0].hypot(s.v[1]),
                    s.theta,
                    s.energy.unwrap_or(f64::NAN),
                    s.lambda.unwrap_or(f64::NAN)
                );
            }
        }
        println!(
            "{}: {:.2} s, {}",
            run.summary.outcome,
            run.summary.time_s,
            run.summary.all_passed()
        );
        Ok(())
    };
    match go() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask scale: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
