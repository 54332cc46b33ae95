//! `cargo xtask bench`: the benchmark figures, measured in release mode.
//!
//! By default the kernels are compiled for this machine's CPU (`--portable`: the baseline
//! x86-64 target of ordinary builds); the JSON says which (`avx2`).
//!
//! Timing is the median of repeated batches (`std::time::Instant`); the criterion benches
//! (`cargo bench -p harmonav-potential`) give the full distributions. Speed goals live here,
//! never in timed unit tests.

use std::hint::black_box;
use std::process::{Command, ExitCode};
use std::time::Instant;

use harmonav_control::DampingPolicy;
use harmonav_field::KPolicy;
use harmonav_potential::{BatchGradient, PointWorld, Vector2, arrangements};
use harmonav_scenario::Model;
// The control-step figures' world (8 seeded mixed obstacles, 1024 states), shared with the
// criterion benches.
use harmonav_bench::diff::control_workspace as control_world;

use crate::quality;

#[path = "bench_harmonic.rs"]
mod harmonic;
#[path = "bench_many.rs"]
mod many;
#[path = "bench_maps.rs"]
mod maps;

pub struct Options {
    json: bool,
    numpy: bool,
    portable: bool,
    /// Only the figures whose names start with this (`--only PREFIX`).
    only: Option<String>,
}

impl Options {
    pub fn parse(args: &[String]) -> Result<Self, String> {
        let mut options = Self {
            json: false,
            numpy: false,
            portable: false,
            only: None,
        };
        let mut args = args.iter();
        while let Some(a) = args.next() {
            match a.as_str() {
                "--json" => options.json = true,
                "--numpy" => options.numpy = true,
                "--portable" => options.portable = true,
                "--only" => match args.next() {
                    Some(prefix) => options.only = Some(prefix.clone()),
                    None => return Err("`--only` needs a figure-name prefix".into()),
                },
                other => return Err(format!("unknown bench option `{other}`")),
            }
        }
        Ok(options)
    }

    /// Whether the figure (or group of figures) `name` is to be measured.
    fn wants(&self, name: &str) -> bool {
        self.only
            .as_deref()
            .is_none_or(|p| name.starts_with(p) || p.starts_with(name))
    }
}

pub fn run(options: &Options) -> ExitCode {
    if cfg!(debug_assertions) {
        return rerun_in_release(options.portable);
    }
    let mut figures = serde_json::Map::new();
    let mut put = |key: &str, value: f64| {
        figures.insert(
            key.to_string(),
            serde_json::json!((value * 1000.0).round() / 1000.0),
        );
    };
    let wants = |name: &str| options.wants(name);
    if wants("grad_single_ns") {
        put("grad_single_ns", grad_single_ns(6));
    }
    let mut ours = f64::NAN;
    if wants("grad_batch") || options.numpy {
        for m in [6, 20, 100, 1000] {
            let ns = grad_batch_ns_per_pair(m, 4096);
            if m == 100 {
                put("grad_batch_ns_per_pair", ns);
                ours = ns;
            }
            put(&format!("grad_batch_ns_per_pair_m{m}"), ns);
        }
    }
    if wants("field_grad_ns_m20") {
        put("field_grad_ns_m20", field_grad_ns(20));
    }
    if wants("field_eval_ns_discs20") || wants("field_eval_many_ns_discs20") {
        match field_eval_ns_discs20() {
            Ok((one, many)) => {
                put("field_eval_ns_discs20", one);
                put("field_eval_many_ns_discs20", many);
            }
            Err(e) => {
                eprintln!("xtask bench: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    if wants("control_step_ns_m6") {
        put(
            "control_step_ns_m6",
            control_step_ns(DampingPolicy::default()),
        );
        put(
            "control_step_ns_m6_damping_paper",
            control_step_ns(DampingPolicy::Paper),
        );
    }
    if wants("navigator_command_ns_m6") {
        use harmonav::{HoldPolicy, Law};
        // The hold (docs/maths.md §10) against the continuous law sampled as is, side by side.
        let dynamic = Law::dynamic(1.0, 10.0);
        let kinematic = Law::kinematic(1.0);
        put(
            "navigator_command_ns_m6",
            navigator_command_ns(dynamic, HoldPolicy::Auto, None),
        );
        put(
            "navigator_command_ns_m6_hold_paper",
            navigator_command_ns(dynamic, HoldPolicy::Paper, None),
        );
        // The braking certificate of a force bound (docs/movers.md §2), side by side: 1 N binds
        // at most of the states (each then traces up to 42 segments).
        put(
            "navigator_command_ns_m6_force_bound",
            navigator_command_ns(dynamic, HoldPolicy::Auto, Some(1.0)),
        );
        put(
            "navigator_command_ns_m6_kinematic",
            navigator_command_ns(kinematic, HoldPolicy::Auto, None),
        );
        put(
            "navigator_command_ns_m6_kinematic_hold_paper",
            navigator_command_ns(kinematic, HoldPolicy::Paper, None),
        );
        // The mover filter (docs/movers.md), side by side with the lines above: 20 movers out
        // of reach (the filter only checks its rows; target: within 1 µs of no movers) and 20
        // movers within reach of every state (the filter projects; target ≤ 20 µs).
        for (name, near) in [("far", false), ("near", true)] {
            put(
                &format!("navigator_command_ns_m6_kinematic_movers_20_{name}"),
                navigator_command_movers_ns(near),
            );
        }
    }
    // A differential-drive base's command (issue 53: target ≤ 30 µs per command; docs/unicycle.md,
    // docs/benchmarks.md): the poses of a closed-loop flight replayed, without and with
    // acceleration limits, in a disc world and on a floor plan, and with 20 movers.
    if wants("diff_command")
        && let Err(e) = diff_command_figures(&mut put)
    {
        eprintln!("xtask bench: the differential-drive benchmark failed: {e}");
        return ExitCode::FAILURE;
    }
    // Memory of a long run, side by side with a short one (docs/benchmarks.md): the peak
    // resident memory the run adds, sampled every 5 ms.
    if wants("long_run") {
        for (name, states) in [("1e5", 1e5), ("1e7", 1e7)] {
            match long_run_rss(states) {
                Ok((mb, steps)) => {
                    put(&format!("long_run_peak_rss_mb_{name}"), mb);
                    put(&format!("long_run_steps_{name}"), steps as f64);
                }
                Err(e) => {
                    eprintln!("xtask bench: the long run failed: {e}");
                    return ExitCode::FAILURE;
                }
            }
        }
    }
    if wants("observe_scan") {
        match observe_scan_hostile_us(360) {
            Ok(us) => put("observe_scan_hostile_us_360", us),
            Err(e) => {
                eprintln!("xtask bench: the hostile scan benchmark failed: {e}");
                return ExitCode::FAILURE;
            }
        }
        for beams in [360, 1080] {
            let (steady, event) = observe_scan_us(beams);
            put(&format!("observe_scan_us_{beams}"), steady);
            put(&format!("observe_scan_event_us_{beams}"), event);
            if beams == 1080 {
                for dense in [10_000, 100_000] {
                    put(
                        &format!("observe_scan_dense_event_us_{dense}"),
                        dense_scan_event_us(dense),
                    );
                }
            }
            match floor_observe_scan_us(beams) {
                Ok((steady, event)) => {
                    put(&format!("floor_observe_scan_us_{beams}"), steady);
                    put(&format!("floor_observe_scan_event_us_{beams}"), event);
                }
                Err(e) => {
                    eprintln!("xtask bench: the floor-plan scan benchmark failed: {e}");
                    return ExitCode::FAILURE;
                }
            }
        }
    }
    if wants("many") {
        many::figures(&mut put);
    }
    if wants("map_")
        && let Err(e) = maps::figures(&mut put)
    {
        eprintln!("xtask bench: the map benchmark failed: {e}");
        return ExitCode::FAILURE;
    }
    if wants("harmonic")
        && let Err(e) = harmonic::figures(&mut put)
    {
        eprintln!("xtask bench: the harmonic-map benchmark failed: {e}");
        return ExitCode::FAILURE;
    }
    if wants("montecarlo_runs_per_s") {
        put("montecarlo_runs_per_s", montecarlo_runs_per_s());
    }
    // The motion-quality benchmark (docs/benchmarks.md): both laws, every policy.
    if wants("quality") {
        let models = [Model::Kinematic, Model::Dynamic];
        let plan = quality::plan(
            &models,
            &KPolicy::ALL,
            quality::LawPolicies::ALL,
            quality::WORLDS,
        );
        let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
        match harmonav_bench::quality::run_cells(&plan, threads) {
            Ok(stats) => {
                quality::figures(&stats, &mut put);
                if !options.json {
                    print!("{}", harmonav_bench::table::table(&stats));
                }
            }
            Err(e) => {
                eprintln!("xtask bench: the motion-quality benchmark failed: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    if options.numpy {
        match numpy_ns_per_pair(100, 4096) {
            Ok((broadcast, per_point)) => {
                put("numpy_broadcast_ns_per_pair", broadcast);
                put("numpy_per_point_ns_per_pair", per_point);
                put("numpy_broadcast_ratio", broadcast / ours);
                put("numpy_per_point_ratio", per_point / ours);
            }
            Err(e) => {
                eprintln!("xtask bench: --numpy: {e}");
                return ExitCode::from(2);
            }
        }
    }
    // Which instruction set the kernels were compiled for (see `rerun_in_release`).
    figures.insert("avx2".to_string(), cfg!(target_feature = "avx2").into());
    if options.json {
        println!("{}", serde_json::Value::Object(figures));
    } else {
        for (key, value) in &figures {
            println!("{key:32} {value}");
        }
    }
    ExitCode::SUCCESS
}

/// Re-executes `cargo xtask bench` with the release profile (timings of a debug build mean
/// nothing), compiled for this machine's CPU (`-C target-cpu=native`, in its own target
/// directory so that the ordinary builds stay portable) unless `--portable` is given.
fn rerun_in_release(portable: bool) -> ExitCode {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut command = Command::new(cargo);
    command
        .args(["run", "--quiet", "--release", "--package", "xtask", "--"])
        .args(&args);
    if !portable {
        let flags = std::env::var("RUSTFLAGS").unwrap_or_default();
        command
            .env("RUSTFLAGS", format!("{flags} -C target-cpu=native"))
            .env("CARGO_TARGET_DIR", "target/bench-native");
    }
    match command.status() {
        Ok(s) if s.success() => ExitCode::SUCCESS,
        Ok(s) => ExitCode::from(s.code().unwrap_or(1).clamp(1, 255) as u8),
        Err(e) => {
            eprintln!("xtask bench: could not run cargo: {e}");
            ExitCode::from(2)
        }
    }
}

/// The golden-spiral benchmark world of `m` points (the same as the criterion benches) and
/// `n` query points between them.
fn setup(m: usize, n: usize) -> (PointWorld, Vec<f64>, Vec<f64>) {
    let world = arrangements::golden_spiral(m);
    let hx = (0..n)
        .map(|i| -3.0 + 6.0 * ((i * 7919) % n) as f64 / n as f64 + 1e-3)
        .collect();
    let hy = (0..n)
        .map(|i| -3.0 + 6.0 * i as f64 / n as f64 + 2e-3)
        .collect();
    (world, hx, hy)
}

/// Median over `samples` runs of `f`, each run timed as a whole, divided by `per_run`.
pub(crate) fn median_ns(samples: usize, per_run: f64, mut f: impl FnMut()) -> f64 {
    f(); // warm up
    let mut times: Vec<f64> = (0..samples)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_nanos() as f64 / per_run
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[samples / 2]
}

/// `PointWorld::grad_phi_k` for one point (M obstacles), ns per call.
fn grad_single_ns(m: usize) -> f64 {
    let (world, hx, hy) = setup(m, 1024);
    let pts: Vec<_> = hx
        .iter()
        .zip(&hy)
        .map(|(&x, &y)| Vector2::new(x, y))
        .collect();
    let reps = 200;
    median_ns(21, (reps * pts.len()) as f64, || {
        for _ in 0..reps {
            for &h in &pts {
                let _ = black_box(world.grad_phi_k(black_box(h)));
            }
        }
    })
}

/// `Field::eval` (Θ, ∇Θ and the direction through `Phi` and `J_Phi`) with `m` known
/// mixed-shape obstacles, ns per query point (1024 random free points, 10 % of them in bands).
fn field_grad_ns(m: usize) -> f64 {
    use harmonav_field::Field;
    use harmonav_transform::random::{self, Kind, Rng};
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let mut rng = Rng::new(20);
    let ws = std::sync::Arc::new(random::workspace(&mut rng, m, &kinds, Kind::Star, 0.1));
    let field = Field::all_known(ws.clone()).expect("valid benchmark world");
    let pts: Vec<_> = (0..1024)
        .map(|_| random::free_point(&mut rng, &ws, 1e-3))
        .collect();
    let reps = 100;
    median_ns(21, (reps * pts.len()) as f64, || {
        for _ in 0..reps {
            for &x in &pts {
                let _ = black_box(field.eval(black_box(x)));
            }
        }
    })
}

/// `Θ` and `∇Θ` per point, one thread, in `scenarios/scale/discs-20-global.toml` (20 discs,
/// all known) at 4096 seeded free points, point by point (`Field::eval`) and batched
/// (`Field::eval_many`): the Rust side of the Python package's benchmark
/// (`python/bench/bench_eval.py`, which times `Field.eval` and NumPy in the same world).
fn field_eval_ns_discs20() -> Result<(f64, f64), String> {
    use harmonav_scenario::Scenario;
    use harmonav_transform::random::{self, Rng};
    let path = std::path::Path::new("scenarios/scale/discs-20-global.toml");
    let prepared = Scenario::load(path).map_err(|e| e.to_string())?;
    let field = prepared.global_field().map_err(|e| e.to_string())?;
    let mut rng = Rng::new(0);
    let pts: Vec<_> = (0..4096)
        .map(|_| random::free_point(&mut rng, &prepared.truth.workspace, 1e-3))
        .collect();
    let reps = 25;
    let one = median_ns(21, (reps * pts.len()) as f64, || {
        for _ in 0..reps {
            for &x in &pts {
                let _ = black_box(field.eval(black_box(x)));
            }
        }
    });
    let mut out = vec![Err(harmonav_field::FieldError::Outside); pts.len()];
    let many = median_ns(21, (reps * pts.len()) as f64, || {
        for _ in 0..reps {
            let _ = black_box(field.eval_many(black_box(&pts), &mut out));
        }
    });
    Ok((one, many))
}

/// One `Navigator::command` of `law` (default policies but the hold `hold`, and the force
/// bound `force_bound` if given) with 6 known obstacles, at the states of
/// [`control_step_ns`]'s world; ns per call.
fn navigator_command_ns(
    law: harmonav::Law,
    hold: harmonav::HoldPolicy,
    force_bound: Option<f64>,
) -> f64 {
    use harmonav::{Navigator, Options};
    let (ws, states) = control_world();
    let mut options = Options::default().with_hold(hold);
    if let Some(f) = force_bound {
        options = options.with_force_bound(f);
    }
    let mut nav = Navigator::new(ws.boundary().clone(), ws.destination(), law, options)
        .expect("valid benchmark world");
    for o in &ws.obstacles()[..6] {
        nav.add_obstacle(o.clone())
            .expect("valid benchmark obstacle");
    }
    let reps = 20;
    median_ns(15, (reps * states.len()) as f64, || {
        for _ in 0..reps {
            for &(x, v) in &states {
                let _ = black_box(nav.command(black_box(x), black_box(v)));
            }
        }
    })
}

/// [`navigator_command_ns`] under the kinematic law with 20 movers (radius 0.3 m, 1 m/s) set
/// before each command: `near`, all within reach of the period (0.5 to 3 cm clear of their
/// rows' discs, round the state); else 20 m away. ns per call, `set_movers` included. The world
/// and the movers are `harmonav_bench::diff`'s (`control_world`, `ring`), shared with the
/// criterion bench `diff_command`.
fn navigator_command_movers_ns(near: bool) -> f64 {
    use harmonav_bench::diff;
    let (mut nav, states) = diff::control_world();
    let inflation = nav.options().inflation();
    let movers: Vec<_> = states
        .iter()
        .map(|&(x, _)| diff::ring(x, inflation, near))
        .collect();
    let reps = 5;
    median_ns(15, (reps * states.len()) as f64, || {
        for _ in 0..reps {
            for (&(x, v), m) in states.iter().zip(&movers) {
                let _ = nav.set_movers(m);
                let _ = black_box(nav.command(black_box(x), black_box(v)));
            }
        }
    })
}

/// One `Navigator::command_pose` of a differential-drive base (issue 53, target ≤ 30 µs;
/// `harmonav_bench::diff`): the poses of a closed-loop flight replayed in order on a fresh
/// copy of the navigator, with `movers` set before each command when given. µs per command:
/// `(median, worst)`, the median of 15 replays (each timed whole, the copy included), and the
/// slowest single command (each command's least time over 5 replays, so that a preemption of
/// this shared machine is not read as a slow command).
fn command_pose_us<W: harmonav::World + Clone>(
    flight: &harmonav_bench::diff::Flight<W>,
    movers: Option<&[Vec<harmonav::Mover>]>,
) -> (f64, f64) {
    use harmonav_bench::diff;
    let n = flight.poses.len();
    let median = median_ns(15, 1e3 * n as f64, || {
        let mut nav = flight.nav.clone();
        black_box(diff::replay(&mut nav, &flight.poses, movers));
    });
    let mut least = vec![f64::INFINITY; n];
    for _ in 0..5 {
        let mut nav = flight.nav.clone();
        for (i, &(x, yaw)) in flight.poses.iter().enumerate() {
            if let Some(m) = movers {
                nav.set_movers(&m[i]).expect("valid movers");
            }
            let t = Instant::now();
            let _ = black_box(nav.command_pose(black_box(x), black_box(yaw)));
            least[i] = least[i].min(t.elapsed().as_nanos() as f64 / 1e3);
        }
    }
    (median, least.iter().copied().fold(0.0, f64::max))
}

/// The `diff_command_pose_us_*` figures (issue 53: each ≤ 30 µs per command, release build;
/// with 20 movers issue 54's ≤ 20 µs within reach, ≤ 1 µs more than none out of reach), put
/// by `put`: in the seeded disc world of `harmonav_bench::diff` and on the L room floor plan,
/// without and with acceleration limits, and in the disc world with 20 movers; with each
/// flight's commands and whether it arrived (1) within its 120 s.
fn diff_command_figures(put: &mut impl FnMut(&str, f64)) -> Result<(), String> {
    use harmonav_bench::diff;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for accel in [false, true] {
        let suffix = if accel { "_accel" } else { "" };
        let discs = diff::disc_world(accel)?;
        let floor = diff::floor_plan(&root, accel)?;
        let flights = [
            (
                "discs10",
                command_pose_us(&discs, None),
                discs.poses.len(),
                discs.arrived,
            ),
            (
                "floor_l_room",
                command_pose_us(&floor, None),
                floor.poses.len(),
                floor.arrived,
            ),
        ];
        for (world, (median, worst), commands, arrived) in flights {
            put(&format!("diff_command_pose_us_{world}{suffix}"), median);
            put(&format!("diff_command_pose_us_{world}{suffix}_max"), worst);
            put(
                &format!("diff_command_pose_commands_{world}{suffix}"),
                commands as f64,
            );
            put(
                &format!("diff_command_pose_arrived_{world}{suffix}"),
                f64::from(u8::from(arrived)),
            );
        }
    }
    let discs = diff::disc_world(false)?;
    let inflation = discs.nav.options().inflation();
    for (name, near) in [("far", false), ("near", true)] {
        let rings: Vec<_> = discs
            .poses
            .iter()
            .map(|&(x, _)| diff::ring(x, inflation, near))
            .collect();
        let (median, worst) = command_pose_us(&discs, Some(&rings));
        put(
            &format!("diff_command_pose_us_discs10_movers_20_{name}"),
            median,
        );
        put(
            &format!("diff_command_pose_us_discs10_movers_20_{name}_max"),
            worst,
        );
    }
    Ok(())
}

/// `Navigator::observe_scan` on a scan of `beams` beams (360°, 3 m, 2 cm noise, 1 % dropouts)
/// in lidar world 0 (`harmonav::checks::lidar`), µs: `(steady, event)`. Steady: the obstacles
/// in view are perceived already, every hit is explained (the common case); event: the first
/// scan of a fresh navigator, which fits, certifies and rebuilds `Θ`. The suite's options
/// (radial hulls, the free fan, the memory) with every segment fitted (`fit_range = ∞`).
fn observe_scan_us(beams: usize) -> (f64, f64) {
    use harmonav::checks::lidar::{LIDAR_WORLD_DEPTH, lidar_options, lidar_world, suite_lidar};
    use harmonav::{Law, Navigator, Pose};
    let world = lidar_world(0, false);
    let lidar = harmonav::perception::sim::Lidar {
        beams,
        ..suite_lidar()
    };
    let mut options = lidar_options(&world, &lidar, lidar.noise, LIDAR_WORLD_DEPTH);
    // Every segment fitted at once, so that the first scan is an event (the suite's fit range
    // would leave the start's far obstacles for later scans).
    options.scan.fit_range = f64::INFINITY;
    let fresh = Navigator::new(
        world.boundary.clone(),
        world.goal,
        Law::kinematic(1.0),
        options,
    )
    .expect("valid benchmark world");
    let pose = Pose::new(world.start.x, world.start.y, 0.0);
    let mut rng = harmonav::transform::random::Rng::new(7);
    let scans: Vec<_> = (0..8)
        .map(|_| lidar.scan(&pose, &world.obstacles, Some(&world.boundary), &mut rng))
        .collect();
    let event = median_ns(5, 1e3, || {
        let mut nav = fresh.clone();
        let _ = black_box(nav.observe_scan(pose, black_box(&scans[0])));
    });
    let mut nav = fresh.clone();
    nav.observe_scan(pose, &scans[0])
        .expect("the benchmark scan is accepted");
    let steady = median_ns(15, 1e3 * scans.len() as f64, || {
        for s in &scans {
            let _ = black_box(nav.observe_scan(pose, black_box(s)));
        }
    });
    (steady, event)
}

/// One `Navigator::observe_scan` of the hostile round's worst-case scan (2026-12-06, D2;
/// `harmonav_bench::hostile`): a full turn of `beams` ranges uniform in [0.05, 3] m on a fresh
/// navigator (a robot of radius 0.1 m at (−3, 0) in a disc of radius 10 m), refused as
/// `ContainsRobot`, µs. Target: ≤ 10 000 µs at 360 beams (`hostile::TARGET_US`); before the fix
/// about 40 s.
fn observe_scan_hostile_us(beams: usize) -> Result<f64, String> {
    use harmonav_bench::hostile;
    let fresh = hostile::navigator();
    let (pose, scan) = (hostile::pose(), hostile::scan(beams, 0.05, 3.0));
    match fresh.clone().observe_scan(pose, &scan) {
        Err(harmonav::NavError::ContainsRobot) => {}
        other => return Err(format!("expected ContainsRobot, got {other:?}")),
    }
    Ok(median_ns(15, 1e3, || {
        let mut nav = fresh.clone();
        let _ = black_box(nav.observe_scan(pose, black_box(&scan)));
    }))
}

/// The first `Navigator::observe_scan` of a fresh navigator on one dense segment, µs: a full
/// turn of `beams` noise-free beams from the origin at a disc of radius 0.5 m about (2, 0)
/// (805 hits at 10 000 beams, 8 043 at 100 000), depth prior 1.5 m. The fit of a segment was
/// quadratic in its hits (3.7 s at 8 043) before the cut polygons' index (docs/maths.md §12.19).
fn dense_scan_event_us(beams: usize) -> f64 {
    use harmonav::perception::sim::Lidar;
    use harmonav::{Law, Navigator, Options, Pose, ScanOptions, StarShape, Vector2};
    let disc = StarShape::circle(Vector2::new(2.0, 0.0), 0.5).expect("a valid circle");
    let pose = Pose::new(0.0, 0.0, 0.0);
    // Noise-free, no dropouts: the seed does not matter.
    let mut rng = harmonav::transform::random::Rng::new(1);
    let scan = Lidar::full_turn(beams, 5.0).scan(&pose, &[disc], None, &mut rng);
    let options = Options::default().with_scan(ScanOptions {
        max_obstacle_depth: 1.5,
        ..ScanOptions::default()
    });
    let boundary = StarShape::circle(Vector2::zeros(), 10.0).expect("a valid circle");
    let fresh = Navigator::new(
        boundary,
        Vector2::new(8.0, 0.0),
        Law::kinematic(1.0),
        options,
    )
    .expect("valid benchmark world");
    median_ns(3, 1e3, || {
        let mut nav = fresh.clone();
        black_box(nav.observe_scan(pose, black_box(&scan))).expect("the dense scan is accepted");
    })
}

/// `FloorNavigator::observe_scan` on a scan of `beams` beams (360°, 4 m, 1 cm noise, 1 %
/// dropouts) in the ROS-map office of `scenarios/floorplans/map-office-lidar.toml` (1 431
/// boundary elements), 0.6 m from its corridor chair, µs: `(steady, event)` as
/// [`observe_scan_us`]. Every hit on the walls is explained by parry's distance to the wall
/// segments (docs/maths.md §12.17).
fn floor_observe_scan_us(beams: usize) -> Result<(f64, f64), String> {
    use harmonav::perception::sim::{Enclosure, Lidar};
    use harmonav::{FloorNavigator, Law, Options, Pose, ScanOptions, Vector2};
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenarios/floorplans/map-office-lidar.toml");
    let p = harmonav_scenario::floorplan::FloorScenario::load(&file).map_err(|e| e.to_string())?;
    let lidar = Lidar {
        noise: 0.01,
        dropout: 0.01,
        ..Lidar::full_turn(beams, 4.0)
    };
    let options = Options::default()
        .with_robot(0.1, 0.1)
        .with_scan(ScanOptions {
            range_noise: 0.01,
            max_obstacle_depth: 0.5,
            ..ScanOptions::default()
        });
    let goal = Vector2::from(p.scenario.robot.goal);
    let fresh = FloorNavigator::new(p.floor.clone(), goal, Law::kinematic(1.0), options)
        .map_err(|e| e.to_string())?;
    let walls = fresh.walls().clone();
    let pose = Pose::new(3.0, 3.4, 0.0);
    let mut rng = harmonav::transform::random::Rng::new(7);
    let scans: Vec<_> = (0..8)
        .map(|_| lidar.scan_in(&pose, &p.obstacles, Enclosure::Walls(&walls), &mut rng))
        .collect();
    let event = median_ns(5, 1e3, || {
        let mut nav = fresh.clone();
        let _ = black_box(nav.observe_scan(pose, black_box(&scans[0])));
    });
    let mut nav = fresh.clone();
    let first = nav
        .observe_scan(pose, &scans[0])
        .map_err(|e| e.to_string())?;
    if !first.changed() {
        return Err("the first scan perceived nothing".into());
    }
    let steady = median_ns(15, 1e3 * scans.len() as f64, || {
        for s in &scans {
            let _ = black_box(nav.observe_scan(pose, black_box(s)));
        }
    });
    Ok((steady, event))
}

/// One full control step with 6 known obstacles (and 2 not yet known): the sector check of
/// the unknown obstacles, `Θ` and `∇Θ`, and the dynamic law under the damping `policy`; ns per
/// step.
fn control_step_ns(policy: DampingPolicy) -> f64 {
    use harmonav_control::Dynamic;
    use harmonav_field::Field;
    use harmonav_sensing::{Sector, axis};
    let (ws, states) = control_world();
    let ws = std::sync::Arc::new(ws);
    let field = Field::new(ws.clone(), 0..6).expect("valid benchmark world");
    let sector = Sector::new(1.0, 60f64.to_radians()).expect("valid sector");
    let law = Dynamic::new(1.0, 10.0, sector.d_min(0.05))
        .expect("valid law")
        .with_damping(policy);
    let reps = 20;
    median_ns(15, (reps * states.len()) as f64, || {
        for _ in 0..reps {
            for &(x, v) in &states {
                let (x, v) = (black_box(x), black_box(v));
                let Ok(e) = field.eval(x) else { continue };
                let seen = axis(v, e.direction)
                    .is_some_and(|a| (6..8).any(|i| sector.detects(x, a, &ws.obstacles()[i])));
                let d = law.damping(&field, &e, v, v.norm());
                black_box((seen, law.force(&field, &e, v, &d)));
            }
        }
    })
}

/// The resident memory of this process, bytes (`VmRSS` of /proc/self/status).
fn rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// A kinematic run across an empty 10 km world (8 km from start to goal, about 5 660 s) with
/// `sim.dt` chosen for about `states` recorded states (and as many integration steps), every state handed to an observer as a streamed recording would be: the peak
/// resident memory it adds over the process's before it (MB, sampled every 5 ms), and its
/// accepted steps. The run keeps a bounded trajectory and judges online, so the peak must
/// not grow with `states` (target: ≤ 100 MB at 10⁷).
fn long_run_rss(states: f64) -> Result<(f64, usize), String> {
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
    let dt = 5660.0 / states;
    let text = format!(
        "name = \"long-run\"\n[workspace]\ntype = \"circle\"\ncenter = [0.0, 0.0]\nradius = 5000.0\n\
         [robot]\nmodel = \"kinematic\"\nstart = [-4000.0, 0.0]\ngoal = [4000.0, 0.0]\n\
         [sim]\ndt = {dt:e}\nmax_time = 1e5\ngoal_tolerance = 0.05\n"
    );
    let path = std::path::Path::new("long-run.toml");
    let prepared = harmonav_scenario::Scenario::parse(path, &text)
        .and_then(|s| s.prepare(path))
        .map_err(|e| e.to_string())?;
    let base = rss_bytes().ok_or("no /proc/self/status")?;
    let (done, peak) = (AtomicBool::new(false), AtomicU64::new(base));
    let run = std::thread::scope(|scope| {
        scope.spawn(|| {
            while !done.load(Ordering::Relaxed) {
                peak.fetch_max(rss_bytes().unwrap_or(0), Ordering::Relaxed);
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
        });
        let mut streamed = 0usize;
        let run = harmonav_sim::run::run_observed(&prepared, None, &mut |e| {
            if let harmonav_sim::trace::Event::State(s) = e {
                streamed += black_box(s).x.len() / 2;
            }
        });
        done.store(true, Ordering::Relaxed);
        run.map(|r| (r, streamed))
    });
    let (run, streamed) = run.map_err(|e| e.to_string())?;
    if !run.summary.reached || streamed != run.summary.recorded_states {
        return Err(format!(
            "the long run did not arrive or lost states: reached {}, {streamed} streamed of {}",
            run.summary.reached, run.summary.recorded_states
        ));
    }
    let added = peak.load(Ordering::Relaxed).saturating_sub(base);
    Ok((added as f64 / 1e6, run.summary.steps))
}

/// The Monte-Carlo study of `cargo xtask verify` (descents from random starts in the
/// 20-obstacle mixed-shape world, global sensing), on both cores: descents per second.
fn montecarlo_runs_per_s() -> f64 {
    use harmonav_field::Field;
    use harmonav_field::descent::{FollowOptions, follow};
    use harmonav_transform::random::{self, Kind, Rng};
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let mut rng = Rng::new(20);
    let ws = std::sync::Arc::new(random::workspace(&mut rng, 20, &kinds, Kind::Star, 0.1));
    let field = Field::all_known(ws.clone()).expect("valid benchmark world");
    let starts: Vec<_> = (0..400)
        .map(|_| random::free_point(&mut rng, &ws, 1e-3))
        .collect();
    let t = Instant::now();
    black_box(harmonav_sim::pool::parallel_map(&starts, 2, |&x| {
        follow(&field, x, &FollowOptions::default()).time
    }));
    starts.len() as f64 / t.elapsed().as_secs_f64()
}

/// `BatchGradient::eval`, ns per obstacle–point pair.
fn grad_batch_ns_per_pair(m: usize, n: usize) -> f64 {
    let (world, hx, hy) = setup(m, n);
    let kernel = BatchGradient::new(&world);
    let (mut gx, mut gy) = (vec![0.0; n], vec![0.0; n]);
    let reps = (20_000 / m).max(1);
    median_ns(21, (reps * m * n) as f64, || {
        for _ in 0..reps {
            kernel
                .eval(black_box(&hx), black_box(&hy), &mut gx, &mut gy)
                .expect("regular query points");
        }
        black_box((&gx, &gy));
    })
}

/// The same eq. (gradient) in NumPy, two straightforward ways: broadcasting an (N, M) array,
/// and a Python loop over points vectorised over the obstacles. ns per pair, median of runs.
fn numpy_ns_per_pair(m: usize, n: usize) -> Result<(f64, f64), String> {
    const SCRIPT: &str = r#"
import sys, time, numpy as np
m, n = int(sys.argv[1]), int(sys.argv[2])
i = np.arange(m); r = 1.0 + 0.05 * i; a = 2.399963 * i
px, py = r * np.cos(a), r * np.sin(a)
dx, dy, k = 0.123, -0.077, m + 1.0
j = np.arange(n)
hx = -3.0 + 6.0 * ((j * 7919) % n) / n + 1e-3
hy = -3.0 + 6.0 * j / n + 2e-3
def broadcast(hx, hy):
    ex = hx[:, None] - px[None, :]; ey = hy[:, None] - py[None, :]
    r2 = ex * ex + ey * ey
    sx = (ex / r2).sum(axis=1); sy = (ey / r2).sum(axis=1)
    qx, qy = hx - dx, hy - dy; q2 = qx * qx + qy * qy
    return 2 * qx / q2 - 2 / k * sx, 2 * qy / q2 - 2 / k * sy
def per_point(hx, hy):
    gx = np.empty(n); gy = np.empty(n)
    for t in range(n):
        ex = hx[t] - px; ey = hy[t] - py; r2 = ex * ex + ey * ey
        qx, qy = hx[t] - dx, hy[t] - dy; q2 = qx * qx + qy * qy
        gx[t] = 2 * qx / q2 - 2 / k * (ex / r2).sum(); gy[t] = 2 * qy / q2 - 2 / k * (ey / r2).sum()
    return gx, gy
def median(f, runs):
    ts = []
    for _ in range(runs):
        t = time.perf_counter(); f(hx, hy); ts.append(time.perf_counter() - t)
    return sorted(ts)[runs // 2] * 1e9 / (m * n)
a, b = broadcast(hx, hy), per_point(hx, hy)
assert np.allclose(a[0], b[0]) and np.allclose(a[1], b[1])
print(median(broadcast, 21), median(per_point, 5))
"#;
    let out = Command::new("python3")
        .args(["-c", SCRIPT, &m.to_string(), &n.to_string()])
        .output()
        .map_err(|e| format!("could not run python3: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "the NumPy script failed (is numpy installed?): {}",
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let v: Vec<f64> = text
        .split_whitespace()
        .filter_map(|s| s.parse().ok())
        .collect();
    match v.as_slice() {
        [a, b] => Ok((*a, *b)),
        _ => Err(format!("unexpected NumPy output `{}`", text.trim())),
    }
}
