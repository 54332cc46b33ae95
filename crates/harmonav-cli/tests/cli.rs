//! The `harmonav` binary: exit codes, JSON shapes, negative coordinates.

use std::path::PathBuf;
use std::process::Command;

fn harmonav(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_harmonav"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn scenario(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

#[test]
fn run_json_has_the_documented_keys_and_exit_code_zero() {
    let (code, out, err) = harmonav(&[
        "run",
        &scenario("shapes/mixed.toml"),
        "--controller",
        "kinematic",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in [
        "reached",
        "time_s",
        "final_distance",
        "min_clearance",
        "max_speed",
        "speed_bound",
        "collisions",
        "physics_contacts",
        "discoveries",
        "guarantees",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["speed_bound"], serde_json::Value::Null);
    assert_eq!(v["physics_contacts"], serde_json::Value::Null);
    assert!(
        v["discoveries"][0]["obstacle"].is_string() && v["discoveries"][0]["time_s"].is_number()
    );
}

#[test]
fn eval_accepts_negative_coordinates_and_reports_points_outside() {
    let (code, out, err) = harmonav(&[
        "eval",
        &scenario("shapes/mixed.toml"),
        "--at",
        "-1.5,-0.2",
        "--at=-2,1.2",
        "--at",
        "9,9",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v[0]["x"], -1.5);
    assert!(
        v[0]["value"].as_f64().unwrap() > 0.0 && v[0]["grad"].is_array() && v[0]["h"].is_array()
    );
    assert_eq!(v[1]["error"], "inside obstacle disc");
    assert!(v[2]["error"].as_str().unwrap().contains("outside"));
    let (code, _, err) = harmonav(&["eval", &scenario("shapes/mixed.toml"), "--at", "1;2"]);
    assert_eq!(code, 2);
    assert!(err.contains("--at 1;2"), "{err}");
}

#[test]
fn census_counts_one_minimum_and_m_saddles() {
    let (code, out, _) = harmonav(&["census", &scenario("shapes/mixed.toml"), "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["minima"], 1);
    assert_eq!(
        v["saddles"].as_u64().unwrap() + v["degenerate"].as_u64().unwrap(),
        4
    );
    for p in v["points"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["kind"] == "saddle")
    {
        let e = p["eigenvalues"].as_array().unwrap();
        assert!(e[0].as_f64().unwrap() < 0.0 && e[1].as_f64().unwrap() > 0.0);
    }
}

/// `--k` overrides the file's policy on run, eval, census and sweep; a bad name exits 2.
#[test]
fn the_k_option_sets_the_policy() {
    let file = scenario("shapes/mixed.toml");
    for (policy, k) in [("paper", 5.0), ("auto", 30.0)] {
        let (code, out, err) = harmonav(&["census", &file, "--k", policy, "--json"]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(
            (v["k"].as_f64(), v["k_policy"].as_str()),
            (Some(k), Some(policy))
        );
    }
    let value = |policy: &str| {
        let (code, out, err) =
            harmonav(&["eval", &file, "--at", "-1.5,-0.2", "--k", policy, "--json"]);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()[0]["value"]
            .as_f64()
            .unwrap()
    };
    assert_ne!(value("paper"), value("auto"));
    for command in ["run", "sweep"] {
        let mut args = vec![command, &file, "--k", "paper"];
        if command == "sweep" {
            args.extend(["--starts", "2"]);
        }
        let (code, _, err) = harmonav(&args);
        assert_eq!(code, 0, "{command}: {err}");
    }
    let (code, _, err) = harmonav(&["census", &file, "--k", "n+1"]);
    assert_eq!(code, 2);
    assert!(err.contains("paper") && err.contains("auto"), "{err}");
}

/// `--damping` overrides `[controller] damping`: the summary names the policy, the two runs
/// differ, and an unknown name exits 2 naming the choices.
#[test]
fn the_damping_option_sets_the_policy() {
    let file = scenario("shapes/dynamic-small.toml");
    let run = |policy: &str| {
        let (code, out, err) = harmonav(&["run", &file, "--damping", policy, "--json"]);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let (paper, auto) = (run("paper"), run("auto"));
    assert_eq!(paper["damping"].as_str(), Some("paper"));
    assert_eq!(auto["damping"].as_str(), Some("auto"));
    assert_ne!(paper["time_s"], auto["time_s"]);
    let (code, _, err) = harmonav(&["run", &file, "--damping", "critical"]);
    assert_eq!(code, 2);
    assert!(err.contains("paper") && err.contains("auto"), "{err}");
}

#[test]
fn sweep_and_check_and_bad_input() {
    let (code, out, err) = harmonav(&[
        "sweep",
        &scenario("shapes/mixed.toml"),
        "--starts",
        "20",
        "--seed",
        "3",
        "--controller",
        "kinematic",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["starts"], 20);
    assert_eq!(v["reached"], 20);
    assert_eq!(v["collisions"], 0);
    let (code, out, _) = harmonav(&["check", &scenario("shapes/mixed.toml")]);
    assert_eq!((code, out.trim()), (0, "ok"));
    let bad = std::env::temp_dir().join(format!("harmonav-bad-{}.toml", std::process::id()));
    std::fs::write(&bad, "name = \"x\"\n[workspace]\ntype = \"circle\"\ncenter = [0.0, 0.0]\nradius = -1.0\n[robot]\nmodel = \"kinematic\"\nstart = [0.0, 0.0]\ngoal = [1.0, 0.0]\n").unwrap();
    let (code, _, err) = harmonav(&["check", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("workspace.radius") && err.contains("must be positive"),
        "{err}"
    );
    let (code, _, _) = harmonav(&["run", "/no/such/file.toml"]);
    assert_eq!(code, 2);
    std::fs::remove_file(bad).unwrap();
}

#[test]
fn a_failed_guarantee_exits_with_one() {
    // Too little time to arrive: the run completes, the arrival guarantee fails.
    let src = std::fs::read_to_string(scenario("shapes/mixed.toml"))
        .unwrap()
        .replace("max_time = 200.0", "max_time = 1.0");
    let file = std::env::temp_dir().join(format!("harmonav-short-{}.toml", std::process::id()));
    std::fs::write(&file, src).unwrap();
    let (code, out, _) = harmonav(&["run", file.to_str().unwrap(), "--controller", "kinematic"]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("FAIL"));
    std::fs::remove_file(file).unwrap();
}
