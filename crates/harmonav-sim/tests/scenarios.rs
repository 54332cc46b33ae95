//! Scenario files: every file in scenarios/ round-trips; each validation error is reported
//! with the file, the field and the problem; runs are deterministic.

use std::path::{Path, PathBuf};

use harmonav_control::SpeedPolicy;
use harmonav_scenario::{Model, Scenario};
use harmonav_sim::guarantee::{Check, Kind};
use harmonav_sim::run::run;
use nalgebra::Vector2;

fn scenario_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    harmonav_scenario::scenario_files(&dir).unwrap()
}

#[test]
fn every_scenario_round_trips_and_validates() {
    let files = scenario_files();
    assert!(files.len() >= 2);
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let parsed = Scenario::parse(&file, &text).unwrap_or_else(|e| panic!("{e}"));
        let again = Scenario::parse(&file, &toml::to_string(&parsed).unwrap()).unwrap();
        assert_eq!(parsed, again, "{}", file.display());
        Scenario::load(&file).unwrap_or_else(|e| panic!("{e}"));
    }
}

const BASE: &str = r#"
name = "t"
[workspace]
type = "circle"
center = [0.0, 0.0]
radius = 5.0
[[obstacles]]
name = "A"
type = "circle"
center = [0.0, 0.0]
radius = 1.0
[[obstacles]]
name = "B"
type = "ellipse"
center = [0.0, 2.5]
semi_axes = [0.8, 0.3]
[robot]
model = "kinematic"
start = [-3.0, 0.0]
goal = [3.0, 0.0]
[sensor]
range = 1.0
aperture_deg = 60.0
"#;

/// One validation case: replace `from` by `to` in BASE and expect an error naming `field`
/// whose text contains `problem` (and, if given, the line).
fn check(from: &str, to: &str, field: &str, problem: &str, line: Option<usize>) {
    assert!(BASE.contains(from), "bad test case {from}");
    let text = BASE.replacen(from, to, 1);
    let path = Path::new("case.toml");
    let Err(err) = Scenario::parse(path, &text).and_then(|s| s.prepare(path)) else {
        panic!("{from} → {to} was accepted");
    };
    assert_eq!(err.file, path);
    assert_eq!(err.field, field, "{err}");
    assert!(err.problem.contains(problem), "{err}");
    if line.is_some() {
        assert_eq!(err.line, line, "{err}");
    }
    let shown = err.to_string();
    assert!(
        shown.starts_with("case.toml") && shown.contains(problem),
        "{shown}"
    );
}

#[test]
fn validation_errors_name_the_file_the_field_and_the_problem() {
    check(
        "radius = 1.0",
        "radius = nan",
        "obstacles[0].radius",
        "NaN or infinite",
        None,
    );
    check(
        "radius = 1.0",
        "radius = -1.0",
        "obstacles[0].radius",
        "must be positive",
        None,
    );
    check(
        "semi_axes = [0.8, 0.3]",
        "semi_axes = [0.8, 0.0]",
        "obstacles[1].semi_axes",
        "must be positive",
        None,
    );
    check(
        "center = [0.0, 2.5]",
        "center = [0.0, 1.1]",
        "obstacles",
        "overlap",
        None,
    );
    check(
        "center = [0.0, 2.5]",
        "center = [0.0, 4.9]",
        "obstacles",
        "crosses or lies outside",
        None,
    );
    check(
        "start = [-3.0, 0.0]",
        "start = [-0.5, 0.0]",
        "robot.start",
        "inside obstacle A",
        None,
    );
    check(
        "goal = [3.0, 0.0]",
        "goal = [6.0, 0.0]",
        "robot.goal",
        "outside the workspace",
        None,
    );
    check(
        "aperture_deg = 60.0",
        "aperture_deg = 400.0",
        "sensor.aperture_deg",
        "(0, 360]",
        None,
    );
    check(
        "aperture_deg = 60.0",
        "aperture_deg = 0.0",
        "sensor.aperture_deg",
        "(0, 360]",
        None,
    );
    check(
        "range = 1.0",
        "range = inf",
        "sensor.range",
        "finite and in [1e-9, 1e9]",
        None,
    );
    // A subnormal curvature bound made d_min underflow and the run end "step size collapsed".
    check(
        "aperture_deg = 60.0",
        "aperture_deg = 60.0\nrho_min = 5e-324",
        "sensor.rho_min",
        "in [1e-9, 1e9] m, got 5e-324",
        None,
    );
    check(
        "model = \"kinematic\"",
        "model = \"kinematic\"\nwheels = 4",
        "robot",
        "unknown field `wheels`",
        Some(19),
    );
    check(
        "name = \"B\"",
        "name = \"A\"",
        "obstacles[1].name",
        "used twice",
        None,
    );
    check(
        "type = \"ellipse\"",
        "type = \"hexagon\"",
        "obstacles[1]",
        "unknown variant `hexagon`",
        None,
    );
    check(
        "[[obstacles]]\nname = \"B\"\ntype = \"ellipse\"\ncenter = [0.0, 2.5]\nsemi_axes = [0.8, 0.3]",
        "[[obstacles]]\nname = \"B\"\ntype = \"polygon\"\nvertices = [[0.0, 2.0], [3.0, 2.0], [3.0, 2.3], [0.5, 2.3], [0.5, 3.7], [3.0, 3.7], [3.0, 4.0], [0.0, 4.0]]\ncorner_radius = 0.05",
        "obstacles[1].vertices",
        "not strictly star-shaped",
        None,
    );
    check(
        "[sensor]",
        "[sensor]\nrho_min = -1.0",
        "sensor.rho_min",
        "finite and in [1e-9, 1e9] m",
        None,
    );
    check(
        "start = [-3.0, 0.0]",
        "start = [-3.0]",
        "robot.start",
        "invalid length 1",
        None,
    );
}

#[test]
fn margin_policy_and_limit_errors_name_the_field_and_the_reason() {
    let goal = "goal = [3.0, 0.0]";
    for bad in ["-0.1", "nan", "inf"] {
        let to = format!("{goal}\nmargin = {bad}");
        check(goal, &to, "robot.margin", "finite and in [0, 1e9] m", None);
    }
    // A (r = 1 at the origin) and B (0.3 below y = 2.5) are 1.2 m apart.
    check(
        goal,
        "goal = [3.0, 0.0]\nmargin = 0.7",
        "robot.margin",
        "the grown obstacles A and B overlap: the passage between them is narrower than 2 × 0.7 m",
        None,
    );
    check(
        goal,
        "goal = [3.0, 0.0]\nradius = 0.7",
        "robot.radius",
        "the grown obstacles A and B overlap",
        None,
    );
    check(
        "start = [-3.0, 0.0]",
        "start = [-1.05, 0.0]\nmargin = 0.1",
        "robot.start",
        "lies 0.0500 m from obstacle A, closer than robot.radius + robot.margin = 0.1 m",
        None,
    );
    check(
        goal,
        "goal = [4.95, 0.0]\nmargin = 0.1",
        "robot.goal",
        "lies 0.0500 m from the workspace boundary, closer than robot.radius + robot.margin",
        None,
    );
    check(
        "[sensor]",
        "[field]\nk = \"n+1\"\n[sensor]",
        "field.k",
        "unknown k policy \"n+1\": expected \"paper\" or \"auto\"",
        None,
    );
    check(
        "[sensor]",
        "[controller]\ndamping = \"critical\"\n[sensor]",
        "controller.damping",
        "unknown damping policy \"critical\": expected \"paper\", \"shaped\", \"auto\", \"fast\" \
         or \"governed\"",
        None,
    );
    check(
        "[sensor]",
        "[controller]\nspeed = \"fast\"\n[sensor]",
        "controller.speed",
        "unknown speed policy \"fast\": expected \"paper\" or \"auto\"",
        None,
    );
    for bad in ["0.0", "-1.0", "nan", "inf", "2e9"] {
        check(
            "[sensor]",
            &format!("[controller]\nv_max = {bad}\n[sensor]"),
            "controller.v_max",
            "must be finite and in [1e-9, 1e9]",
            None,
        );
    }
    // A stated limit needs a "paper" policy for the other model (here the dynamic law).
    let limit = "[expect]\nother_model_reached = false\n[sensor]";
    check(
        "[sensor]",
        limit,
        "expect.other_model_reached",
        "under the default policies every scenario must arrive",
        None,
    );
    let path = Path::new("case.toml");
    for policy in [
        "[field]\nk = \"paper\"",
        "[controller]\ndamping = \"paper\"",
    ] {
        let text = BASE.replacen("[sensor]", &format!("{policy}\n{limit}"), 1);
        let parsed = Scenario::parse(path, &text).and_then(|s| s.prepare(path));
        assert!(parsed.is_ok(), "{policy}: {:?}", parsed.err());
    }
}

/// `[controller] speed` and `v_max`: parsed, written back, and in force in a run. Both speeds
/// follow the same path (the same flow lines); `"auto"` (the default) arrives sooner, at most
/// `v_max`.
#[test]
fn the_speed_policy_and_v_max_are_read_and_change_only_the_timing() {
    let path = Path::new("speed.toml");
    let run_with = |controller: &str| {
        // Off the axis through A (on it the descent ends at A's saddle).
        let text = BASE
            .replacen("start = [-3.0, 0.0]", "start = [-3.0, 0.4]", 1)
            .replacen(
                "[sensor]",
                &format!("[controller]\n{controller}\n[sensor]"),
                1,
            );
        let p = Scenario::parse(path, &text).unwrap().prepare(path).unwrap();
        let r = run(&p, Some(Model::Kinematic)).unwrap();
        assert!(r.summary.reached && r.summary.all_passed(), "{controller}");
        (p, r)
    };
    let (p, auto) = run_with("");
    assert_eq!(p.speed_policy(), SpeedPolicy::Auto);
    assert_eq!(p.scenario.controller.v_max, None);
    let (p, paper) = run_with("speed = \"paper\"");
    assert_eq!(p.speed_policy(), SpeedPolicy::Paper);
    let text = toml::to_string(&p.scenario).unwrap();
    assert!(text.contains("speed = \"paper\""), "{text}");
    let (p, slow) = run_with("v_max = 0.5");
    assert_eq!(p.scenario.controller.v_max, Some(0.5));
    let top = |r: &harmonav_sim::summary::Run| {
        r.samples
            .iter()
            .map(|x| Vector2::from(x.v).norm())
            .fold(0.0, f64::max)
    };
    assert!(top(&slow) <= 0.5 * (1.0 + 1e-6), "{}", top(&slow));
    let (ta, tp, ts) = (
        auto.summary.time_s,
        paper.summary.time_s,
        slow.summary.time_s,
    );
    assert!(
        ta < 0.8 * tp && ta < ts,
        "auto {ta} s, paper {tp} s, v_max 0.5: {ts} s"
    );
    // The same flow lines: the end points of the discoveries agree.
    let order = |r: &harmonav_sim::summary::Run| {
        r.summary
            .discoveries
            .iter()
            .map(|d| d.obstacle.clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(order(&auto), order(&paper));
}

/// `robot.margin`: the field is built on shapes grown by it, so the run keeps that clearance to
/// the true shapes and the monitor checks it; without it the same robot passes closer.
#[test]
fn a_margin_is_kept_as_clearance_and_checked() {
    let path = Path::new("margin.toml");
    let text = BASE
        .replacen("start = [-3.0, 0.0]", "start = [-3.0, 0.4]", 1)
        .replacen("[sensor]\nrange = 1.0\naperture_deg = 60.0\n", "", 1);
    let clearance = |margin: f64| {
        let text = text.replacen(
            "goal = [3.0, 0.0]",
            &format!("goal = [3.0, 0.0]\nmargin = {margin}"),
            1,
        );
        let p = Scenario::parse(path, &text).unwrap().prepare(path).unwrap();
        let s = run(&p, None).unwrap().summary;
        assert!(s.reached && s.all_passed(), "{:?}", s.guarantees);
        s.min_clearance
    };
    let (without, with) = (clearance(0.0), clearance(0.1));
    assert!(without < 0.1, "without a margin: {without} m");
    assert!((0.1..0.2).contains(&with), "with a 0.1 m margin: {with} m");
    // The monitor judges the margin: the same run against a larger stated margin fails.
    let mut p = Scenario::parse(path, &text).unwrap().prepare(path).unwrap();
    p.scenario.robot.margin = 0.2;
    let s = run(&p, None).unwrap().summary;
    let g = s
        .guarantees
        .iter()
        .find(|g| g.kind() == Kind::NoCollision)
        .unwrap();
    assert!(!g.passed, "{g:?}");
    assert!(
        matches!(g.check, Check::NoCollision { min_clearance, margin } if margin == 0.2 && min_clearance < 0.2),
        "{g:?}"
    );
}

#[test]
fn runs_are_deterministic_and_the_kinematic_run_keeps_every_guarantee() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shapes/mixed.toml");
    let prepared = Scenario::load(&file).unwrap();
    let a = run(&prepared, Some(Model::Kinematic)).unwrap();
    let b = run(&prepared, Some(Model::Kinematic)).unwrap();
    let (ja, jb) = (
        serde_json::to_string(&a.summary).unwrap(),
        serde_json::to_string(&b.summary).unwrap(),
    );
    assert_eq!(ja, jb, "two runs differ");
    assert_eq!(a.samples, b.samples);
    let s = &a.summary;
    assert!(s.reached && s.all_passed() && s.safe(), "{ja}");
    assert!(s.min_clearance > 0.0 && s.collisions == 0);
    // The typed policy fields keep summary.json's names (a contract: readers key on them).
    let v: serde_json::Value = serde_json::from_str(&ja).unwrap();
    assert_eq!(
        (&v["physics"], &v["k_policy"], &v["damping"], &v["model"]),
        (
            &serde_json::json!("builtin"),
            &serde_json::json!("auto"),
            &serde_json::Value::Null,
            &serde_json::json!("kinematic")
        )
    );
    let dynamic = run(&prepared, Some(Model::Dynamic)).unwrap().summary;
    let v = serde_json::to_value(&dynamic).unwrap();
    assert_eq!(v["damping"], serde_json::json!("governed"), "{v}");
    assert!(!s.discoveries.is_empty());
    // Samples on the dt grid (plus discovery instants and the end).
    let dt = prepared.scenario.sim.dt;
    assert!(
        a.samples
            .windows(2)
            .all(|w| w[1].t - w[0].t <= dt * (1.0 + 1e-9))
    );
    let on_grid = a
        .samples
        .iter()
        .filter(|s| ((s.t / dt).round() * dt - s.t).abs() < 1e-9)
        .count();
    assert!(on_grid * 10 > a.samples.len() * 9);
}

#[test]
fn dynamic_run_keeps_the_speed_bound_and_arrives_without_overshoot() {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shapes/dynamic-small.toml");
    let prepared = Scenario::load(&file).unwrap();
    let r = run(&prepared, None).unwrap();
    let s = &r.summary;
    assert!(
        s.reached && s.all_passed(),
        "{}",
        serde_json::to_string_pretty(s).unwrap()
    );
    assert!(s.max_speed < s.speed_bound.unwrap());
    let overshoot = s
        .guarantees
        .iter()
        .find(|g| g.kind() == Kind::NoOvershoot)
        .unwrap();
    // It entered the critically damped basin (at least two samples there) and did not overshoot.
    assert!(
        overshoot.passed
            && matches!(overshoot.check, Check::NoOvershoot { samples, .. } if samples >= 2),
        "{overshoot:?}"
    );
    // Energy never rises between discoveries (V̇ = −λ|ẋ|²).
    let d: Vec<f64> = s.discoveries.iter().map(|d| d.time_s).collect();
    for w in r.samples.windows(2) {
        if !d.iter().any(|&t| t > w[0].t - 1e-12 && t <= w[1].t + 1e-12) {
            let (a, b) = (w[0].energy.unwrap(), w[1].energy.unwrap());
            assert!(
                b <= a * (1.0 + 1e-6) + 1e-12,
                "V rose from {a} to {b} at t = {}",
                w[1].t
            );
        }
    }
}

/// Eq. dissipationfun's switch (scenarios/hard/lambda-switch.toml), under both damping policies:
/// wherever a recorded state has `V ≥ μ_p` (the pull), the damping is switched and at least
/// `(m/d_min)|ẋ(T_n)|`, exactly that under "paper"; with "auto", "fast" and "governed" the
/// discovery does lift `V` to μ_p (4μ under "governed") and the switch is recorded; and the
/// stopping-distance argument holds: the robot ends the switched interval within `d_min` of
/// where it began, never touching the disc.
#[test]
fn the_damping_switch_engages_after_a_discovery_and_brakes_within_d_min() {
    use harmonav_control::DampingPolicy;
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/hard/lambda-switch.toml");
    let base = Scenario::load(&file).unwrap();
    let harmonav_scenario::Sensor::Sector(sector) = base.truth.sensor else {
        panic!("the file has a sector")
    };
    let d_min = sector.d_min(base.truth.rho_min);
    for policy in DampingPolicy::ALL {
        let mut prepared = base.clone();
        prepared.scenario.controller.damping = policy;
        // The paper's robot reaches the disc only after 81 s.
        prepared.scenario.sim.max_time = 300.0;
        let r = run(&prepared, None).unwrap();
        let s = &r.summary;
        let held = s.guarantees.iter().all(|g| {
            g.passed
                || (policy == DampingPolicy::Paper
                    && matches!(g.check, Check::ExpectDampingSwitched { .. }))
        });
        assert!(
            held,
            "{policy}: {}",
            serde_json::to_string_pretty(s).unwrap()
        );
        // The switch is at V ≥ μ_p, the pull of a navigator built as the simulator builds it
        // (m = 1 and μ = 10 in the file; the pull grows with the shrunk boundary's radius).
        let truth = &prepared.truth;
        let nav = harmonav::Navigator::new(
            truth.boundary.clone(),
            truth.goal(),
            harmonav::Law::dynamic(1.0, 10.0),
            harmonav::Options::default()
                .with_robot(truth.radius, truth.margin)
                .with_damping(policy),
        )
        .unwrap();
        let harmonav::Controller::Dynamic(law) = nav.controller() else {
            panic!("a dynamic navigator")
        };
        let pull = law.pull();
        let t_n = s.discoveries.last().unwrap().time_s;
        let at_discovery = r.samples.iter().find(|x| x.t == t_n).unwrap();
        let v_n = Vector2::from(at_discovery.v).norm();
        let switched: Vec<_> = r
            .samples
            .iter()
            .filter(|x| x.energy.unwrap() >= pull && x.t > 0.0)
            .collect();
        for x in &switched {
            assert!(
                !x.critical,
                "{policy}: V ≥ μ at t = {} but λ not switched",
                x.t
            );
            let floor = 1.0 / d_min * v_n;
            let lambda = x.lambda.unwrap();
            match policy {
                DampingPolicy::Paper => assert_eq!(lambda, floor),
                _ => assert!(lambda >= floor, "{lambda} < {floor}"),
            }
        }
        if matches!(
            policy,
            DampingPolicy::Auto | DampingPolicy::Fast | DampingPolicy::Governed
        ) {
            assert!(
                !switched.is_empty(),
                "{policy}: the discovery did not lift V to μ"
            );
            assert!(r.samples.iter().any(|x| !x.critical && x.t == t_n));
            let last = r.samples.iter().rfind(|x| !x.critical).unwrap();
            let travelled = (Vector2::from(last.x) - Vector2::from(at_discovery.x)).norm();
            assert!(
                travelled <= d_min,
                "{travelled} m in the switched interval, d_min {d_min}"
            );
        }
    }
}

/// The paper runs its two studies in one world: the two files must not drift apart.
#[test]
fn the_paper_studies_share_one_world() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/paper");
    let read = |name: &str| {
        let path = dir.join(name);
        let text = std::fs::read_to_string(&path).unwrap();
        Scenario::parse(&path, &text).unwrap()
    };
    let (kin, dyn_) = (read("kinematic.toml"), read("dynamic.toml"));
    assert_eq!(kin.workspace, dyn_.workspace);
    assert_eq!(kin.obstacles, dyn_.obstacles);
    assert_eq!(kin.sensor, dyn_.sensor);
    assert_eq!(kin.controller, dyn_.controller);
    assert_eq!(
        (kin.robot.start, kin.robot.goal),
        (dyn_.robot.start, dyn_.robot.goal)
    );
    assert_eq!(
        (kin.robot.model, dyn_.robot.model),
        (Model::Kinematic, Model::Dynamic)
    );
    assert_eq!(kin.obstacles.len(), 6);
}

/// hard/non-morse.toml: the census finds the degenerate critical point of proposition Morse at
/// the origin, the file's start (0.001 m off the axis) reaches the goal, and a start on the
/// symmetry axis flows into the degenerate point and stays there.
#[test]
fn the_non_morse_world_has_a_degenerate_point_that_only_the_axis_reaches() {
    use harmonav_potential::CriticalKind;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/hard/non-morse.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let scenario = Scenario::parse(&path, &text).unwrap();
    let prepared = scenario.clone().prepare(&path).unwrap();
    let field = prepared.global_field().unwrap();
    let degenerate: Vec<_> = field
        .critical_points()
        .into_iter()
        .filter(|c| {
            c.point_world
                .as_ref()
                .is_some_and(|p| p.kind == CriticalKind::Degenerate)
        })
        .collect();
    assert_eq!(degenerate.len(), 1);
    // A root of multiplicity 3 is located to about ε^(1/3) ≈ 6e-6.
    assert!(degenerate[0].x.norm() < 1e-4, "{:?}", degenerate[0].x);

    let off_axis = run(&prepared, None).unwrap();
    assert!(
        off_axis.summary.all_passed(),
        "{:?}",
        off_axis.summary.guarantees
    );

    let mut on_axis = scenario;
    on_axis.robot.start = [2.5, 0.0];
    on_axis.sim.max_time = 20.0;
    let stuck = run(&on_axis.prepare(&path).unwrap(), None).unwrap();
    assert!(!stuck.summary.reached);
    assert_eq!(stuck.summary.collisions, 0);
    let end = stuck.samples.last().unwrap().x;
    // On the axis by symmetry, and within the integrator's chatter of the point.
    assert_eq!(end[1], 0.0);
    assert!(end[0].abs() < 1e-5, "stopped at {end:?}");

    // The sweep types the same ending: stalled on the axis, reached off it.
    use harmonav_sim::sweep::{Counts, Outcome, sweep};
    let starts = [Vector2::new(2.5, 0.0), Vector2::new(2.5, 0.3)];
    let outcomes = sweep(&prepared, &starts, Model::Kinematic, 2).unwrap();
    assert!(
        matches!(outcomes[0], Outcome::Stalled { .. }),
        "{outcomes:?}"
    );
    assert!(outcomes[1].reached(), "{outcomes:?}");
    let c = Counts::of(&outcomes);
    assert_eq!((c.reached, c.stalled, c.collisions), (1, 1, 0));
}

/// `[expect]` describes the file's own model: a run with the other model is judged on the
/// guarantees alone (the paper's kinematic study, driven by the dynamic law, creeps and finds
/// only O1 — not what its `[expect]` says of the kinematic run).
#[test]
fn expectations_apply_to_the_files_own_model_only() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/paper/kinematic.toml");
    let prepared = Scenario::load(&file).unwrap();
    let expects = |model| {
        run(&prepared, Some(model))
            .unwrap()
            .summary
            .guarantees
            .iter()
            .filter(|g| g.kind() == Kind::Expect)
            .count()
    };
    assert_eq!(expects(Model::Kinematic), 2);
    assert_eq!(expects(Model::Dynamic), 0);
}

/// A start on the symmetry axis of a deep star facing it (`k = "paper"`) descends onto the
/// saddle on the axis, where the normalised kinematic law chatters at ever smaller steps: the
/// run stops as stalled after `STALL_STEPS` steps at rest (it used to integrate on for 188
/// million steps to max_time). The same start 0.3 m off the axis arrives.
#[test]
fn a_start_on_a_symmetry_axis_ends_stalled_at_once() {
    let toml = |y: f64| {
        format!(
            "name = \"symmetric-saddle\"\n[workspace]\ntype = \"circle\"\ncenter = [0.0, 0.0]\n\
             radius = 5.0\n[[obstacles]]\nname = \"star\"\ntype = \"star\"\ncenter = [0.0, 0.0]\n\
             radius = 1.6\nharmonics = [[3, 0.8, 0.0]]\n[robot]\nmodel = \"kinematic\"\n\
             start = [-4.0, {y}]\ngoal = [4.2, 0.0]\nradius = 0.1\n[field]\nk = \"paper\"\n\
             [sim]\nmax_time = 120.0\n"
        )
    };
    let path = std::path::Path::new("symmetric-saddle.toml");
    let on_axis = harmonav_scenario::Scenario::parse(path, &toml(0.0))
        .unwrap()
        .prepare(path)
        .unwrap();
    let r = harmonav_sim::run::run(&on_axis, None).unwrap();
    assert!(
        matches!(
            r.summary.outcome,
            harmonav_sim::outcome::Outcome::Stalled { .. }
        ),
        "{:?}",
        r.summary.outcome
    );
    assert!(
        r.summary.steps <= harmonav_sim::STALL_STEPS + 2000,
        "{} steps",
        r.summary.steps
    );
    assert!(
        r.summary.time_s < 1.0,
        "stopped at t = {}",
        r.summary.time_s
    );
    let off_axis = harmonav_scenario::Scenario::parse(path, &toml(0.3))
        .unwrap()
        .prepare(path)
        .unwrap();
    assert!(
        harmonav_sim::run::run(&off_axis, None)
            .unwrap()
            .summary
            .reached
    );
}

/// The validation gaps of the hostile round (issue: hardening), each refused with the file, the
/// field and the problem named.
#[test]
fn hostile_values_are_refused_naming_the_field() {
    let base = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shapes/mixed.toml"),
    )
    .unwrap();
    let path = Path::new("hostile.toml");
    let check = |from: &str, to: &str, field: &str, words: &[&str]| {
        assert!(base.contains(from), "{from}");
        let text = base.replacen(from, to, 1);
        let e = Scenario::parse(path, &text)
            .and_then(|s| s.prepare(path))
            .expect_err(to);
        assert_eq!(e.field, field, "{to}: {e}");
        let msg = e.to_string();
        for w in words {
            assert!(msg.contains(w), "{to}: {msg}");
        }
    };
    // A bad value in the third obstacle names it and its line.
    check(
        "corner_radius = 0.1",
        "corner_radius = \"x\"",
        "obstacles[2]",
        &["hostile.toml:22"],
    );
    // A top-level type error names its key.
    check(
        "name = \"shapes-mixed\"",
        "name = 5",
        "name",
        &["hostile.toml:1"],
    );
    check(
        "radius = 0.5\n",
        "radius = 1e155\n",
        "obstacles[0].radius",
        &["at most"],
    );
    check("dt = 0.01", "dt = 1e-300", "sim.dt", &["[1e-9"]);
    check(
        "dt = 0.01",
        "dt = 1e-9",
        "sim.dt",
        &["states to record", "1e9"],
    );
    check("mass = 1.0", "mass = 5e-324", "robot.mass", &["[1e-9"]);
    check(
        "max_time = 200.0",
        "max_time = 1e12",
        "sim.max_time",
        &["1e9"],
    );
    check(
        "aperture_deg = 60.0",
        "aperture_deg = 1e-320",
        "sensor.aperture_deg",
        &["0.001°"],
    );
    check(
        "goal_tolerance = 0.01",
        "goal_tolerance = 0.01\n[expect]\nmax_speed_below = nan",
        "expect.max_speed_below",
        &["finite"],
    );
    let many: String = (0..2001)
        .map(|i| {
            format!(
                "[[obstacles]]\ntype = \"circle\"\ncenter = [{}, {}]\nradius = 0.01\n",
                -5.0 + 0.2 * (i % 50) as f64,
                -4.0 + 0.2 * (i / 50) as f64
            )
        })
        .collect();
    let text = base.replacen("[robot]", &format!("{many}[robot]"), 1);
    let e = Scenario::parse(path, &text)
        .unwrap()
        .prepare(path)
        .unwrap_err();
    assert!(e.to_string().contains("at most 2000"), "{e}");
}

/// A device or an oversized file is refused, not read forever: a device (and a FIFO, which
/// would block `open` for ever, issue 56 D14) as not a regular file, a large file by its size.
#[test]
fn an_endless_file_is_refused() {
    let e = Scenario::load(Path::new("/dev/zero")).unwrap_err();
    assert!(e.to_string().contains("not a regular file"), "{e}");
    let dir = std::env::temp_dir().join(format!("harmonav-endless-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let big = dir.join("big.toml");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(harmonav_scenario::MAX_FILE_BYTES + 1)
        .unwrap();
    let e = Scenario::load(&big).unwrap_err();
    assert!(e.to_string().contains("larger than"), "{e}");
    let fifo = dir.join("fifo.toml");
    if std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        let e = Scenario::load(&fifo).unwrap_err();
        assert!(e.to_string().contains("not a regular file"), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The sweep follows the law with its gain: twice the gain, half the time on the same paths
/// (under the paper's speed `K√(2Θ)`; under `"auto"` the braking distance `d_b ∝ K` does not
/// scale with the goal tolerance, so the time is not exactly halved).
#[test]
fn the_sweep_follows_the_gain() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shapes/mixed.toml");
    let prepared = Scenario::load(&file).unwrap();
    let starts = harmonav_sim::sweep::random_starts(&prepared, 4, 1).unwrap();
    let times = |gain: f64| -> Vec<f64> {
        let mut p = prepared.clone();
        p.scenario.controller.gain = gain;
        p.scenario.controller.speed = SpeedPolicy::Paper;
        harmonav_sim::sweep::sweep(&p, &starts, Model::Kinematic, 2)
            .unwrap()
            .iter()
            .map(|o| o.time().unwrap())
            .collect()
    };
    for (a, b) in times(1.0).iter().zip(times(2.0)) {
        assert!((b / a - 0.5).abs() < 0.02, "{a} s at K = 1, {b} s at K = 2");
    }
    assert!(harmonav_sim::sweep::random_starts(&prepared, 2_000_000, 1).is_err());
}

/// The format example of scenarios/README.md is a valid scenario whose run holds every
/// guarantee and its own `[expect]`.
#[test]
fn the_readme_format_example_holds_its_own_expectations() {
    let readme = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/README.md"),
    )
    .unwrap();
    let start = readme.find("```toml\n").expect("a toml block") + "```toml\n".len();
    let text = &readme[start..start + readme[start..].find("```").unwrap()];
    let path = Path::new("scenarios/README.md");
    let prepared = Scenario::parse(path, text).unwrap().prepare(path).unwrap();
    let r = run(&prepared, None).unwrap();
    let failed: Vec<_> = r.summary.guarantees.iter().filter(|g| !g.passed).collect();
    assert!(failed.is_empty(), "{failed:?}");
    assert_eq!(
        r.summary
            .guarantees
            .iter()
            .filter(|g| g.kind() == Kind::Expect)
            .count(),
        4,
        "every [expect] line is checked"
    );
}

/// The warnings: none in the suites but one (`lidar/margin-band.toml` fits within the robot's
/// margin on purpose, and is told so); a goal tolerance of 0.5 m over a 6 m route, a start at
/// the saddle itself, and a start on the saddle's stable manifold each draw theirs.
#[test]
fn warnings_name_what_the_verdict_alone_would_not_explain() {
    use harmonav_sim::physics::warnings as check;
    use harmonav_sim::warning::Warning;
    for file in scenario_files() {
        let p = Scenario::load(&file).unwrap();
        let warnings = check(&p, None).unwrap();
        if file.ends_with("lidar/margin-band.toml") {
            assert!(
                matches!(warnings[..], [Warning::ScansTooSparse { room, .. }] if room < 0.0),
                "{warnings:?}"
            );
        } else {
            assert_eq!(warnings, [], "{}", file.display());
        }
    }
    // BASE with global sensing: disc A sits on the start–goal axis, B above it.
    let global = BASE.replace("[sensor]\nrange = 1.0\naperture_deg = 60.0\n", "");
    let load = |text: &str| {
        Scenario::parse(Path::new("w.toml"), text)
            .unwrap()
            .prepare(Path::new("w.toml"))
            .unwrap()
    };
    let loose = load(&format!("{global}[sim]\ngoal_tolerance = 0.5\n"));
    assert!(matches!(
        check(&loose, None).unwrap().as_slice(),
        [Warning::GoalToleranceLarge { goal_tolerance, scale }, ..]
            if *goal_tolerance == 0.5 && (*scale - 5.0).abs() < 1e-9
    ));
    // Without B the world is mirror-symmetric about y = 0: the axis through A is the stable
    // manifold of the saddle between A and the start.
    let symmetric = global.replace(
        "[[obstacles]]\nname = \"B\"\ntype = \"ellipse\"\ncenter = [0.0, 2.5]\nsemi_axes = [0.8, 0.3]\n",
        "",
    );
    let on_axis = load(&symmetric);
    let w = check(&on_axis, None).unwrap();
    let [Warning::StartOnSaddleManifold { saddle }] = w.as_slice() else {
        panic!("{w:?}");
    };
    assert!(saddle[0] < -1.0 && saddle[1].abs() < 1e-9, "{saddle:?}");
    let r =
        harmonav_sim::physics::simulate(&on_axis, None, harmonav_sim::physics::Physics::Builtin)
            .unwrap();
    assert_eq!(r.summary.outcome.kind(), "stalled");
    assert_eq!(r.summary.warnings, w);
    let at_saddle = load(&symmetric.replace(
        "start = [-3.0, 0.0]",
        &format!("start = [{:?}, 0.0]", saddle[0]),
    ));
    let w = check(&at_saddle, None).unwrap();
    assert!(
        matches!(
            w.as_slice(),
            [Warning::StartAtCriticalPoint] | [Warning::StartOnSaddleManifold { .. }]
        ),
        "{w:?}"
    );
    // Off the axis by 5 cm: no warning, and the run arrives.
    let off = load(&symmetric.replace("start = [-3.0, 0.0]", "start = [-3.0, 0.05]"));
    assert_eq!(check(&off, None).unwrap(), []);
}

/// Issue 51: `[robot] control_period` of a star-world file is its navigator's control period:
/// the user's loop (a golden trace) steps by it under both laws; without it, the law's
/// default. A bad one is refused by name.
#[test]
fn a_star_world_file_sets_the_control_period() {
    let path = Path::new("period.toml");
    let with = BASE.replace(
        "goal = [3.0, 0.0]",
        "goal = [3.0, 0.0]\ncontrol_period = 0.02",
    );
    let set = Scenario::parse(path, &with)
        .and_then(|s| s.prepare(path))
        .unwrap();
    let default = Scenario::parse(path, BASE)
        .and_then(|s| s.prepare(path))
        .unwrap();
    // The second line of a trace is at t = h, the navigator's control period.
    let second_t = |trace: &str| {
        let t = trace.lines().nth(1).unwrap().split(' ').next().unwrap();
        f64::from_bits(u64::from_str_radix(t, 16).unwrap())
    };
    for (model, law_default) in [(Model::Kinematic, 0.01), (Model::Dynamic, 0.001)] {
        let trace = harmonav_sim::golden::star(&set, model, 3).unwrap();
        assert_eq!(second_t(&trace), 0.02, "{trace}");
        let trace = harmonav_sim::golden::star(&default, model, 3).unwrap();
        assert_eq!(second_t(&trace), law_default, "{trace}");
    }
    check(
        "goal = [3.0, 0.0]",
        "goal = [3.0, 0.0]\ncontrol_period = -1.0",
        "robot.control_period",
        "must be finite",
        None,
    );
}

/// Issue 51: in the rapier cross-check of a star world, `[robot] control_period` is the period
/// over which each command is held (in rapier steps of at most 1 ms); the run still arrives
/// without contact, along another path than the one commanded every step.
#[cfg(feature = "rapier")]
#[test]
fn the_rapier_loop_holds_each_command_for_the_control_period() {
    use harmonav_sim::rapier::{Drive, run_rapier};
    let path = Path::new("period.toml");
    let load = |text: &str| {
        Scenario::parse(path, text)
            .and_then(|s| s.prepare(path))
            .unwrap()
    };
    let held = load(&BASE.replace(
        "goal = [3.0, 0.0]",
        "goal = [3.0, 0.0]\ncontrol_period = 0.05",
    ));
    let every_step = load(BASE);
    let (a, ra) = run_rapier(&held, None, Drive::Law, None).unwrap();
    let (b, rb) = run_rapier(&every_step, None, Drive::Law, None).unwrap();
    for (run, report) in [(&a, &ra), (&b, &rb)] {
        assert!(run.summary.reached, "{:?}", run.summary);
        assert_eq!(report.contacts, 0);
    }
    assert_ne!(a.summary.time_s, b.summary.time_s);
    // The recording interval is still `sim.dt` (discoveries add states between).
    let mut dts: Vec<f64> = a.samples.windows(2).map(|w| w[1].t - w[0].t).collect();
    dts.sort_by(f64::total_cmp);
    let dt = dts[dts.len() / 2];
    assert!((dt - 0.01).abs() < 1e-9, "{dt}");
}
