//! `harmonav check FILE --json` (issue 52, the interface outside checks read): one JSON object
//! on stdout with the map's size, set-up time, `c_δ`, each start's certificate and the
//! certified fraction of the reachable free area; for a star world the theorem's; nothing on
//! stdout for a bad file.

mod common;

use common::{harmonav, scenario, scratch};
use serde_json::Value;

/// `check FILE --json`, which must succeed and print exactly one JSON object.
fn check_json(file: &str) -> Value {
    let (code, out, err) = harmonav(&["check", file, "--json"]);
    assert_eq!(code, 0, "{err}\n{out}");
    let v: Value = serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"));
    assert!(v.is_object(), "{v}");
    v
}

fn f(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number: {v}"))
}

/// Each start's `[x, y]` and `certified`.
fn starts(v: &Value) -> Vec<([f64; 2], bool)> {
    v["starts"]
        .as_array()
        .unwrap_or_else(|| panic!("no starts: {v}"))
        .iter()
        .map(|s| {
            let p = s["position"].as_array().unwrap();
            (
                [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()],
                s["certified"].as_bool().unwrap(),
            )
        })
        .collect()
}

#[test]
fn a_floor_plan_gives_one_object_whose_starts_agree_with_the_text_check() {
    let file = scenario("floorplans/u-trap.toml");
    let v = check_json(&file);
    assert_eq!(v["kind"], "floor_plan");
    assert_eq!(v["basis"], "grid");
    assert!(v["elements"].as_u64().unwrap() > 100, "{v}");
    assert_eq!(v["holes"], 1);
    assert_eq!(f(&v, "delta"), 0.05);
    assert!(f(&v, "setup_s") > 0.0);
    let (level, fraction) = (f(&v, "level"), f(&v, "certified_fraction"));
    assert!(level > 0.0 && level < 1.0, "{v}");
    // c_s (§13.9): a rest point of the slide may lie in the U's pocket, at or above c_δ.
    let slide = f(&v, "slide_level");
    assert!(
        slide >= level && slide < 1.0 && v["slide_rest_at"].is_array(),
        "{v}"
    );
    assert!((0.0..=1.0).contains(&fraction), "{v}");
    assert_eq!(f(&v, "certified_grid_m"), 0.05);
    assert!(v["reachable_samples"].as_u64().unwrap() > 1000, "{v}");
    // The parts of the reachable area: certified, in the layer, above c_δ.
    let parts = fraction + f(&v, "uncertified_layer") + f(&v, "uncertified_above_level");
    assert!((parts - 1.0).abs() < 1e-12, "{parts}: {v}");
    // robot.start, then the file's six seeded starts, each as the text check finds it.
    let s = starts(&v);
    assert_eq!(s.len(), 7, "{v}");
    assert_eq!(s[0], ([1.0, 2.1], false));
    let (code, text, err) = harmonav(&["check", &file]);
    assert_eq!(code, 0, "{err}");
    for (p, certified) in &s {
        let line = format!(
            "  start ({:.3}, {:.3}): {}",
            p[0],
            p[1],
            if *certified {
                "certified"
            } else {
                "not certified"
            }
        );
        assert!(text.contains(&line), "{line} not in\n{text}");
    }
    assert!(
        text.contains(&format!(
            "{} of 7 starts certified",
            s.iter().filter(|(_, c)| *c).count()
        )),
        "{text}"
    );
    // The text output is as it was: no JSON in it.
    assert!(
        text.starts_with("ok: floor plan, ") && !text.contains('{'),
        "{text}"
    );
}

/// In a long corridor with the goal at one end, `c_δ` certifies little, and `Θ` from `eval`
/// (another path: the navigator's field) agrees about a start far down the corridor (above
/// `c_δ`) and a point beside the goal (below it); but the slide along `∂W_δ` has no rest point
/// (`c_s` = 1, docs/maths.md §13.9), so every start is certified. The negative control: a bar
/// with the goal just behind it, whose slide has attracting rest points below the bar, is
/// not all certified, and `c_s` names a place by the bar.
#[test]
fn a_long_corridor_is_certified_by_its_slide_and_a_bar_with_the_goal_behind_it_is_not() {
    let dir = scratch("check-corridor");
    let file = dir.join("corridor.toml");
    std::fs::write(
        &file,
        r#"name = "corridor"
[floor_plan]
outer = [[0.0, 0.0], [16.0, 0.0], [16.0, 1.0], [0.0, 1.0]]
max_element = 0.1
[robot]
model = "kinematic"
start = [15.0, 0.5]
goal = [1.0, 0.5]
radius = 0.15
margin = 0.05
[starts]
count = 4
seed = 3
[sim]
max_time = 100.0
"#,
    )
    .unwrap();
    let file = file.to_str().unwrap();
    let v = check_json(file);
    assert_eq!(f(&v, "certified_fraction"), 1.0, "{v}");
    assert_eq!(f(&v, "slide_level"), 1.0, "{v}");
    assert!(v["slide_rest_at"].is_null(), "{v}");
    let s = starts(&v);
    assert_eq!(s.len(), 5, "{v}");
    assert!(s.iter().all(|(_, c)| *c), "{v}");
    let (code, out, err) = harmonav(&["eval", file, "--at", "15,0.5", "--at", "1.1,0.5", "--json"]);
    assert_eq!(code, 0, "{err}");
    let rows: Value = serde_json::from_str(&out).unwrap();
    let level = f(&v, "level");
    assert!(
        f(&rows[0], "value") >= level,
        "{rows} against c_δ = {level}"
    );
    assert!(f(&rows[1], "value") < level, "{rows} against c_δ = {level}");

    let bar = dir.join("bar.toml");
    std::fs::write(
        &bar,
        r#"name = "bar"
[floor_plan]
outer = [[0.0, 0.0], [6.0, 0.0], [6.0, 4.0], [0.0, 4.0]]
holes = [[[1.0, 1.8], [5.0, 1.8], [5.0, 2.2], [1.0, 2.2]]]
max_element = 0.1
[robot]
model = "kinematic"
start = [3.0, 0.8]
goal = [3.0, 2.6]
radius = 0.15
margin = 0.05
[sim]
max_time = 100.0
"#,
    )
    .unwrap();
    let v = check_json(bar.to_str().unwrap());
    let fraction = f(&v, "certified_fraction");
    assert!(fraction < 1.0, "{v}");
    let slide = f(&v, "slide_level");
    assert!(slide < 1.0 && slide >= f(&v, "level"), "{v}");
    let at = v["slide_rest_at"].as_array().unwrap();
    let (x, y) = (at[0].as_f64().unwrap(), at[1].as_f64().unwrap());
    // Measured: (4.87, 2.40), by the bar's end on the goal's side (the covering's least
    // bound; the attracting rest points below the bar lie higher in Θ).
    assert!((0.8..5.2).contains(&x) && (1.4..2.6).contains(&y), "{v}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_star_world_gives_the_theorems_fraction() {
    let v = check_json(&scenario("shapes/mixed.toml"));
    assert_eq!(v["kind"], "star_world");
    assert_eq!(v["elements"], 0);
    assert!(f(&v, "setup_s") >= 0.0);
    assert_eq!(f(&v, "certified_fraction"), 1.0);
    assert_eq!(v["basis"], "theorem");
    assert_eq!(starts(&v), vec![([-4.0, 0.1], true)]);
    // The text check is unchanged.
    let (code, out, _) = harmonav(&["check", &scenario("shapes/mixed.toml")]);
    assert_eq!((code, out.as_str()), (0, "ok\n"));
}

#[test]
fn a_bad_file_exits_with_two_and_prints_nothing_on_stdout() {
    let dir = scratch("check-bad");
    // A floor plan whose start lies in the U's wall, and a missing file.
    let bad = dir.join("bad.toml");
    let text = std::fs::read_to_string(scenario("floorplans/u-trap.toml"))
        .unwrap()
        .replace("start = [1.0, 2.1]", "start = [4.8, 2.5]");
    std::fs::write(&bad, text).unwrap();
    let missing = dir.join("missing.toml");
    for file in [&bad, &missing] {
        let (code, out, err) = harmonav(&["check", file.to_str().unwrap(), "--json"]);
        assert_eq!(code, 2, "{out}");
        assert!(out.is_empty(), "stdout: {out}");
        assert!(err.starts_with("harmonav: "), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A file whose navigator follows a chain of funnels (`floor_plan.funnels`, docs/maths.md
/// §13.10): `certified_fraction` and the starts are the chain's (`"basis": "funnels"`), and
/// `funnels` describes it; `--funnels` reports a chain for a file without the key, leaving
/// `certified_fraction` the goal's own; `--funnels` without `--json` is refused.
#[test]
fn a_chain_of_funnels_is_reported_and_counted_when_the_file_follows_it() {
    let dir = scratch("check-funnels");
    let room = "name = \"room\"\n[floor_plan]\nouter = [[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], \
                [0.0, 3.0]]\nmax_element = 0.1\nFUNNELS[robot]\nmodel = \"kinematic\"\n\
                start = [0.8, 0.8]\ngoal = [3.2, 2.2]\nradius = 0.1\nmargin = 0.05\n";
    let followed = dir.join("followed.toml");
    std::fs::write(&followed, room.replace("FUNNELS", "funnels = true\n")).unwrap();
    let v = check_json(followed.to_str().unwrap());
    assert_eq!(v["basis"], "funnels", "{v}");
    assert_eq!(v["funnels"]["followed"], true, "{v}");
    assert_eq!(v["funnels"]["count"], 1, "{v}");
    assert_eq!(
        f(&v, "certified_fraction"),
        f(&v["funnels"], "certified_fraction")
    );
    assert!(v["funnels"]["seconds"].is_null(), "{v}");
    assert!(starts(&v).iter().all(|(_, c)| *c), "{v}");
    let (code, out, err) = harmonav(&["check", followed.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("a chain of 1 funnel certifies"), "{out}");
    let plain = dir.join("plain.toml");
    std::fs::write(&plain, room.replace("FUNNELS", "")).unwrap();
    let file = plain.to_str().unwrap();
    let v = check_json(file);
    assert!(v.get("funnels").is_none(), "{v}");
    let (code, out, err) = harmonav(&["check", file, "--json", "--funnels"]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["basis"], "grid", "{v}");
    assert_eq!(v["funnels"]["followed"], false, "{v}");
    assert!(f(&v["funnels"], "seconds") >= 0.0, "{v}");
    let (code, out, err) = harmonav(&["check", file, "--funnels"]);
    assert_ne!(code, 0);
    assert!(out.is_empty() && err.contains("--json"), "{err}");
}
