//! Every constant of the navigator in one module (issue 51, item 5): the defaults a user gets,
//! the ranges the options are checked against, and the tuning of the hold, the escapes, the
//! differential drive and the perception. Each is documented, with its equation, where it is
//! used; this module only gathers them. The same names at the crate's root are deprecated
//! aliases, kept for one release.

/// Defaults: the arrival tolerance, the goal heading's, the control periods and the scan
/// memory.
pub use crate::base::{GOAL_ARRIVAL, GOAL_HEADING_TOLERANCE};
pub use crate::options::{DEFAULT_DYNAMIC_PERIOD, DEFAULT_KINEMATIC_PERIOD};
pub use crate::scanning::DEFAULT_FREE_MEMORY;

/// Ranges: what the options, the movers and the scenario files accept.
pub use crate::ranges::{MAX_MOVER, MIN_APERTURE_DEG, PARAMETER_RANGE};

/// The hold (docs/maths.md §10): the certified step's fractions, its halvings and traces.
pub use crate::hold::{
    CHORD_AFTER_HALVINGS, CHORD_SUBSTEPS, DYNAMIC_FRACTION, KINEMATIC_FRACTION, MAX_HALVINGS,
    MAX_TRACE_BALLS, REST_DIRECTIONS, REST_SCALE, SPEED_SLACK,
};

/// The way out of a margin band: its candidate directions and the blind spread.
pub use crate::certified::{BLIND, CANDIDATES};

/// A floor plan's escapes from the rest points of the hold's slide (docs/maths.md §13.7).
pub use crate::floor::{ESCAPE_BLOCKED, ESCAPE_DROP, ESCAPE_STALL};

/// The differential drive's gains (docs/unicycle.md).
pub use crate::diff::{GOAL_GAIN_RATIO, RECOVERY_ALIGNMENT, TURN_GAIN};

/// Range-scan perception: how far behind the depth prior a fit may reach.
pub use crate::scanning::FIT_BEYOND_DEPTH;

/// The deprecated aliases at the crate's root, one release long: `harmonav::NAME` is
/// `harmonav::tuning::NAME`.
macro_rules! root_aliases {
    ($($name:ident: $t:ty),* $(,)?) => {
        $(
            #[doc = concat!("Deprecated: moved to [`tuning::", stringify!($name), "`](crate::tuning::", stringify!($name), ").")]
            #[deprecated(note = "moved to the module `harmonav::tuning` (issue 51)")]
            pub const $name: $t = crate::tuning::$name;
        )*
    };
}

/// The aliases themselves, re-exported at the root by `lib.rs`.
pub(crate) mod root {
    root_aliases!(
        GOAL_ARRIVAL: f64,
        GOAL_HEADING_TOLERANCE: f64,
        DEFAULT_DYNAMIC_PERIOD: f64,
        DEFAULT_KINEMATIC_PERIOD: f64,
        DEFAULT_FREE_MEMORY: usize,
        MAX_MOVER: f64,
        MIN_APERTURE_DEG: f64,
        PARAMETER_RANGE: (f64, f64),
        CHORD_AFTER_HALVINGS: u32,
        CHORD_SUBSTEPS: usize,
        DYNAMIC_FRACTION: f64,
        KINEMATIC_FRACTION: f64,
        MAX_HALVINGS: u32,
        MAX_TRACE_BALLS: usize,
        REST_DIRECTIONS: usize,
        REST_SCALE: f64,
        SPEED_SLACK: f64,
        BLIND: f64,
        CANDIDATES: usize,
        ESCAPE_BLOCKED: f64,
        ESCAPE_DROP: f64,
        ESCAPE_STALL: f64,
        GOAL_GAIN_RATIO: f64,
        RECOVERY_ALIGNMENT: f64,
        TURN_GAIN: f64,
        FIT_BEYOND_DEPTH: f64,
    );
}
