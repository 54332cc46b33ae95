//! Files with `[[movers]]` (issue 54, item 4; docs/movers.md §8): the held-command loop with
//! the movers reported every period, its summary's counts, and the negative control (the
//! robot blind to the movers touches them).

use std::path::{Path, PathBuf};

use harmonav_scenario::{Model, Scenario};
use harmonav_sim::physics::{Physics, simulate};
use harmonav_sim::run::run_without_filter;

fn file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/movers")
        .join(name)
}

#[test]
fn the_suite_never_touches_a_mover_under_a_certified_command() {
    for name in [
        "person-crossing.toml",
        "pursuer-at-bound.toml",
        "five-walkers.toml",
    ] {
        let prepared = Scenario::load(&file(name)).unwrap();
        for model in [Model::Kinematic, Model::Dynamic] {
            let run = simulate(&prepared, Some(model), Physics::Builtin).unwrap();
            let s = &run.summary;
            let m = s.movers.as_ref().expect("a mover report");
            println!(
                "{name} {model:?}: reached {} in {:.2} s, {m:?}",
                s.reached, s.time_s
            );
            assert_eq!(m.contacts_after_certified, 0, "{name} {model:?}");
            assert!(s.all_passed(), "{name} {model:?}: {:?}", s.guarantees);
            assert_eq!(
                m.certified_commands + m.overwhelmed_commands + m.refused_commands,
                s.steps,
                "one command a period"
            );
            assert!(
                m.yielding_commands > 0,
                "{name} {model:?}: the filter acted"
            );
            if m.overwhelmed_commands == 0 {
                assert!(m.min_mover_clearance >= prepared.margin() - 1e-9);
            }
        }
    }
}

#[test]
fn blind_to_the_movers_the_robot_touches_one() {
    let prepared = Scenario::load(&file("person-crossing.toml")).unwrap();
    let run = run_without_filter(&prepared, None).unwrap();
    let m = run.summary.movers.as_ref().unwrap();
    assert!(
        m.mover_contacts > 0 && m.contacts_after_certified > 0,
        "{m:?}"
    );
    assert_eq!(m.yielding_commands, 0);
    let g = run
        .summary
        .guarantees
        .iter()
        .find(|g| g.name() == "no-collision-with-movers")
        .unwrap();
    assert!(!g.passed);
}

/// Since 2026-12-07 rapier flies a file with movers (one robot) and refuses one with robots
/// by name (it refused both before).
#[test]
fn rapier_flies_a_file_with_movers_and_refuses_one_with_robots() {
    let prepared = Scenario::load(&file("person-crossing.toml")).unwrap();
    let run = simulate(&prepared, None, Physics::Rapier).unwrap();
    let m = run.summary.movers.as_ref().unwrap();
    assert!(run.summary.all_passed(), "{:?}", run.summary.guarantees);
    assert_eq!(m.mover_contacts, 0);
    let robots = Scenario::load(&file("four-robots-swap.toml")).unwrap();
    let e = simulate(&robots, None, Physics::Rapier).unwrap_err();
    assert!(
        matches!(e, harmonav_sim::summary::RunError::RobotsInRapier),
        "{e}"
    );
}

#[test]
fn a_floor_plan_with_a_mover_yields_and_arrives() {
    use harmonav_scenario::floorplan::FloorScenario;
    use harmonav_sim::floor::FloorSummary;
    use harmonav_sim::physics::simulate_floor;
    let prepared = FloorScenario::load(&file("floor-corridor.toml")).unwrap();
    let start = nalgebra::Vector2::from(prepared.scenario.robot.start);
    for model in [Model::Kinematic, Model::Dynamic] {
        let run = simulate_floor(&prepared, Some(model), start, Physics::Builtin).unwrap();
        let s = FloorSummary::new(&prepared, Some(model), start, &run);
        let m = s.movers.as_ref().unwrap();
        assert!(s.all_passed(), "{model:?}: {:?}", s.guarantees);
        assert_eq!(
            m.certified_commands + m.overwhelmed_commands + m.refused_commands,
            s.commands
        );
        assert!(m.yielding_commands > 0 && m.mover_contacts == 0, "{m:?}");
    }
    // In rapier too (since 2026-12-07): the walls as colliders, the mover judged by the monitor.
    let run = simulate_floor(&prepared, None, start, Physics::Rapier).unwrap();
    let s = FloorSummary::new(&prepared, None, start, &run);
    assert!(s.all_passed(), "{:?}", s.guarantees);
    assert_eq!(s.movers.as_ref().unwrap().mover_contacts, 0);
}

/// A force-bounded robot in the corridor a person paces (`floor-corridor-force-bound.toml`,
/// 1 N at 50 Hz): it arrives with every guarantee under the built-in loop and in rapier, and
/// no contact follows a certified command (passive safety: where the person walks at it from
/// closer than it can brake the commands are `Overwhelmed`). Measured: built-in 1 contact
/// episode, 41 periods refused with the bodies overlapping; rapier none. Before KeepRight
/// turned a force-bounded robot's nominal and eq. backuppieces certified its moving off the
/// person's line (2026-12-07), the person walked into the standing robot: 2 contact episodes
/// and 114 periods refused.
#[test]
fn a_force_bounded_robot_steps_off_a_pacing_persons_line() {
    use harmonav_scenario::floorplan::FloorScenario;
    use harmonav_sim::floor::FloorSummary;
    use harmonav_sim::physics::simulate_floor;
    let prepared = FloorScenario::load(&file("floor-corridor-force-bound.toml")).unwrap();
    let start = nalgebra::Vector2::from(prepared.scenario.robot.start);
    for physics in [Physics::Builtin, Physics::Rapier] {
        let run = simulate_floor(&prepared, None, start, physics).unwrap();
        let s = FloorSummary::new(&prepared, None, start, &run);
        let m = s.movers.as_ref().unwrap();
        assert!(
            s.all_passed() && s.reached,
            "{physics:?}: {:?}",
            s.guarantees
        );
        assert_eq!(m.contacts_after_certified, 0, "{m:?}");
        assert!(m.refused_commands < 114 && m.mover_contacts < 2, "{m:?}");
        assert!(run.max_force <= 1.0, "{}", run.max_force);
    }
}

#[test]
fn four_robots_swap_places_without_touching() {
    let prepared = Scenario::load(&file("four-robots-swap.toml")).unwrap();
    for model in [Model::Kinematic, Model::Dynamic] {
        let run = simulate(&prepared, Some(model), Physics::Builtin).unwrap();
        let s = &run.summary;
        let f = s.fleet.as_ref().expect("a fleet report");
        assert_eq!(f.others.len(), 3);
        assert!(s.all_passed(), "{model:?}: {:?}", s.guarantees);
        assert!(f.others.iter().all(|o| o.reached && o.safe), "{f:?}");
        assert_eq!(f.robot_contacts, 0);
        // Each keeps its margin from the other's body (Theorem 1 with reciprocal rows).
        assert!(f.min_robot_clearance >= prepared.margin() - 1e-9, "{f:?}");
        assert!(s.movers.is_none(), "no scripted movers");
        assert!(
            s.guarantees
                .iter()
                .any(|g| g.name() == "no-collision-between-robots" && g.passed)
        );
    }
}

#[test]
fn four_robots_blind_to_each_other_collide() {
    let prepared = Scenario::load(&file("four-robots-swap.toml")).unwrap();
    let run = run_without_filter(&prepared, None).unwrap();
    let f = run.summary.fleet.as_ref().unwrap();
    assert!(
        f.robot_contacts > 0 && f.contacts_after_certified > 0,
        "{f:?}"
    );
    assert!(!run.summary.all_passed());
}

/// A differential drive among walkers (`diff-walkers.toml`): `command_pose` is given the
/// movers every period and certifies each arc against their reach; the monitor bounds every
/// clearance along the arcs (docs/movers.md §8). No contact under a certified command, every
/// guarantee held, and the filter acted.
#[test]
fn a_diff_robot_among_walkers_never_touches_one_under_a_certified_arc() {
    let prepared = Scenario::load(&file("diff-walkers.toml")).unwrap();
    assert!(prepared.base().is_some());
    let run = simulate(&prepared, None, Physics::Builtin).unwrap();
    let s = &run.summary;
    let m = s.movers.as_ref().expect("a mover report");
    let d = s.diff.as_ref().expect("a differential-drive report");
    println!("reached {} in {:.2} s, {m:?}, {d:?}", s.reached, s.time_s);
    assert!(s.all_passed(), "{:?}", s.guarantees);
    assert_eq!(m.contacts_after_certified, 0);
    assert_eq!(m.mover_contacts, 0);
    assert_eq!(
        m.certified_commands + m.overwhelmed_commands + m.refused_commands,
        s.steps,
        "one command a period"
    );
    assert!(m.yielding_commands > 0, "the filter acted");
    // The dynamic law is refused for a differential drive, by name.
    let e = simulate(&prepared, Some(Model::Dynamic), Physics::Builtin).unwrap_err();
    assert!(e.to_string().contains("base"), "{e}");
}

/// The negative control: the same robot never given the movers (`set_movers` not called, the
/// arcs certified against the known shapes only) drives into a walker, and
/// `no-collision-with-movers` fails.
#[test]
fn blind_to_the_walkers_the_diff_robot_touches_one() {
    let prepared = Scenario::load(&file("diff-walkers.toml")).unwrap();
    let run = run_without_filter(&prepared, None).unwrap();
    let m = run.summary.movers.as_ref().unwrap();
    println!("{m:?}");
    assert!(
        m.mover_contacts > 0 && m.contacts_after_certified > 0,
        "{m:?}"
    );
    assert_eq!(m.yielding_commands, 0);
    let g = run
        .summary
        .guarantees
        .iter()
        .find(|g| g.name() == "no-collision-with-movers")
        .unwrap();
    assert!(!g.passed);
}

/// Four differential drives swapping across an empty disc, each facing its goal: every robot
/// is a differential drive (`[robot] base = "diff"`, each `[[robots]]` entry with its own
/// start heading), each certifies its arcs against the others' rows (reciprocal, share ½).
fn diff_swap() -> harmonav_scenario::Prepared {
    let text = r#"
        name = "diff-swap"
        [workspace]
        type = "circle"
        center = [0.0, 0.0]
        radius = 6.0
        [robot]
        model = "kinematic"
        base = "diff"
        omega_max = 2.0
        yaw = 0.0
        control_period = 0.1
        start = [-3.0, 0.1]
        goal = [3.0, 0.1]
        radius = 0.2
        margin = 0.05
        [controller]
        v_max = 0.5
        [sim]
        dt = 0.1
        max_time = 80.0
        [[robots]]
        start = [3.0, -0.1]
        goal = [-3.0, -0.1]
        yaw = 3.14159
        [[robots]]
        start = [0.1, 3.0]
        goal = [0.1, -3.0]
        yaw = -1.5708
        [[robots]]
        start = [-0.1, -3.0]
        goal = [-0.1, 3.0]
        yaw = 1.5708
    "#;
    let path = Path::new("diff-swap.toml");
    Scenario::parse(path, text).unwrap().prepare(path).unwrap()
}

#[test]
fn four_diff_robots_swap_places_without_touching() {
    let prepared = diff_swap();
    let run = simulate(&prepared, None, Physics::Builtin).unwrap();
    let s = &run.summary;
    let f = s.fleet.as_ref().expect("a fleet report");
    println!(
        "reached {} in {:.2} s; {f:?}; {:?}",
        s.reached, s.time_s, s.diff
    );
    assert!(s.all_passed(), "{:?}", s.guarantees);
    assert!(s.diff.is_some(), "the first robot's arcs are reported");
    assert!(f.others.iter().all(|o| o.reached && o.safe), "{f:?}");
    assert_eq!(f.robot_contacts, 0);
    assert!(f.min_robot_clearance >= prepared.margin() - 1e-9, "{f:?}");
}

/// The negative control: the four differential drives blind to each other collide.
#[test]
fn four_diff_robots_blind_to_each_other_collide() {
    let prepared = diff_swap();
    let run = run_without_filter(&prepared, None).unwrap();
    let f = run.summary.fleet.as_ref().unwrap();
    println!("{f:?}");
    assert!(
        f.robot_contacts > 0 && f.contacts_after_certified > 0,
        "{f:?}"
    );
    assert!(!run.summary.all_passed());
}

/// A floor plan with `[[robots]]` (`floor-corridor-swap.toml`): four robots swap rooms
/// through a corridor, each with its own floor navigator on the one map, the others given as
/// reciprocal movers; under both laws every robot arrives with every guarantee, and no two
/// touch (each keeps its margin from the others' bodies).
#[test]
fn four_robots_swap_rooms_on_a_floor_plan_without_touching() {
    use harmonav_scenario::floorplan::FloorScenario;
    use harmonav_sim::floor::FloorSummary;
    use harmonav_sim::physics::simulate_floor;
    let prepared = FloorScenario::load(&file("floor-corridor-swap.toml")).unwrap();
    let start = nalgebra::Vector2::from(prepared.scenario.robot.start);
    let margin = prepared.scenario.robot.margin;
    for model in [Model::Kinematic, Model::Dynamic] {
        let run = simulate_floor(&prepared, Some(model), start, Physics::Builtin).unwrap();
        let s = FloorSummary::new(&prepared, Some(model), start, &run);
        let f = s.fleet.as_ref().expect("a fleet report");
        println!(
            "{model:?}: reached {} in {:.2} s, {f:?}",
            s.reached, s.time_s
        );
        assert_eq!(f.others.len(), 3);
        assert!(s.all_passed(), "{model:?}: {:?}", s.guarantees);
        assert!(f.others.iter().all(|o| o.reached && o.safe), "{f:?}");
        assert_eq!(f.robot_contacts, 0);
        assert!(f.min_robot_clearance >= margin - 1e-9, "{f:?}");
        assert!(
            s.guarantees
                .iter()
                .any(|g| g.name() == "no-collision-between-robots" && g.passed)
        );
    }
    assert!(simulate_floor(&prepared, None, start, Physics::Rapier).is_err());
}

/// The negative control on a floor plan: the four robots blind to each other collide in the
/// corridor, and `no-collision-between-robots` fails.
#[test]
fn four_robots_blind_to_each_other_collide_on_a_floor_plan() {
    use harmonav_scenario::floorplan::FloorScenario;
    use harmonav_sim::floor::{FloorSummary, run_without_filter};
    let prepared = FloorScenario::load(&file("floor-corridor-swap.toml")).unwrap();
    let start = nalgebra::Vector2::from(prepared.scenario.robot.start);
    let run = run_without_filter(&prepared, None, start).unwrap();
    let s = FloorSummary::new(&prepared, None, start, &run);
    let f = s.fleet.as_ref().unwrap();
    println!("{f:?}");
    assert!(
        f.robot_contacts > 0 && f.contacts_after_certified > 0,
        "{f:?}"
    );
    let g = s
        .guarantees
        .iter()
        .find(|g| g.name() == "no-collision-between-robots")
        .unwrap();
    assert!(!g.passed);
}

/// The same swap with every robot a differential drive (`[robot] base = "diff"`, the robots
/// from the right facing left): each floor navigator's `command_pose` certifies its arcs
/// against the others; every robot arrives with every guarantee, no two touch.
#[test]
fn four_diff_robots_swap_rooms_on_a_floor_plan_without_touching() {
    use harmonav_scenario::floorplan::FloorScenario;
    use harmonav_sim::floor::FloorSummary;
    use harmonav_sim::physics::simulate_floor;
    let text = std::fs::read_to_string(file("floor-corridor-swap.toml"))
        .unwrap()
        .replace(
            "v_max = 0.5\n",
            "v_max = 0.5\nbase = \"diff\"\nomega_max = 2.0\ncontrol_period = 0.1\n",
        )
        .replace("goal = [0.7, 2.0]\n", "goal = [0.7, 2.0]\nyaw = 3.14159\n")
        .replace("goal = [0.7, 1.0]\n", "goal = [0.7, 1.0]\nyaw = 3.14159\n");
    let path = Path::new("floor-corridor-swap-diff.toml");
    let prepared = FloorScenario::parse(path, &text)
        .unwrap()
        .prepare(path)
        .unwrap();
    assert!(prepared.base().is_some());
    let start = nalgebra::Vector2::from(prepared.scenario.robot.start);
    let run = simulate_floor(&prepared, None, start, Physics::Builtin).unwrap();
    let s = FloorSummary::new(&prepared, None, start, &run);
    let f = s.fleet.as_ref().expect("a fleet report");
    println!("reached {} in {:.2} s, {f:?}", s.reached, s.time_s);
    assert!(s.all_passed(), "{:?}", s.guarantees);
    assert!(s.diff.is_some());
    assert!(f.others.iter().all(|o| o.reached && o.safe), "{f:?}");
    assert_eq!(f.robot_contacts, 0);
    assert!(f.min_robot_clearance >= prepared.scenario.robot.margin - 1e-9);
}

/// A force-bounded robot (issue 54, `[robot] force_bound`): its runs are judged by
/// `force-within-bound` under the dynamic law, in a star world with a mover and on a floor
/// plan, and every guarantee holds; a kinematic run of the same file has no such guarantee.
#[test]
fn a_force_bounded_run_is_judged_against_its_bound_in_either_world() {
    use harmonav_scenario::floorplan::FloorScenario;
    use harmonav_sim::floor::FloorSummary;
    use harmonav_sim::physics::simulate_floor;

    let force = |g: &[harmonav_sim::guarantee::Guarantee]| {
        g.iter()
            .find(|g| g.name() == "force-within-bound")
            .map(|g| (g.passed, g.check.to_string()))
    };
    let prepared = Scenario::load(&file("person-crossing-force-bound.toml")).unwrap();
    let run = simulate(&prepared, Some(Model::Dynamic), Physics::Builtin).unwrap();
    let s = &run.summary;
    assert!(s.all_passed() && s.reached, "{:?}", s.guarantees);
    let (passed, detail) = force(&s.guarantees).expect("force-within-bound");
    assert!(passed && detail.contains("F = 2 N"), "{detail}");
    let run = simulate(&prepared, Some(Model::Kinematic), Physics::Builtin).unwrap();
    assert_eq!(force(&run.summary.guarantees), None);

    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/floorplans/l-room.toml");
    let text = std::fs::read_to_string(&path).unwrap().replace(
        "mu = 2.0\n",
        "mu = 2.0\nforce_bound = 0.5\ncontrol_period = 0.01\n",
    );
    assert!(text.contains("force_bound = 0.5"));
    let p = FloorScenario::parse(&path, &text)
        .and_then(|s| s.prepare(&path))
        .unwrap();
    let start = nalgebra::Vector2::new(1.0, 5.4);
    let r = simulate_floor(&p, None, start, Physics::Builtin).unwrap();
    let summary = FloorSummary::new(&p, None, start, &r);
    assert!(summary.all_passed(), "{:?}", summary.guarantees);
    assert!(r.max_force <= 0.5 && r.max_force > 0.49, "{}", r.max_force);
    let (passed, _) = force(&summary.guarantees).expect("force-within-bound");
    assert!(passed);
}
