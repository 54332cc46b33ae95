//! Issue 51, item 5: the navigator's constants live in `harmonav::tuning`; the names at the
//! crate's root are deprecated aliases of the same values, kept for one release.

#![allow(deprecated)]

use harmonav::tuning;

#[test]
fn the_roots_constants_are_aliases_of_the_tuning_modules() {
    let floats = [
        (harmonav::GOAL_ARRIVAL, tuning::GOAL_ARRIVAL),
        (
            harmonav::GOAL_HEADING_TOLERANCE,
            tuning::GOAL_HEADING_TOLERANCE,
        ),
        (
            harmonav::DEFAULT_DYNAMIC_PERIOD,
            tuning::DEFAULT_DYNAMIC_PERIOD,
        ),
        (
            harmonav::DEFAULT_KINEMATIC_PERIOD,
            tuning::DEFAULT_KINEMATIC_PERIOD,
        ),
        (harmonav::MAX_MOVER, tuning::MAX_MOVER),
        (harmonav::MIN_APERTURE_DEG, tuning::MIN_APERTURE_DEG),
        (harmonav::PARAMETER_RANGE.0, tuning::PARAMETER_RANGE.0),
        (harmonav::PARAMETER_RANGE.1, tuning::PARAMETER_RANGE.1),
        (harmonav::DYNAMIC_FRACTION, tuning::DYNAMIC_FRACTION),
        (harmonav::KINEMATIC_FRACTION, tuning::KINEMATIC_FRACTION),
        (harmonav::REST_SCALE, tuning::REST_SCALE),
        (harmonav::SPEED_SLACK, tuning::SPEED_SLACK),
        (harmonav::BLIND, tuning::BLIND),
        (harmonav::ESCAPE_BLOCKED, tuning::ESCAPE_BLOCKED),
        (harmonav::ESCAPE_DROP, tuning::ESCAPE_DROP),
        (harmonav::ESCAPE_STALL, tuning::ESCAPE_STALL),
        (harmonav::GOAL_GAIN_RATIO, tuning::GOAL_GAIN_RATIO),
        (harmonav::RECOVERY_ALIGNMENT, tuning::RECOVERY_ALIGNMENT),
        (harmonav::TURN_GAIN, tuning::TURN_GAIN),
        (harmonav::FIT_BEYOND_DEPTH, tuning::FIT_BEYOND_DEPTH),
    ];
    for (i, (root, moved)) in floats.into_iter().enumerate() {
        assert_eq!(root.to_bits(), moved.to_bits(), "entry {i}");
    }
    let counts = [
        (harmonav::DEFAULT_FREE_MEMORY, tuning::DEFAULT_FREE_MEMORY),
        (harmonav::CHORD_SUBSTEPS, tuning::CHORD_SUBSTEPS),
        (harmonav::MAX_TRACE_BALLS, tuning::MAX_TRACE_BALLS),
        (harmonav::REST_DIRECTIONS, tuning::REST_DIRECTIONS),
        (harmonav::CANDIDATES, tuning::CANDIDATES),
    ];
    for (i, (root, moved)) in counts.into_iter().enumerate() {
        assert_eq!(root, moved, "entry {i}");
    }
    assert_eq!(harmonav::CHORD_AFTER_HALVINGS, tuning::CHORD_AFTER_HALVINGS);
    assert_eq!(harmonav::MAX_HALVINGS, tuning::MAX_HALVINGS);
}
