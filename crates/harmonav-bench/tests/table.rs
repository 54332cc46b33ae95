//! The one tabulation of studies (`harmonav_bench::table`) against hand-computed cells:
//! grouping, order, nearest-rank quantiles, the time ratio's pairing by world and start, and
//! the table's optional columns.

use harmonav::SpeedPolicy;
use harmonav_bench::table::{
    CellKey, Record, cells, kinematic_twin, not_arrived_text, quantiles, table, time_ratio,
};

fn run(world: &str, law: &str, sensing: &str, time: f64, reached: bool) -> Record {
    Record {
        world: world.to_string(),
        generated: true,
        obstacles: Some(6),
        law: Some(law.to_string()),
        damping: Some("auto".to_string()),
        speed: Some("paper".to_string()),
        k: Some("auto".to_string()),
        sensing: Some(sensing.to_string()),
        margin: Some(0.0),
        physics: Some("builtin".to_string()),
        max_time: Some(120.0),
        start_index: None,
        error: None,
        reached,
        time_s: Some(time),
        path_over_shortest: Some(1.0 + time / 100.0),
        min_clearance: Some(time / 1000.0),
        collisions: Some(0),
        overshoot: Some(0.0),
        steps: Some(time as u64 * 10),
        guarantees_held: true,
        command_us: None,
        outcome: Some(if reached { "reached" } else { "timed-out" }.to_string()),
        conservatism: None,
    }
}

#[test]
fn quantiles_are_nearest_rank() {
    let v: Vec<f64> = (1..=10).map(f64::from).collect();
    assert_eq!(quantiles(&v), [5.0, 9.0, 10.0]);
    assert_eq!(quantiles(&[3.0]), [3.0; 3]);
    assert_eq!(quantiles(&[2.0, 1.0]), [1.0, 2.0, 2.0]);
    let v = [8.0, 1.0, 7.0, 2.0, 6.0, 3.0, 5.0, 4.0];
    assert_eq!(quantiles(&v), [4.0, 8.0, 8.0]);
    assert!(quantiles(&[]).iter().all(|x| x.is_nan()));
}

#[test]
fn cells_group_the_worlds_in_the_order_the_records_give() {
    // Records in a study's run order (world-major) give the cells in plan order.
    let mut records = Vec::new();
    for w in ["w1", "w2", "w3"] {
        records.push(run(w, "kinematic", "sector", 10.0, true));
        records.push(run(w, "kinematic", "global", 8.0, true));
        records.push(run(w, "dynamic", "sector", 15.0, w != "w2"));
    }
    let c = cells(&records);
    let order: Vec<(&str, &str)> = c
        .iter()
        .map(|c| {
            (
                c.key.law.as_deref().unwrap(),
                c.key.sensing.as_deref().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        order,
        [
            ("kinematic", "sector"),
            ("kinematic", "global"),
            ("dynamic", "sector")
        ]
    );
    assert!(c.iter().all(|c| c.runs == 3 && c.key.world.is_none()));
    let dynamic = &c[2];
    assert_eq!(dynamic.reached, 2);
    assert_eq!(dynamic.arrived_times, [15.0, 15.0]);
    assert_eq!(dynamic.steps, [150.0; 3]);
    // One dynamic run did not arrive: its ratio is +∞, so p90 and max are +∞.
    let twin = kinematic_twin(&c, &dynamic.key, SpeedPolicy::Paper).unwrap();
    assert_eq!(twin.key.sensing.as_deref(), Some("sector"));
    assert_eq!(
        time_ratio(dynamic, twin),
        [1.5, f64::INFINITY, f64::INFINITY]
    );
}

#[test]
fn the_time_ratio_pairs_runs_by_world_and_start_and_leaves_out_the_references_failures() {
    let mut records = vec![
        run("a", "kinematic", "global", 10.0, true),
        run("b", "kinematic", "global", 20.0, false),
        run("c", "kinematic", "global", 5.0, true),
    ];
    // The dynamic runs come in another order: pairing must be by world, not position.
    records.push(run("c", "dynamic", "global", 20.0, true));
    records.push(run("a", "dynamic", "global", 12.0, true));
    records.push(run("b", "dynamic", "global", 30.0, true));
    let c = cells(&records);
    // a: 1.2, c: 4.0; b is left out (the reference did not arrive).
    assert_eq!(time_ratio(&c[1], &c[0]), [1.2, 4.0, 4.0]);
    // Starts are told apart.
    let mut twice = vec![
        run("a", "kinematic", "global", 10.0, true),
        run("a", "kinematic", "global", 40.0, true),
        run("a", "dynamic", "global", 20.0, true),
        run("a", "dynamic", "global", 40.0, true),
    ];
    for (i, r) in twice.iter_mut().enumerate() {
        r.start_index = Some(i as i64 % 2);
    }
    let c = cells(&twice);
    assert_eq!(time_ratio(&c[1], &c[0]), [1.0, 2.0, 2.0]);
}

#[test]
fn the_table_prints_each_cell_and_the_columns_that_vary() {
    let records = vec![
        run("a", "kinematic", "global", 10.0, true),
        run("a", "dynamic", "global", 13.0, true),
    ];
    let text = table(&cells(&records));
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 4);
    assert!(lines[0].starts_with("| law | damping or speed |"));
    assert_eq!(lines[1].matches("---|").count(), 15);
    assert_eq!(
        lines[2],
        "| Kinematic | paper | auto | global | 0 | 6 | 1/1 | 1/1 | 0 | 1.100 / 1.100 / 1.100 \
         | 10.0 / 10.0 / 10.0 | — | 0.0100 | 0.0e0 | 100 / 100 / 100 |"
    );
    assert!(lines[3].contains("| 1.30 / 1.30 / 1.30 |"), "{}", lines[3]);

    // A NaN measure is a missing one: a run without a shortest path or a clearance (a
    // descent) leaves the others' quantiles as they are, and no clearance at all prints `—`.
    let mut no_shortest = records[0].clone();
    no_shortest.path_over_shortest = Some(f64::NAN);
    no_shortest.min_clearance = Some(f64::NAN);
    no_shortest.world = "b".to_string();
    let c = cells(&[records[0].clone(), no_shortest.clone()]);
    assert_eq!(c[0].ratio, [1.1; 3]);
    assert_eq!(c[0].min_clearance, 0.01);
    let text = table(&cells(&[no_shortest]));
    assert!(
        text.lines()
            .nth(2)
            .unwrap()
            .contains("| NaN / NaN / NaN | 10.0 / 10.0 / 10.0 | — | — |"),
        "{text}"
    );

    // A scenario file, a second physics and a failed run add their columns.
    let mut file = run("scenarios/x.toml", "kinematic", "global", 10.0, true);
    file.generated = false;
    file.physics = Some("rapier".to_string());
    let failed = Record {
        error: Some("bad".to_string()),
        reached: false,
        time_s: None,
        steps: None,
        outcome: None,
        ..run("a", "kinematic", "global", 0.0, false)
    };
    let measured = Record {
        command_us: Some(2.5),
        ..records[0].clone()
    };
    let text = table(&cells(&[measured, file, failed]));
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].starts_with("| world | law |"));
    assert!(lines[0].ends_with("| physics | µs per command median / p90 / max | errors |"));
    assert_eq!(lines[1].matches("---|").count(), 19);
    assert!(lines[2].starts_with("| — | Kinematic |"));
    assert!(
        lines[2].ends_with("| builtin | 2.5 / 2.5 / 2.5 | 1 |"),
        "{}",
        lines[2]
    );
    assert!(lines[3].starts_with("| scenarios/x.toml | Kinematic |"));
    assert!(
        lines[3].ends_with("| rapier | NaN / NaN / NaN | 0 |"),
        "{}",
        lines[3]
    );
}

#[test]
fn the_outcomes_of_runs_that_did_not_arrive_and_the_perceived_area_get_their_columns() {
    // Lidar runs: two refused scans and a stall among five runs; one run recorded no
    // perception, one a NaN (both left out of the quantiles).
    let outcomes = [
        ("reached", true, Some(2.0)),
        ("scan-refused", false, Some(4.0)),
        ("stalled", false, Some(3.0)),
        ("scan-refused", false, None),
        ("reached", true, Some(f64::NAN)),
    ];
    let records: Vec<Record> = outcomes
        .iter()
        .enumerate()
        .map(|(i, &(outcome, reached, area))| Record {
            outcome: Some(outcome.to_string()),
            conservatism: area,
            sensing: Some("lidar".to_string()),
            ..run(&format!("w{i}"), "kinematic", "lidar", 10.0, reached)
        })
        .collect();
    let c = cells(&records);
    assert_eq!(c.len(), 1);
    assert_eq!(c[0].reached, 2);
    assert_eq!(
        c[0].not_arrived.iter().collect::<Vec<_>>(),
        [
            (&"scan-refused".to_string(), &2),
            (&"stalled".to_string(), &1)
        ]
    );
    assert_eq!(c[0].conservatism, [3.0, 4.0, 4.0]);
    assert_eq!(not_arrived_text(&c[0]), "scan-refused 2, stalled 1");
    let text = table(&c);
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].ends_with("| not arrived | perceived/true area median / p90 / max |"),
        "{}",
        lines[0]
    );
    assert_eq!(lines[1].matches("---|").count(), 17);
    assert!(
        lines[2].ends_with("| scan-refused 2, stalled 1 | 3.00 / 4.00 / 4.00 |"),
        "{}",
        lines[2]
    );

    // A run that claims `reached` but did not arrive is told apart; a cell whose runs all
    // arrived prints `—`; without perception there is no area column.
    let mut odd = run("a", "dynamic", "global", 10.0, false);
    odd.outcome = Some("reached".to_string());
    let fine = run("a", "kinematic", "global", 10.0, true);
    let c = cells(&[fine, odd]);
    assert_eq!(not_arrived_text(&c[0]), "—");
    assert_eq!(not_arrived_text(&c[1]), "not-reached 1");
    let text = table(&c);
    assert!(
        text.lines().next().unwrap().ends_with("| not arrived |"),
        "{text}"
    );
}

#[test]
fn the_figure_key_names_the_law_policy_and_cell() {
    let mut r = run("a", "dynamic", "sector", 1.0, true);
    // "auto" is a named policy since "governed" became the default damping (2026-12-03).
    assert_eq!(
        CellKey::of(&r).figure_key(),
        "dynamic-damping-auto.auto.sector.m6"
    );
    r.damping = Some("governed".to_string());
    assert_eq!(CellKey::of(&r).figure_key(), "dynamic.auto.sector.m6");
    r.damping = Some("paper".to_string());
    r.margin = Some(0.1);
    assert_eq!(
        CellKey::of(&r).figure_key(),
        "dynamic-damping-paper.auto.sector.m6.margin0.1"
    );
    let k = run("a", "kinematic", "global", 1.0, true);
    assert_eq!(
        CellKey::of(&k).figure_key(),
        "kinematic-speed-paper.auto.global.m6"
    );
}
