//! The CLI's errors: each names the file, argument or start it is about, and each ends the
//! program with exit code 2 (bad input, or outputs that could not be written).

use std::path::PathBuf;

use harmonav_field::FieldError;
use harmonav_output::atomic::OutputError;
use harmonav_rs::NavError;
use harmonav_scenario::ScenarioError;
use harmonav_sim::summary::RunError;
use harmonav_sim::sweep::SweepError;

/// Why a command failed.
#[derive(Debug)]
pub enum CliError {
    /// `-` given as the scenario: standard input is not read.
    Stdin,
    /// The scenario file cannot be loaded.
    Scenario(ScenarioError),
    /// `--at` is not two finite numbers `X,Y`.
    Point {
        /// The argument as given.
        arg: String,
    },
    /// The field of the scenario cannot be built.
    Field(FieldError),
    /// The run of `scenario` could not start.
    Run {
        /// The scenario file.
        scenario: PathBuf,
        /// Why.
        error: RunError,
    },
    /// `--out` cannot take the outputs: found before the run.
    Out(OutputError),
    /// Writing the outputs into `--out` failed after the run (whose summary was printed).
    Write(OutputError),
    /// `--starts` is out of range, or a start of the sweep could not be run.
    Sweep(SweepError),
    /// A start of the sweep of `scenario` could not be run.
    SweepStart {
        /// The scenario file.
        scenario: PathBuf,
        /// Which start, and why.
        error: SweepError,
    },
    /// The JSON output could not be made.
    Json(serde_json::Error),
    /// `--starts` above a floor-plan sweep's cap (`harmonav_scenario::floorplan::MAX_STARTS`).
    FloorStarts {
        /// The scenario file.
        scenario: PathBuf,
        /// `--starts` as given.
        count: usize,
    },
    /// `sweep` on a star world without `--starts`.
    StartsRequired {
        /// The scenario file.
        scenario: PathBuf,
    },
    /// The navigator of a floor plan could not be built or refused an obstacle.
    Navigator {
        /// The scenario file.
        scenario: PathBuf,
        /// Why.
        error: NavError,
    },
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Stdin => write!(
                f,
                "`-`: reading a scenario from standard input is not supported; give the file's path"
            ),
            Self::Scenario(e) => write!(f, "{e}"),
            Self::Point { arg } => write!(f, "`--at {arg}`: expected two finite numbers X,Y"),
            Self::Field(e) => write!(f, "{e}"),
            Self::Run { scenario, error } => write!(f, "{}: {error}", scenario.display()),
            Self::Out(e) => write!(f, "--out: {e}; nothing was run"),
            Self::Write(e) => write!(
                f,
                "--out: the outputs were not written: {e} (the summary above is the run's)"
            ),
            Self::Sweep(e @ (SweepError::NoStarts | SweepError::TooManyStarts { .. })) => {
                write!(f, "--starts: {e}")
            }
            Self::Sweep(e) => write!(f, "{e}"),
            Self::SweepStart { scenario, error } => {
                write!(f, "{}: {error}", scenario.display())
            }
            Self::Json(e) => write!(f, "cannot write the JSON output: {e}"),
            Self::FloorStarts { scenario, count } => write!(
                f,
                "--starts: a floor-plan sweep flies at most {} starts, got {count} ({}; a star \
                 world's sweep takes up to {})",
                harmonav_scenario::floorplan::MAX_STARTS,
                scenario.display(),
                harmonav_sim::sweep::MAX_STARTS
            ),
            Self::StartsRequired { scenario } => write!(
                f,
                "{}: `sweep` on a star world needs --starts N (seeded random starts); a floor \
                 plan sweeps the starts of its file",
                scenario.display()
            ),
            Self::Navigator { scenario, error } => write!(f, "{}: {error}", scenario.display()),
        }
    }
}

impl std::error::Error for CliError {}

impl From<ScenarioError> for CliError {
    fn from(e: ScenarioError) -> Self {
        Self::Scenario(e)
    }
}

impl From<FieldError> for CliError {
    fn from(e: FieldError) -> Self {
        Self::Field(e)
    }
}

impl From<SweepError> for CliError {
    fn from(e: SweepError) -> Self {
        Self::Sweep(e)
    }
}

impl From<serde_json::Error> for CliError {
    fn from(e: serde_json::Error) -> Self {
        Self::Json(e)
    }
}
