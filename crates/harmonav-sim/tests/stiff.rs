//! Issue 51, "a valid run that cannot be judged": a world of 1 000 discs, all known from the start
//! (`k` = 6 006), where the dynamic law's exact solution turns round about 1e-19 m from a grown
//! disc, below the spacing of `f64` positions. The built-in integrator's steps collapsed there
//! (t = 6.01 s, 85.6 m from the goal) until it crossed such barrier layers in the stretched time
//! (`run.rs`, `barrier_layer`). The world is `scenarios/long/discs-1000-global.toml`.

use std::path::PathBuf;

use harmonav_scenario::Scenario;

fn world() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/long/discs-1000-global.toml")
}

#[test]
fn the_dynamic_law_crosses_barrier_layers_below_f64_resolution_and_arrives() {
    let prepared = Scenario::load(&world()).expect("the scenario loads");
    let run = harmonav_sim::run::run(&prepared, None).expect("the run starts");
    let s = &run.summary;
    let failed: Vec<String> = s
        .guarantees
        .iter()
        .filter(|g| !g.passed)
        .map(|g| g.check.to_string())
        .collect();
    assert!(
        s.reached && s.all_passed(),
        "reached {} at t = {:.3} s, {:.2} m from the goal; failed: {failed:?}",
        s.reached,
        s.time_s,
        s.final_distance
    );
    // The layers are crossed at the margin: as close to the grown discs as the law goes.
    assert!(s.min_clearance >= 0.05 - harmonav_sim::MARGIN_TOLERANCE);
}
