//! The `harmonav` binary: exit codes, JSON shapes, negative coordinates.

use std::path::PathBuf;
use std::process::Command;

mod common;

use common::{harmonav, scenario, scratch};

#[test]
fn run_json_has_the_documented_keys_and_exit_code_zero() {
    let (code, out, err) = harmonav(&[
        "run",
        &scenario("shapes/mixed.toml"),
        "--model",
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
        "--at",
        "4,0",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v[0]["x"], -1.5);
    // At the goal phi is −∞, which JSON has no number for: null, and a note says why (D21).
    assert!(v[3]["phi"].is_null() && v[3]["note"].as_str().unwrap().contains("goal"));
    assert!(v[0].get("note").is_none());
    // A far point's coordinates are not printed with 309 digits (D18).
    let (_, text, _) = harmonav(&[
        "eval",
        &scenario("shapes/mixed.toml"),
        "--at",
        "1e308,1e308",
    ]);
    assert!(text.contains("1.0000e308") && text.len() < 400, "{text}");
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

/// The CLI's cases of the hostile round (issue 16; the file cases are `scenarios/adversarial/`,
/// run by `cargo xtask verify`): each ends at once with exit 2 and names the problem.
#[test]
fn hostile_arguments_end_with_exit_two_and_say_why() {
    let file = scenario("shapes/mixed.toml");
    // A start count that overflowed an allocation ("capacity overflow", exit 101).
    let (code, _, err) = harmonav(&["sweep", &file, "--starts", "18446744073709551615"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("at most 1000000"), "{err}");
    // A device that never ends.
    let (code, _, err) = harmonav(&["check", "/dev/zero"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("/dev/zero"), "{err}");
    // Standard input.
    let (code, _, err) = harmonav(&["check", "-"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("standard input is not supported"), "{err}");
    // `--out` naming a file: refused before the run, and the file is left as it was.
    let out = std::env::temp_dir().join(format!("harmonav-out-file-{}", std::process::id()));
    std::fs::write(&out, "keep").unwrap();
    let (code, _, err) = harmonav(&["run", &file, "--out", out.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("not a directory") || err.contains("--out"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep");
    std::fs::remove_file(out).unwrap();
}

/// The first world a user writes, one disc between start and goal: the run says where and why
/// it stopped, and warns before.
#[test]
fn a_start_on_a_symmetry_axis_is_explained() {
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/adversarial/one-disc-on-the-axis.toml");
    let (code, out, _) = harmonav(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("outcome: stalled at a saddle of Θ at (-1.17"),
        "{out}"
    );
    assert!(
        out.contains("warning: the descent from the start ends at a saddle"),
        "{out}"
    );
    let (_, out, _) = harmonav(&["run", file.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["outcome"]["kind"], "stalled");
    assert_eq!(v["outcome"]["point"], "saddle");
    assert_eq!(v["warnings"][0]["kind"], "start-on-saddle-manifold");
    let x = v["warnings"][0]["saddle"][0].as_f64().unwrap();
    assert!((x - v["outcome"]["position"][0].as_f64().unwrap()).abs() < 1e-3);
}

/// An interrupt at any moment of `run --out` leaves the previous complete set or the new
/// complete one, and no staging folder: a kinematic set (no speed.svg) is overwritten by a
/// dynamic run (speed.svg, energy.svg) that SIGINT stops after a growing delay. The paper's
/// dynamic study runs in about 20 ms and writes its outputs in about 90 ms here, so most
/// delays land while the set is written; the last lets it complete. (With the handler's
/// clean-up removed, the interrupt after 35 ms left `.<pid>.0.staging`.)
#[test]
fn an_interrupted_run_leaves_one_complete_output_set() {
    let dir = std::env::temp_dir().join(format!("harmonav-interrupt-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.to_str().unwrap();
    let kinematic = scenario("shapes/mixed.toml");
    let (code, _, err) = harmonav(&["run", &kinematic, "--controller", "kinematic", "--out", out]);
    assert_eq!(code, 0, "{err}");
    let (mut interrupted, mut completed) = (0, 0);
    for delay_ms in (0..24).map(|i| 10 + 5 * i).chain([3000u64]) {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_harmonav"))
            .args(["run", &scenario("paper/dynamic.toml"), "--out", out])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let _ = std::process::Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status();
        let status = child.wait().unwrap();
        match status.code() {
            Some(130) => interrupted += 1,
            Some(0 | 1) => completed += 1,
            other => panic!("after {delay_ms} ms: exit {other:?}"),
        }
        let names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(
            names.iter().all(|n| !n.starts_with('.')),
            "after {delay_ms} ms: {names:?}"
        );
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        let dynamic = summary["model"] == "dynamic";
        let has = |n: &str| names.iter().any(|x| x == n);
        assert!(has("run.mcap") && has("trajectory.svg"), "{names:?}");
        assert_eq!(
            (has("speed.svg"), has("energy.svg")),
            (dynamic, dynamic),
            "after {delay_ms} ms: a mixed set {names:?}"
        );
    }
    assert!(
        interrupted > 0 && completed > 0,
        "{interrupted} interrupted, {completed} completed"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every entry below `d` with its content (files) or `None` (folders, links), sorted.
fn tree(d: &std::path::Path) -> Vec<(PathBuf, Option<Vec<u8>>)> {
    let mut out = Vec::new();
    let mut todo = vec![d.to_path_buf()];
    while let Some(at) = todo.pop() {
        for e in std::fs::read_dir(&at).unwrap() {
            let e = e.unwrap();
            let kind = e.file_type().unwrap();
            if kind.is_dir() {
                todo.push(e.path());
            }
            let content = kind.is_file().then(|| std::fs::read(e.path()).unwrap());
            out.push((e.path(), content));
        }
    }
    out.sort();
    out
}

/// Every `--out` problem is found before the run: exit 2, a message naming the path and the
/// problem, no summary (the run did not happen: a run's summary is always printed), and
/// nothing changed. Before, only a file named as `--out` was found up front; a path below a
/// file, a dangling or looping link, an unwritable folder and a path longer than PATH_MAX
/// failed after the whole run with the system's bare message, and a folder named
/// `summary.json` left a mixed set.
#[test]
fn out_problems_are_found_before_the_run_and_change_nothing() {
    use std::os::unix::fs::symlink;
    let file = scenario("shapes/mixed.toml");
    let d = scratch("out-problems");
    std::fs::write(d.join("a-file"), "keep").unwrap();
    symlink(d.join("nowhere"), d.join("dangling")).unwrap();
    symlink(d.join("loop"), d.join("loop")).unwrap();
    // A complete previous set, and a folder where its summary.json should go.
    let taken = d.join("taken");
    let (code, _, err) = harmonav(&["run", &file, "--out", taken.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    std::fs::remove_file(taken.join("summary.json")).unwrap();
    std::fs::create_dir(taken.join("summary.json")).unwrap();
    // Root writes into a read-only folder; /sys refuses new entries to everyone.
    let unwritable = {
        use std::os::unix::fs::PermissionsExt;
        let ro = d.join("read-only");
        std::fs::create_dir(&ro).unwrap();
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
        if std::fs::create_dir(ro.join("x")).is_ok() {
            std::fs::remove_dir(ro.join("x")).unwrap();
            PathBuf::from("/sys")
        } else {
            ro
        }
    };
    let long: PathBuf = std::iter::once(d.clone())
        .chain((0..20).map(|i| PathBuf::from(format!("{i:0>200}"))))
        .collect();
    let before = tree(&d);
    let cases: [(PathBuf, &[&str]); 6] = [
        (d.join("a-file/out"), &["a-file is a file"]),
        (
            d.join("dangling"),
            &["is a symbolic link to", "does not exist"],
        ),
        (d.join("loop/out"), &["is a symbolic link that loops"]),
        (unwritable.join("out"), &["cannot create anything in"]),
        (long, &["PATH_MAX"]),
        (taken.clone(), &["summary.json: is a directory"]),
    ];
    for (out, words) in cases {
        let shown = out.display().to_string();
        let (code, stdout, err) = harmonav(&["run", &file, "--out", &shown, "--json"]);
        assert_eq!(code, 2, "{shown}: {err}");
        assert_eq!(stdout, "", "{shown}: no run, so no summary");
        for w in words.iter().chain(&["--out", "nothing was run"]) {
            assert!(err.contains(w), "{shown}: {w:?} not in {err}");
        }
    }
    assert_eq!(tree(&d), before, "a refused --out changes nothing");
    let _ = std::fs::remove_dir_all(&d);
}

/// Writing the outputs can still fail after the run (here the file-size limit of the process
/// stops run.mcap): the summary is printed all the same, the error follows on stderr with
/// exit 2, and the previous set is left whole. Before, the summary was lost.
#[test]
fn the_summary_is_printed_when_writing_the_outputs_fails() {
    let file = scenario("shapes/mixed.toml");
    let d = scratch("write-fails");
    let out = d.join("out");
    let out = out.to_str().unwrap();
    let (code, _, err) = harmonav(&["run", &file, "--out", out]);
    assert_eq!(code, 0, "{err}");
    let before = tree(&d);
    // SIGXFSZ ignored, so that the write fails with EFBIG instead of killing the process.
    let limited = |extra: &[&str]| {
        let o = Command::new("sh")
            .arg("-c")
            .arg("trap '' XFSZ; ulimit -f 1; exec \"$0\" \"$@\"")
            .arg(env!("CARGO_BIN_EXE_harmonav"))
            .args(["run", &file, "--out", out])
            .args(extra)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (code, stdout, err) = limited(&[]);
    assert_eq!(code, Some(2), "{stdout}{err}");
    assert!(
        stdout.starts_with("shapes-mixed (Kinematic model, builtin physics): goal reached"),
        "{stdout}"
    );
    assert!(!stdout.contains("outputs in"), "{stdout}");
    assert!(
        err.contains("the outputs were not written") && err.contains("run.mcap"),
        "{err}"
    );
    let (code, stdout, err) = limited(&["--json"]);
    assert_eq!(code, Some(2), "{err}");
    let summary: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(summary["reached"], true);
    assert_eq!(
        tree(&d),
        before,
        "the previous set is whole, no staging folder"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Names reach the terminal escaped: a scenario name and an obstacle name holding ESC
/// sequences (retitle, clear, colour) and a BEL, and a file name with one, print as `\u{1b}`
/// text in the text output and on stderr; the JSON output keeps the names exact (serde
/// escapes them). Before, they were written raw.
#[test]
fn control_characters_in_names_are_escaped_in_text_and_kept_in_json() {
    let d = scratch("escape");
    let src = std::fs::read_to_string(scenario("shapes/mixed.toml")).unwrap();
    let name = "evil\u{1b}]0;pwned\u{7}\u{1b}[2J";
    let src = src.replacen(
        "name = \"shapes-mixed\"",
        "name = \"evil\\u001b]0;pwned\\u0007\\u001b[2J\"",
        1,
    );
    assert!(src.contains("u001b"), "the scenario's name line moved");
    let src = src.replacen("name = \"disc\"", "name = \"disc\\u001b[31m\"", 1);
    let path = d.join("evil.toml");
    std::fs::write(&path, src).unwrap();
    let raw = |s: &str| s.contains('\u{1b}') || s.contains('\u{7}');
    let (code, out, err) = harmonav(&["run", path.to_str().unwrap(), "--controller", "kinematic"]);
    assert_eq!(code, 0, "{err}");
    assert!(!raw(&out), "{out:?}");
    assert!(
        out.starts_with("evil\\u{1b}]0;pwned\\u{7}\\u{1b}[2J ("),
        "{out}"
    );
    let (_, out, _) = harmonav(&["eval", path.to_str().unwrap(), "--at", "-2,1.2"]);
    assert!(!raw(&out) && out.contains("disc\\u{1b}[31m"), "{out:?}");
    let (code, out, _) = harmonav(&["run", path.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["name"], name);
    let (code, _, err) = harmonav(&["check", d.join("no\u{1b}[2Jsuch.toml").to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        !raw(&err) && err.contains("no\\u{1b}[2Jsuch.toml"),
        "{err:?}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// `--starts 0` is refused by the check the Python `sweep` shares; the report counts invalid
/// starts.
#[test]
fn a_sweep_of_no_starts_is_refused_and_invalid_starts_are_counted() {
    let file = scenario("shapes/mixed.toml");
    let (code, _, err) = harmonav(&["sweep", &file, "--starts", "0"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--starts") && err.contains("at least 1"),
        "{err}"
    );
    let (code, out, err) = harmonav(&["sweep", &file, "--starts", "2", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["invalid_starts"], 0);
}
