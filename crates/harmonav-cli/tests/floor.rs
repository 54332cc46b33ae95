//! `harmonav run | eval | sweep | check` on floor-plan files (`[floor_plan]`, issue 25): the
//! summary's guarantees (built-in and rapier), the output set, `Θ` against finite differences,
//! the sweep over the file's starts, and the star-world options refused by name.

use std::path::{Path, PathBuf};

mod common;

use common::{harmonav, scenario, scratch};

fn floorplan(name: &str) -> String {
    scenario(&format!("floorplans/{name}"))
}

fn guarantee<'a>(v: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    v["guarantees"]
        .as_array()
        .unwrap()
        .iter()
        .find(|g| g["name"] == name)
        .unwrap_or_else(|| panic!("no guarantee {name} in {v}"))
}

#[test]
fn a_floor_plan_runs_with_every_guarantee_judged_and_writes_one_output_set() {
    let dir = scratch("out");
    // A stale recording of an earlier star-world run in the folder: the set replaces it.
    std::fs::write(dir.join("run.mcap"), b"stale").unwrap();
    let (code, out, err) = harmonav(&[
        "run",
        &floorplan("l-room.toml"),
        "--model",
        "kinematic",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}\n{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["reached"], true);
    assert_eq!(v["outcome"], "reached");
    assert_eq!(v["model"], "kinematic");
    assert_eq!(v["speed_bound"], serde_json::Value::Null);
    for name in [
        "reached-goal",
        "no-collision",
        "no-collision-between-states",
        "stayed-in-workspace",
        "stayed-in-certified-region",
        "discoveries",
    ] {
        assert_eq!(guarantee(&v, name)["passed"], true, "{name}: {v}");
    }
    // The swept bound lies below the clearance at the states, by at most half a step.
    let (swept, states) = (
        v["swept_clearance"].as_f64().unwrap(),
        v["min_clearance"].as_f64().unwrap(),
    );
    let step = 0.01 * v["max_speed"].as_f64().unwrap();
    assert!(
        swept <= states && swept >= states - 0.5 * step - 1e-12,
        "{swept} {states}"
    );
    assert!(states >= 0.1 - 1e-6, "the margin: {states}");
    // The sensed obstacles of the file, in the order met along the lower arm.
    let names: Vec<&str> = v["discoveries"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["obstacle"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["box", "bin"]);
    // The set: the summary as printed, the figure, and the run's own recording.
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(written, v);
    let svg = std::fs::read_to_string(dir.join("trajectory.svg")).unwrap();
    assert!(
        svg.starts_with("<svg") && svg.contains("<polyline"),
        "{}",
        &svg[..200]
    );
    assert!(
        svg.contains("box") && svg.contains("bin"),
        "the discovered names"
    );
    // The recording replaced the stale one: an MCAP file (its magic at both ends).
    let mcap = std::fs::read(dir.join("run.mcap")).unwrap();
    let magic = b"\x89MCAP0\r\n";
    assert!(
        mcap.starts_with(magic) && mcap.ends_with(magic),
        "{}",
        mcap.len()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_dynamic_law_on_a_floor_plan_is_judged_against_its_speed_bound() {
    let (code, out, err) = harmonav(&["run", &floorplan("u-trap.toml"), "--model", "dynamic"]);
    assert_eq!(code, 0, "{err}\n{out}");
    assert!(out.contains("goal reached"), "{out}");
    assert!(out.contains("speed-below-bound"), "{out}");
    assert!(out.contains("stayed-in-certified-region"), "{out}");
}

#[test]
fn a_floor_plan_run_that_does_not_arrive_exits_with_one() {
    let dir = scratch("short");
    let text = std::fs::read_to_string(floorplan("l-room.toml"))
        .unwrap()
        .replace("max_time = 240.0", "max_time = 1.0");
    let file = dir.join("short.toml");
    std::fs::write(&file, text).unwrap();
    let (code, out, err) = harmonav(&["run", file.to_str().unwrap(), "--json"]);
    assert_eq!(code, 1, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["outcome"], "timed_out");
    assert_eq!(guarantee(&v, "reached-goal")["passed"], false);
    assert_eq!(guarantee(&v, "no-collision")["passed"], true);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn eval_on_a_floor_plan_agrees_with_finite_differences_and_names_bad_points() {
    let file = floorplan("l-room.toml");
    let h = 1e-5;
    let (x, y) = (1.0, 3.0);
    let at = |dx: f64, dy: f64| format!("{},{}", x + dx, y + dy);
    let points = [
        at(0.0, 0.0),
        at(h, 0.0),
        at(-h, 0.0),
        at(0.0, h),
        at(0.0, -h),
        "1.0,4.0".to_string(),  // inside the pillar (a hole of the plan)
        "3.5,0.9".to_string(),  // inside the box
        "0.18,3.0".to_string(), // in the boundary layer (0.15–0.2 m from the wall)
        "0.1,3.0".to_string(),  // the robot's disc across the wall
    ];
    let mut args = vec!["eval", file.as_str(), "--json"];
    for p in &points {
        args.push("--at");
        args.push(p);
    }
    let (code, out, err) = harmonav(&args);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let value = |i: usize| v[i]["value"].as_f64().unwrap();
    assert!(value(0) > 0.0 && value(0) < 1.0, "{v}");
    let fd = [
        (value(1) - value(2)) / (2.0 * h),
        (value(3) - value(4)) / (2.0 * h),
    ];
    let grad = [
        v[0]["grad"][0].as_f64().unwrap(),
        v[0]["grad"][1].as_f64().unwrap(),
    ];
    let norm = grad[0].hypot(grad[1]);
    assert!(norm > 0.0);
    for (g, f) in grad.iter().zip(fd) {
        assert!((g - f).abs() <= 1e-4 * norm, "∇Θ {grad:?} against {fd:?}");
    }
    assert!(v[5]["error"].is_string(), "{v}");
    assert_eq!(v[6]["error"], "inside obstacle box");
    // Named as the layer it is (issue 56, D19.1: "on or outside the workspace boundary").
    let layer = v[7]["error"].as_str().unwrap();
    assert!(
        layer.contains("boundary layer") && layer.contains("δ = 0.05 m"),
        "{layer}"
    );
    let outside = v[8]["error"].as_str().unwrap();
    assert!(
        outside.contains("outside") && !outside.contains("layer"),
        "{outside}"
    );
}

#[test]
fn check_solves_the_map() {
    let file = floorplan("u-trap.toml");
    let (code, out, err) = harmonav(&["check", &file]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("ok: floor plan, "), "{out}");
    // c_δ certified over the walls, and each start's place against it (the start beside the
    // goal, (5.02, 0.76), below it; the file's start across the U above it).
    assert!(
        out.contains("c_δ = 0.") && out.contains("c_s = ") && out.contains("of 7 starts certified"),
        "{out}"
    );
    assert!(out.contains("start (1.000, 2.100): not certified"), "{out}");
    assert!(out.contains("start (5.024, 0.762): certified"), "{out}");
    // A bad floor plan is named by its field, as every scenario error is.
    let dir = scratch("bad");
    let bad = dir.join("bad.toml");
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace("start = [1.0, 2.1]", "start = [4.8, 2.5]");
    std::fs::write(&bad, text).unwrap();
    let (code, _, err) = harmonav(&["run", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("robot.start") && err.contains("bad.toml"),
        "{err}"
    );
    assert!(Path::new(&bad).exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--physics rapier` on a floor plan: the walls are rapier colliders, the summary says which
/// integrator ran and carries rapier's checks (no contact event, the deviation from the
/// built-in run) besides every guarantee of the built-in loop.
#[test]
fn a_floor_plan_runs_in_rapier_with_no_contact() {
    let (code, out, err) = harmonav(&[
        "run",
        &floorplan("u-trap.toml"),
        "--physics",
        "rapier",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}\n{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["physics"], "rapier");
    assert_eq!(v["physics_contacts"], 0);
    assert_eq!(v["reached"], true);
    for name in [
        "reached-goal",
        "no-collision",
        "no-collision-between-states",
        "stayed-in-certified-region",
        "physics-no-contact",
        "physics-deviation",
    ] {
        assert_eq!(guarantee(&v, name)["passed"], true, "{name}: {v}");
    }
    let deviation = guarantee(&v, "physics-deviation")["measured"]["max_deviation"]
        .as_f64()
        .unwrap();
    assert!(deviation < 1e-3, "{deviation}");
    // The built-in run says so, and has no contact count.
    let (code, out, err) = harmonav(&["run", &floorplan("u-trap.toml"), "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["physics"], "builtin");
    assert_eq!(v["physics_contacts"], serde_json::Value::Null);
}

/// `sweep` on a floor plan runs the file's starts (`robot.start` and `[starts]`; `--starts`
/// and `--seed` override the count and seed) and prints the star world's report.
#[test]
fn sweep_on_a_floor_plan_runs_the_files_starts() {
    let file = floorplan("u-trap.toml");
    let (code, out, err) = harmonav(&["sweep", &file, "--starts", "2", "--json"]);
    assert_eq!(code, 0, "{err}\n{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["starts"], 3, "robot.start and 2 seeded: {v}");
    assert_eq!(v["reached"], 3, "{v}");
    assert_eq!(v["collisions"], 0);
    assert!(v["failures"].as_array().unwrap().is_empty(), "{v}");
    assert!(v["median_time_s"].as_f64().unwrap() > 0.0);
    let (code, out, err) = harmonav(&["sweep", &file, "--starts", "1"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("2 of 2 starts reached the goal"), "{out}");
    // More seeded starts than a floor-plan file takes: named by the flag that asked for them
    // (issue 56, D19.4; before, by the file's `starts.count`, which the file did not set).
    let (code, _, err) = harmonav(&["sweep", &file, "--starts", "65"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--starts") && err.contains("at most 64") && err.contains("u-trap.toml"),
        "{err}"
    );
    assert!(!err.contains("starts.count"), "{err}");
    // A star world still needs --starts.
    let star = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/shapes/mixed.toml")
        .to_string_lossy()
        .into_owned();
    let (code, _, err) = harmonav(&["sweep", &star]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--starts") && err.contains("mixed.toml"),
        "{err}"
    );
}

/// `--k` and `--damping` set a floor plan's `[field] k` and `[controller] damping`, as in a star
/// world: the summary names the policies, `Θ` differs between the two `k` policies (the U-trap
/// has one hole and senses its pillar: `k = n + 1 = 3` at the end under "paper"), and the
/// damping changes the dynamic run.
#[test]
fn k_and_damping_set_a_floor_plans_policies() {
    let file = floorplan("u-trap.toml");
    let value = |policy: &str| {
        let (code, out, err) = harmonav(&["eval", &file, "--at", "1,2.1", "--k", policy, "--json"]);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()[0]["value"]
            .as_f64()
            .unwrap()
    };
    assert_ne!(value("paper"), value("auto"));
    let run = |args: &[&str]| {
        let mut all = vec!["run", &file, "--json"];
        all.extend_from_slice(args);
        let (code, out, err) = harmonav(&all);
        assert!(code == 0 || code == 1, "{args:?}: {err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let paper = run(&["--k", "paper"]);
    assert_eq!(paper["k_policy"], "paper", "{paper}");
    assert_eq!(paper["k"].as_f64(), Some(3.0), "{paper}");
    assert_eq!(paper["damping"], serde_json::Value::Null, "{paper}");
    let (governed, shaped) = (
        run(&["--controller", "dynamic"]),
        run(&["--controller", "dynamic", "--damping", "paper"]),
    );
    assert_eq!(governed["damping"], "governed", "{governed}");
    assert_eq!(shaped["damping"], "paper", "{shaped}");
    assert_ne!(governed["time_s"], shaped["time_s"]);
    let (code, _, err) = harmonav(&["sweep", &file, "--damping", "critical"]);
    assert_eq!(code, 2);
    assert!(err.contains("paper") && err.contains("governed"), "{err}");
}

/// `census` on a floor plan (theorem `isNF` through `Phi`): the U-trap's `Θ` over its hole and
/// its pillar has the goal as its one minimum and one saddle per hole and obstacle, whose
/// Hessian has one negative and one positive eigenvalue; the goal's is positive definite.
#[test]
fn census_on_a_floor_plan_finds_the_goal_and_one_saddle_per_hole_and_obstacle() {
    let file = floorplan("u-trap.toml");
    let (code, out, err) = harmonav(&["census", &file, "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        (v["minima"].as_u64(), v["saddles"].as_u64()),
        (Some(1), Some(2)),
        "{v}"
    );
    assert_eq!(v["outside_certified_region"].as_u64(), Some(0), "{v}");
    let points = v["points"].as_array().unwrap();
    assert_eq!(
        (points[0]["x"].as_f64(), points[0]["y"].as_f64()),
        (Some(6.8), Some(2.5))
    );
    let e0 = points[0]["eigenvalues"].as_array().unwrap();
    assert!(e0[0].as_f64().unwrap() > 0.0, "{v}");
    // Each saddle's Hessian is indefinite (crates/harmonav-floorplan/tests/census.rs checks
    // that `∇Θ` vanishes there).
    for p in &points[1..] {
        assert_eq!(p["kind"], "saddle");
        let e = p["eigenvalues"].as_array().unwrap();
        assert!(
            e[0].as_f64().unwrap() < 0.0 && e[1].as_f64().unwrap() > 0.0,
            "{p}"
        );
    }
    let (code, text, err) = harmonav(&["census", &file]);
    assert_eq!(code, 0, "{err}");
    assert!(
        text.starts_with("1 minimum, 2 saddles, 0 degenerate (M = 2"),
        "{text}"
    );
}
