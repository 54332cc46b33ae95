//! A run's outputs as one set: `summary.json`, `run.mcap` and the figures, checked before the
//! run ([`check_output_dir`]), streamed while it goes ([`Outputs`]) and moved into place
//! together ([`crate::atomic::StagedDir`]).

use std::path::{Path, PathBuf};

use harmonav_scenario::Prepared;
use harmonav_sim::summary::Run;
use harmonav_sim::trace::Event;

use crate::atomic::{CreatedDir, OutputError, StagedDir};
use crate::record::{RecordError, Stream, replay};

/// The figures a run may write; those a run does not write are removed from `dir`, so that a
/// folder never mixes the files of two runs.
const FIGURES: [&str; 3] = ["trajectory.svg", "speed.svg", "energy.svg"];

/// Every file a set of outputs may write or remove.
pub const OUTPUT_FILES: [&str; 5] = [
    "summary.json",
    "run.mcap",
    "trajectory.svg",
    "speed.svg",
    "energy.svg",
];

/// Checks that `dir` can take the outputs, before a run that would otherwise fail only at its
/// end, and changes nothing: [`crate::atomic::check_output_names`] for [`OUTPUT_FILES`] (an empty
/// path, a path below a file, a dangling or looping link, an unwritable folder, a path too
/// long, an output name taken by a folder are refused).
pub fn check_output_dir(dir: &Path) -> Result<(), OutputError> {
    crate::atomic::check_output_names(dir, &OUTPUT_FILES)
}

/// Writes `run.mcap`, `trajectory.svg`, (dynamic runs) `speed.svg` and `energy.svg`, and
/// `summary.json` into `dir` as one set: [`Outputs::begin`], the run replayed into its
/// recording ([`replay`]), then [`Outputs::finish`]. Returns the paths, `summary.json` first.
pub fn write_outputs(
    dir: &Path,
    prepared: &Prepared,
    run: &Run,
) -> Result<Vec<std::path::PathBuf>, OutputError> {
    let mut outputs = Outputs::begin(dir, prepared)?;
    replay(run, &mut |e| outputs.observe(e));
    outputs.finish(run)
}

/// A set of outputs being written while its run goes: the recording streams into a fresh
/// staging folder inside `dir` ([`crate::atomic::StagedDir`]) as the run hands it its events
/// ([`Outputs::observe`], the observer of `harmonav_sim::physics::simulate_observed`), and
/// [`Outputs::finish`] adds the figures and the summary and moves the set into place. Dropped
/// before (the run failed, an interrupt), nothing of it is left and the previous set is
/// untouched.
pub struct Outputs<'p> {
    set: Opened<'p>,
    prepared: &'p Prepared,
}

/// A set being written, of either world: its folder, its staging folder and its recording
/// ([`Outputs`], [`crate::floor::FloorOutputs`]).
pub(crate) struct Opened<'p> {
    pub(crate) dir: PathBuf,
    stage: StagedDir,
    pub(crate) stream: Stream<'p>,
    /// Dropped last: the output folder, if this set created it, goes when it is left empty.
    created: CreatedDir,
}

impl<'p> Opened<'p> {
    /// Checks `dir` ([`check_output_dir`]), creates it (and its missing parents, removed again
    /// if the set is dropped unfinished: [`CreatedDir`]) and its staging folder, and opens the
    /// recording there with `open` (given the path of `run.mcap`).
    pub(crate) fn open(
        dir: &Path,
        open: impl FnOnce(&Path) -> Result<Stream<'p>, RecordError>,
    ) -> Result<Self, OutputError> {
        check_output_dir(dir)?;
        let created = CreatedDir::create(dir)?;
        let stage = StagedDir::new(dir)?;
        let stream = open(&stage.path().join("run.mcap")).map_err(|e| OutputError::Content {
            file: "run.mcap",
            problem: e.to_string(),
        })?;
        Ok(Self {
            dir: dir.to_path_buf(),
            stage,
            stream,
            created,
        })
    }

    /// Ends the recording, writes `files` (name and content, the summary last) into the
    /// staging folder, and moves the set into place: `run.mcap`, then `files` in their order,
    /// the other names of `stale` removed. Returns the paths, the last file first.
    pub(crate) fn commit(
        self,
        files: &[(&'static str, String)],
        stale: &[&str],
    ) -> Result<Vec<PathBuf>, OutputError> {
        let Self {
            dir,
            stage,
            stream,
            created,
        } = self;
        // On an error the staging folder goes first (with `move_in`'s arguments), then the
        // output folder if this set created it and it is empty again.
        let mut names = move_in(stage, stream, files, stale)?;
        created.keep();
        names.rotate_right(1);
        Ok(names.iter().map(|n| dir.join(n)).collect())
    }
}

/// Ends the recording, writes `files` into the staging folder and moves the set into place
/// ([`Opened::commit`]); the names moved, `run.mcap` first.
fn move_in(
    stage: StagedDir,
    stream: Stream<'_>,
    files: &[(&'static str, String)],
    stale: &[&str],
) -> Result<Vec<&'static str>, OutputError> {
    stream.finish().map_err(|e| OutputError::Content {
        file: "run.mcap",
        problem: e.to_string(),
    })?;
    let mut names = vec!["run.mcap"];
    for (name, text) in files {
        let path = stage.path().join(name);
        std::fs::write(&path, text.as_bytes())
            .map_err(|source| OutputError::Io { path, source })?;
        names.push(name);
    }
    stage.commit(&names, stale)?;
    Ok(names)
}

impl<'p> Outputs<'p> {
    /// Checks `dir` ([`check_output_dir`]), creates it (and its missing parents, removed again if
    /// the set is dropped unfinished: [`crate::atomic::CreatedDir`]) and its staging folder, and opens the
    /// recording.
    pub fn begin(dir: &Path, prepared: &'p Prepared) -> Result<Self, OutputError> {
        let set = Opened::open(dir, |path| Stream::create(path, prepared))?;
        Ok(Self { set, prepared })
    }

    /// Logs one event of the run into the recording.
    pub fn observe(&mut self, event: Event<'_>) {
        self.set.stream.observe(event);
    }

    /// Ends the recording, draws the figures of `run` (the run whose events were observed),
    /// writes `summary.json` and moves the set into place: `summary.json` last, and the
    /// figures this run does not draw removed (a kinematic run removes a stale `speed.svg`
    /// and `energy.svg`). `dir` is checked again first ([`check_output_dir`]: it may have
    /// changed during the run), and the set's names once more before anything is moved. On
    /// an error while writing, nothing of the new set is left and the previous set is
    /// untouched (a failing rename while moving the set, an I/O fault, can leave a mix).
    /// Returns the paths, `summary.json` first.
    pub fn finish(self, run: &Run) -> Result<Vec<std::path::PathBuf>, OutputError> {
        let Self { mut set, prepared } = self;
        check_output_dir(&set.dir)?;
        // A run with `[[robots]]`: the other robots' own trajectories.
        if let Some(fleet) = &run.summary.fleet {
            set.stream.robots(&fleet.others);
        }
        let content =
            |file: &'static str| move |problem: String| OutputError::Content { file, problem };
        let mut figures = vec![(
            "trajectory.svg",
            crate::figures::trajectory_svg(prepared, run).map_err(content("trajectory.svg"))?,
        )];
        if run.summary.speed_bound.is_some() {
            figures.push((
                "speed.svg",
                crate::figures::speed_svg(run).map_err(content("speed.svg"))?,
            ));
            figures.push((
                "energy.svg",
                crate::figures::energy_svg(run).map_err(content("energy.svg"))?,
            ));
        }
        let summary = serde_json::to_string_pretty(&run.summary)
            .map_err(|e| content("summary.json")(e.to_string()))?
            + "\n";
        figures.push(("summary.json", summary));
        set.commit(&figures, &FIGURES)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A set that fails while it is moved in (here: a file it cannot write) leaves neither its
    /// staging folder nor the output folders it created.
    #[test]
    fn a_set_that_fails_while_committing_leaves_no_folder_it_created() {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shapes/mixed.toml");
        let prepared = harmonav_scenario::Scenario::load(&file).unwrap();
        let base =
            std::env::temp_dir().join(format!("harmonav-commit-fail-{}", std::process::id()));
        let dir = base.join("new/set");
        let _ = std::fs::remove_dir_all(&base);
        std::fs::create_dir_all(&base).unwrap();
        let set = Opened::open(&dir, |p| Stream::create(p, &prepared)).unwrap();
        assert!(dir.is_dir());
        let e = set
            .commit(&[("no-such-folder/summary.json", String::new())], &[])
            .unwrap_err();
        assert!(matches!(e, OutputError::Io { .. }), "{e}");
        assert!(
            !base.join("new").exists(),
            "the folders the set created are gone"
        );
        std::fs::remove_dir_all(&base).unwrap();
    }
}
