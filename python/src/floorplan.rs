//! Floor-plan files (`[floor_plan]`, issue 25): loading (the harmonic map is solved then,
//! without the GIL) and runs of the user's loop around a `FloorNavigator`, judged as
//! `harmonav run` judges them (`harmonav_sim::floor`).

use std::path::PathBuf;

use harmonav_output::floor::FloorOutputs;
use harmonav_rs::HeadingPolicy;
use harmonav_scenario::floorplan::{FloorPrepared, FloorScenario};
use harmonav_sim::floor::FloorSummary;
use harmonav_sim::physics::{Physics, simulate_floor_observed};
use numpy::{PyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyOSError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{detach_interruptible, escape, point_like, policy, rows2, value_error};
use crate::scenario::{model, to_python};

/// A floor-plan file: a polygon with holes (or a ROS map) as the known walls and star
/// obstacles sensed online inside it, its harmonic map solved on load.
///
/// Immutable: `copy.copy` and `copy.deepcopy` return the same object. It does not pickle
/// (`TypeError`): it holds a harmonic map solved from files (the floor-plan file, a map's YAML
/// and image) that another process may not have, or have changed; pass the path and call
/// `FloorPlan.load(path)` there.
#[pyclass(module = "harmonav", frozen)]
pub struct FloorPlan {
    prepared: FloorPrepared,
}

#[pymethods]
impl FloorPlan {
    /// Loads and validates `path` and solves its harmonic map, without the GIL. Raises
    /// `ValueError` naming the file, the field and the problem.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let prepared = py
            .detach(|| FloorScenario::load(&path))
            .map_err(value_error)?;
        Ok(Self { prepared })
    }

    /// The scenario's `name`.
    #[getter]
    fn name(&self) -> &str {
        &self.prepared.scenario.name
    }

    /// The file it was loaded from.
    #[getter]
    fn path(&self) -> String {
        self.prepared.path.display().to_string()
    }

    /// `robot.start`, then the file's seeded `[starts]`: an (N, 2) array.
    #[getter]
    fn starts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = &self.prepared.starts;
        rows2(py, s.iter().flat_map(|p| [p.x, p.y]).collect(), s.len())
    }

    /// The boundary elements of the harmonic map.
    #[getter]
    fn elements(&self) -> usize {
        self.prepared.floor.map().elements().len()
    }

    /// `δ`, the width of the boundary layer outside the certified region `W_δ`, m.
    #[getter]
    fn delta(&self) -> f64 {
        self.prepared.floor.delta()
    }

    /// Runs the loop from `start` (default `robot.start`) under `model` (`"kinematic"` or
    /// `"dynamic"`; None: the file's), without the GIL, and judges every guarantee. `physics`
    /// is `"builtin"` or `"rapier"` (the walls as colliders, cross-checked against a built-in
    /// run: `harmonav run --physics rapier`). `out`, a folder, receives run.mcap (streamed
    /// during the run), trajectory.svg and summary.json as one set; it is checked before the run (`ValueError`, nothing run), and
    /// a failure to write after it raises `OSError` whose `result` is the `FloorRunResult`.
    /// `heading` (`"auto"` or `"paper"`; None: the file's `[robot] heading`) is the heading
    /// policy of either law (docs/maths.md §13.3: the dynamic law turns its velocity towards
    /// the shortest path by a force that does no work).
    #[pyo3(signature = (model=None, start=None, out=None, physics="builtin", heading=None))]
    fn run(
        &self,
        py: Python<'_>,
        model: Option<&str>,
        start: Option<&Bound<'_, PyAny>>,
        out: Option<PathBuf>,
        physics: &str,
        heading: Option<&str>,
    ) -> PyResult<FloorRunResult> {
        let model = self::model(py, model, None)?;
        let physics: Physics = policy(physics)?;
        let mut chosen;
        let prepared = match heading {
            Some(name) => {
                chosen = self.prepared.clone();
                chosen.scenario.robot.heading = name
                    .parse::<HeadingPolicy>()
                    .map_err(|e| value_error(format!("heading: {e}")))?;
                &chosen
            }
            None => &self.prepared,
        };
        let start = match start {
            Some(p) => point_like(p, "start")?,
            None => prepared.starts[0],
        };
        prepared
            .check_start(start)
            .map_err(|e| value_error(format!("start: {e}")))?;
        // As `harmonav run --out`: the folder checked first, the recording streamed during the
        // run, the set completed after it. Ctrl-C during the run (polled at its events) raises
        // `KeyboardInterrupt`; the unfinished set is dropped on the way out, which removes its
        // staging folder (and the output folder, if the run created it).
        let (result, summary, written) = detach_interruptible(py, |poll| {
            let mut outputs = match &out {
                Some(dir) => Some(
                    FloorOutputs::begin(dir, prepared)
                        .map_err(|e| format!("out: {e}; nothing was run"))?,
                ),
                None => None,
            };
            let result = simulate_floor_observed(prepared, model, start, physics, &mut |e| {
                poll.check();
                if let Some(o) = outputs.as_mut() {
                    o.observe(e);
                }
            })
            .map_err(|e| format!("{}: {e}", prepared.path.display()))?;
            let summary = FloorSummary::new(prepared, model, start, &result);
            let written = outputs.map(|o| o.finish(&summary, &result));
            Ok::<_, String>((result, summary, written))
        })?
        .map_err(value_error)?;
        let n = result.positions.len();
        let flat = result.positions.iter().flatten().copied().collect();
        let value = FloorRunResult {
            summary: to_python(py, &summary)?.unbind(),
            x: rows2(py, flat, n)?.unbind(),
        };
        if let Some(Err(e)) = written {
            let err = PyOSError::new_err(format!(
                "out: the outputs were not written: {} (the run's result is this error's \
                 `result`)",
                escape(&e.to_string())
            ));
            err.value(py).setattr("result", Py::new(py, value)?)?;
            return Err(err);
        }
        Ok(value)
    }

    /// `c_δ` certified over the walls (docs/maths.md §13.5), without the GIL: a dict with
    /// `c_delta` (a lower bound of `Θ` on the edge of the certified region), `c_delta_sampled`
    /// (the least `Θ` at its samples), the same two as `phi_certified` and `phi_sampled` (in
    /// `phi_k`, where `Θ` rounds to 1 near the walls), `evaluations`, `unresolved` (cells left
    /// at the depth limit), `c_slide` and `phi_slide` (`c_s`, below which the slide along that
    /// edge cannot rest, docs/maths.md §13.9: 1 and `inf` when it rests nowhere) and
    /// `starts_certified`, one bool per row of `starts`: `Θ(x₀) < c_δ` or `< c_s`, so its
    /// convergence is certified (the others run under the hold, clear at every step).
    fn certify_level<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let p = &self.prepared;
        let (level, starts) = py
            .detach(|| p.start_certificates())
            .map_err(|e| value_error(format!("{}: {e}", p.path.display())))?;
        let d = PyDict::new(py);
        d.set_item("c_delta", level.certified())?;
        d.set_item("c_delta_sampled", level.sampled())?;
        d.set_item("phi_certified", level.phi_certified)?;
        d.set_item("phi_sampled", level.phi_sampled)?;
        d.set_item("evaluations", level.evaluations)?;
        d.set_item("unresolved", level.unresolved)?;
        d.set_item("c_slide", level.slide())?;
        d.set_item("phi_slide", level.phi_slide)?;
        d.set_item("starts_certified", starts)?;
        Ok(d)
    }

    /// The same object: a floor plan is immutable.
    fn __copy__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    /// The same object: a floor plan is immutable (`memo` is unused).
    fn __deepcopy__(slf: Py<Self>, _memo: &Bound<'_, PyAny>) -> Py<Self> {
        slf
    }

    /// Refused with a `TypeError` that says why and what to do instead.
    fn __reduce__(&self) -> PyResult<()> {
        Err(PyTypeError::new_err(format!(
            "cannot pickle 'harmonav.FloorPlan' object: it holds a harmonic map solved from \
             files ({}) that another process may not have, or may have changed; pass the path \
             and call harmonav.FloorPlan.load(path) there",
            escape(&self.prepared.path.display().to_string())
        )))
    }

    fn __repr__(&self) -> String {
        escape(&format!(
            "FloorPlan({:?}, {}, {} elements)",
            self.prepared.scenario.name,
            self.prepared.path.display(),
            self.elements()
        ))
        .into_owned()
    }
}

/// The result of `FloorPlan.run`: `summary` (the dict of its summary.json: `reached`,
/// `outcome`, `time_s`, `min_clearance`, `swept_clearance`, `layer_clearance`, `heading`, `escapes`,
/// `guarantees`, …) and `x`, the kept positions (N, 2) from the start to the end.
#[pyclass(module = "harmonav", frozen, get_all)]
pub struct FloorRunResult {
    summary: Py<PyAny>,
    x: Py<PyArray2<f64>>,
}

#[pymethods]
impl FloorRunResult {
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let summary = self.summary.bind(py);
        Ok(format!(
            "FloorRunResult(reached={}, time_s={}, points={})",
            summary.get_item("reached")?,
            summary.get_item("time_s")?,
            self.x.bind(py).len()
        ))
    }
}
