//! Scenario files: loading (with the CLI's validation), runs and sweeps. File I/O and
//! simulations run without the GIL; a sweep runs in parts and checks for Ctrl-C between them.

use std::path::PathBuf;

use harmonav_output::set::Outputs;
use harmonav_scenario::scenario::read_text;
use harmonav_scenario::{Model, Prepared, Scenario as RsScenario};
use harmonav_sim::physics::{Physics, simulate_observed};
use harmonav_sim::summary::Run;
use harmonav_sim::sweep::{Report, check_count, random_starts, sweep_part};
use numpy::{PyArray1, PyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert::{
    detach_interruptible, escape, integer, points_like, policy, rows2, value_error,
};
use crate::field::Field;

/// A scenario file (TOML, `scenarios/README.md`), validated as `harmonav check` does.
///
/// Immutable: `copy.copy` and `copy.deepcopy` return the same object. Pickle stores the path
/// and the text read from it, and unpickling validates that text again (the file itself is not
/// read again: it may have changed, or be missing in another process).
#[pyclass(module = "harmonav", frozen)]
pub struct Scenario {
    pub(crate) prepared: Prepared,
    path: PathBuf,
    /// The file's text, as read (what pickle stores).
    text: String,
}

impl Scenario {
    /// `text` (read from `path`) parsed and validated, without the GIL.
    fn parsed(py: Python<'_>, path: PathBuf, text: String) -> PyResult<Self> {
        let prepared = py
            .detach(|| RsScenario::parse(&path, &text)?.prepare(&path))
            .map_err(value_error)?;
        Ok(Self {
            prepared,
            path,
            text,
        })
    }
}

/// The robot model asked for by `model=` (the facade's and the scenario file's name), or by
/// the old keyword `controller=`, kept as a deprecated alias (a `DeprecationWarning`; both at
/// once is an error).
pub fn model(
    py: Python<'_>,
    model: Option<&str>,
    controller: Option<&str>,
) -> PyResult<Option<Model>> {
    let name = match (model, controller) {
        (Some(_), Some(_)) => {
            return Err(value_error(
                "model and controller name the same thing: give model only",
            ));
        }
        (None, Some(old)) => {
            PyErr::warn(
                py,
                &py.get_type::<pyo3::exceptions::PyDeprecationWarning>(),
                c"controller= is deprecated: use model=",
                1,
            )?;
            Some(old)
        }
        (name, None) => name,
    };
    match name {
        None => Ok(None),
        Some("kinematic") => Ok(Some(Model::Kinematic)),
        Some("dynamic") => Ok(Some(Model::Dynamic)),
        Some(other) => Err(value_error(format!(
            "unknown model \"{other}\": expected \"kinematic\" or \"dynamic\""
        ))),
    }
}

/// A JSON-serialisable Rust value as a Python object (through `json.loads`), so that the keys
/// are exactly those of the files the CLI writes.
pub fn to_python<'py>(
    py: Python<'py>,
    value: &impl serde::Serialize,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(value_error)?;
    py.import("json")?.call_method1("loads", (text,))
}

#[pymethods]
impl Scenario {
    /// Loads and validates `path`, without the GIL (a FIFO or a slow file system does not
    /// stop other threads). Raises `ValueError` naming the file, the field and the line of the
    /// first problem.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        // As `RsScenario::load`, keeping the text for pickle.
        let text = py.detach(|| read_text(&path)).map_err(value_error)?;
        Self::parsed(py, path, text)
    }

    /// The scenario of `text` as if read from `path` (pickle's way back: see `__reduce__`).
    #[staticmethod]
    fn _from_text(py: Python<'_>, path: PathBuf, text: String) -> PyResult<Self> {
        Self::parsed(py, path, text)
    }

    /// Pickle support: `Scenario._from_text(path, text)`, the text as it was read.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let from_text = py.get_type::<Self>().getattr("_from_text")?;
        let args = (self.path.clone(), self.text.clone()).into_pyobject(py)?;
        Ok((from_text, args))
    }

    /// The same object: a scenario is immutable.
    fn __copy__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    /// The same object: a scenario is immutable (`memo` is unused).
    fn __deepcopy__(slf: Py<Self>, _memo: &Bound<'_, PyAny>) -> Py<Self> {
        slf
    }

    /// The scenario's `name`.
    #[getter]
    fn name(&self) -> &str {
        &self.prepared.scenario.name
    }

    /// The file it was loaded from.
    #[getter]
    fn path(&self) -> String {
        self.path.display().to_string()
    }

    /// The field `Θ` of the scenario with every obstacle known (global sensing), grown by the
    /// robot's radius and margin: what `harmonav eval` evaluates.
    fn field(slf: Bound<'_, Self>) -> PyResult<Field> {
        let field = slf.get().prepared.global_field().map_err(value_error)?;
        Ok(Field::of_scenario(field, slf.into_any().unbind()))
    }

    /// Runs the scenario and checks every guarantee. `model` (`"kinematic"` or `"dynamic"`)
    /// overrides the file's `[robot] model` (`controller=` is its deprecated alias); `physics` is `"builtin"` or `"rapier"` (the
    /// rapier2d cross-check); `out`, a directory, receives summary.json, run.mcap and the
    /// figures (a kinematic run removes a stale speed.svg and energy.svg there). The
    /// simulation runs without the GIL; Ctrl-C stops it (`KeyboardInterrupt`), and an unfinished
    /// `out` set leaves nothing behind.
    ///
    /// `out` is checked before the run: an empty path, a path below a file, a dangling or
    /// looping link, an unwritable folder, a path that is too long or a folder named like an
    /// output raise `ValueError`, and nothing is run or written. If writing fails after the
    /// run, `OSError` is raised with the run's `RunResult` as its `result` attribute and the
    /// summary as `summary`; the previous outputs are left whole.
    #[pyo3(signature = (model=None, physics="builtin", out=None, *, controller=None))]
    fn run(
        &self,
        py: Python<'_>,
        model: Option<&str>,
        physics: &str,
        out: Option<PathBuf>,
        controller: Option<&str>,
    ) -> PyResult<RunResult> {
        let model = self::model(py, model, controller)?;
        let physics: Physics = policy(physics)?;
        let prepared = &self.prepared;
        // As `harmonav run --out`: the folder checked first, the recording streamed during the
        // run (every event of it, a lidar's every scan), the set completed after it.
        // Ctrl-C is polled at the run's events; the unfinished set is dropped on the way out,
        // which removes its staging folder.
        let (run, written) = detach_interruptible(py, |poll| {
            let mut outputs = match &out {
                Some(dir) => Some(
                    Outputs::begin(dir, prepared)
                        .map_err(|e| format!("out: {e}; nothing was run"))?,
                ),
                None => None,
            };
            let run = simulate_observed(prepared, model, physics, &mut |e| {
                poll.check();
                if let Some(o) = outputs.as_mut() {
                    o.observe(e);
                }
            })
            .map_err(|e| format!("{}: {e}", self.path.display()))?;
            let written = outputs.map(|o| o.finish(&run));
            Ok::<_, String>((run, written))
        })?
        .map_err(value_error)?;
        let result = RunResult::new(py, &run)?;
        if let Some(Err(e)) = written {
            let err = PyOSError::new_err(format!(
                "out: the outputs were not written: {} (the run's result is this error's \
                 `result`)",
                escape(&e.to_string())
            ));
            let value = err.value(py);
            value.setattr("summary", result.summary.clone_ref(py))?;
            value.setattr("result", Py::new(py, result)?)?;
            return Err(err);
        }
        Ok(result)
    }

    /// The shortest collision-free path from the start to the goal around the shapes grown by
    /// the robot's radius and margin (a reduced visibility graph over their outlines,
    /// independent of `Θ`): `(length, waypoints (K, 2))`. The true shortest length lies within
    /// the outline's chord error of `length`. Raises `ValueError` if there is none.
    fn shortest_path<'py>(&self, py: Python<'py>) -> PyResult<(f64, Bound<'py, PyArray2<f64>>)> {
        let path = harmonav_sim::shortest::of_scenario(&self.prepared).map_err(value_error)?;
        let flat = path.waypoints.iter().flat_map(|p| [p.x, p.y]).collect();
        Ok((path.length, rows2(py, flat, path.waypoints.len())?))
    }

    fn __repr__(&self) -> String {
        escape(&format!(
            "Scenario({:?}, {})",
            self.prepared.scenario.name,
            self.path.display()
        ))
        .into_owned()
    }
}

/// The result of `Scenario.run`: `summary` (the dict of summary.json: `reached`, `time_s`,
/// `guarantees`, `outcome`, `path_length`, `recorded_states`, …), the recorded states `t`
/// (N,), `x` (N, 2), `v` (N, 2), `theta` (N,), and `discoveries` (a list of dicts:
/// `obstacle`, `time_s`, `position`). A run of more than 2¹⁷ recorded states keeps N ≤ 2¹⁷ of
/// them, evenly spaced in time (the monitors judged all `recorded_states`).
#[pyclass(module = "harmonav", frozen, get_all)]
pub struct RunResult {
    summary: Py<PyAny>,
    t: Py<PyArray1<f64>>,
    x: Py<PyArray2<f64>>,
    v: Py<PyArray2<f64>>,
    theta: Py<PyArray1<f64>>,
    discoveries: Py<PyAny>,
}

impl RunResult {
    fn new(py: Python<'_>, run: &Run) -> PyResult<Self> {
        let n = run.samples.len();
        let column = |f: &dyn Fn(&harmonav_sim::trace::Sample) -> f64| -> Vec<f64> {
            run.samples.iter().map(f).collect()
        };
        let pairs = |f: &dyn Fn(&harmonav_sim::trace::Sample) -> [f64; 2]| -> Vec<f64> {
            run.samples.iter().flat_map(f).collect()
        };
        let discoveries = pyo3::types::PyList::empty(py);
        for d in &run.summary.discoveries {
            let item = PyDict::new(py);
            item.set_item("obstacle", &d.obstacle)?;
            item.set_item("index", d.index)?;
            item.set_item("time_s", d.time_s)?;
            item.set_item("position", d.position)?;
            discoveries.append(item)?;
        }
        Ok(Self {
            summary: to_python(py, &run.summary)?.unbind(),
            t: PyArray1::from_vec(py, column(&|s| s.t)).unbind(),
            x: rows2(py, pairs(&|s| s.x), n)?.unbind(),
            v: rows2(py, pairs(&|s| s.v), n)?.unbind(),
            theta: PyArray1::from_vec(py, column(&|s| s.theta)).unbind(),
            discoveries: discoveries.into_any().unbind(),
        })
    }
}

#[pymethods]
impl RunResult {
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let summary = self.summary.bind(py);
        Ok(format!(
            "RunResult(reached={}, time_s={}, samples={})",
            summary.get_item("reached")?,
            summary.get_item("time_s")?,
            self.t.bind(py).len()
        ))
    }
}

/// The result of `sweep`: `starts` (N, 2), `outcomes` (N,) strings (`"reached"`,
/// `"collision"`, `"left-workspace"`, `"stalled"`, `"timed-out"`, `"step-collapsed"`,
/// `"invalid-start"`), `times` (N,) seconds (the arrival time for reached starts, the stall,
/// budget or collapse time otherwise, NaN for a collision or an invalid start), `reached`
/// (N,) booleans and `report`, the dict of `harmonav sweep --json` (its `failures` say why
/// each start did not arrive: `"not run: starts[3] lies inside obstacle disc"`).
#[pyclass(module = "harmonav", frozen, get_all)]
pub struct SweepResult {
    starts: Py<PyArray2<f64>>,
    outcomes: Py<PyAny>,
    times: Py<PyArray1<f64>>,
    reached: Py<PyArray1<bool>>,
    report: Py<PyAny>,
}

#[pymethods]
impl SweepResult {
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let report = self.report.bind(py);
        Ok(format!(
            "SweepResult(starts={}, reached={})",
            report.get_item("starts")?,
            report.get_item("reached")?
        ))
    }
}

/// `seed=`: an integer from 0 to 2⁶⁴ − 1, refused by name (pyo3's `OverflowError` names
/// nothing).
pub(crate) fn seed_arg(obj: &Bound<'_, PyAny>) -> PyResult<u64> {
    integer(obj, "seed", "an integer from 0 to 2^64 - 1")
}

/// Many starts in the scenario's world with every obstacle known (global sensing), in
/// parallel without the GIL: `starts` is a count of seeded random free starts (`seed`) or an
/// (N, 2) array of starts, at least 1 and at most 1 000 000 (as `harmonav sweep --starts`).
/// A start outside the free space is the outcome `"invalid-start"`, not an error.
/// `model` overrides the file's (`controller=` is its deprecated alias). The starts run in parts of two per core, and
/// Ctrl-C between two parts raises `KeyboardInterrupt`.
#[pyfunction]
#[pyo3(signature = (scenario, starts, seed=0, model=None, *, controller=None))]
pub fn sweep(
    py: Python<'_>,
    scenario: &Scenario,
    starts: &Bound<'_, PyAny>,
    #[pyo3(from_py_with = seed_arg)] seed: u64,
    model: Option<&str>,
    controller: Option<&str>,
) -> PyResult<SweepResult> {
    let prepared = &scenario.prepared;
    // A count of any size (not a bool) is a count, refused by name when out of range.
    let is_count = starts.is_instance_of::<pyo3::types::PyInt>()
        && !starts.is_instance_of::<pyo3::types::PyBool>();
    let count = if is_count {
        Some(integer::<usize>(
            starts,
            "starts",
            "a count from 1 to 1000000 or an (N, 2) array of starts",
        )?)
    } else {
        starts.extract::<usize>().ok()
    };
    let pts = if let Some(count) = count {
        py.detach(|| random_starts(prepared, count, seed))
            .map_err(|e| value_error(format!("starts: {e}")))?
    } else {
        // Any array-like of points, as the rest of the module takes them.
        let pts = points_like(starts, "starts")?;
        if let Some(i) = pts.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(value_error(format!("starts[{i}] is not finite")));
        }
        pts
    };
    check_count(pts.len()).map_err(|e| value_error(format!("starts: {e}")))?;
    let model = self::model(py, model, controller)?.unwrap_or(prepared.scenario.robot.model);
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    // Parts of two starts per thread: Ctrl-C waits for at most one part, and the threads
    // lose little to the last start of each part.
    let part = 2 * threads;
    let mut outcomes = Vec::with_capacity(pts.len());
    for first in (0..pts.len()).step_by(part) {
        let range = first..first + part;
        outcomes.extend(
            py.detach(|| sweep_part(prepared, &pts, range, model, threads))
                .map_err(value_error)?,
        );
        py.check_signals()?;
    }
    let report = Report::of(&pts, &outcomes);
    let n = pts.len();
    let flat: Vec<f64> = pts.iter().flat_map(|p| [p.x, p.y]).collect();
    let kinds: Vec<&str> = outcomes.iter().map(|o| o.kind()).collect();
    let numpy = py.import("numpy")?;
    Ok(SweepResult {
        starts: rows2(py, flat, n)?.unbind(),
        outcomes: numpy.call_method1("asarray", (kinds,))?.unbind(),
        times: PyArray1::from_vec(
            py,
            outcomes
                .iter()
                .map(|o| o.time().unwrap_or(f64::NAN))
                .collect(),
        )
        .unbind(),
        reached: PyArray1::from_vec(py, outcomes.iter().map(|o| o.reached()).collect()).unbind(),
        report: to_python(py, &report)?.unbind(),
    })
}
