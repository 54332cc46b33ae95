//! The tables of an experiment's records (`harmonav.experiment report`, issue 28): each row
//! (a dict of the Parquet columns) becomes a `harmonav_bench::table::Record`, and the one
//! tabulation of the workspace, the one `cargo xtask quality` prints, does the rest. Nothing
//! here computes a statistic.

use harmonav_bench::table::{self, CellStats, Record};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::experiment;

/// `row[key]` (`None` when the row does not have it or holds `None`), a `TypeError` naming the
/// column otherwise.
fn item<'py, T>(row: &Bound<'py, PyDict>, key: &str) -> PyResult<Option<T>>
where
    T: for<'a> FromPyObject<'a, 'py>,
    for<'a> <T as FromPyObject<'a, 'py>>::Error: Into<PyErr>,
{
    experiment::item(row, key).map_err(|e| PyTypeError::new_err(format!("records: column {e}")))
}

/// The record of one row.
fn record(row: &Bound<'_, PyDict>) -> PyResult<Record> {
    let steps = match (
        item::<u64>(row, "steps")?,
        item::<u64>(row, "rejected_steps")?,
    ) {
        (Some(s), rejected) => Some(s + rejected.unwrap_or(0)),
        (None, _) => None,
    };
    Ok(Record {
        world: item(row, "world")?.unwrap_or_default(),
        generated: item::<String>(row, "generator")?.is_some(),
        obstacles: item(row, "obstacles")?,
        law: item(row, "law")?,
        damping: item(row, "damping")?,
        speed: item(row, "speed")?,
        k: item(row, "k")?,
        sensing: item(row, "sensing")?,
        margin: item(row, "margin")?,
        physics: item(row, "physics")?,
        max_time: item(row, "max_time")?,
        start_index: item(row, "start_index")?,
        error: item(row, "error")?,
        reached: item(row, "reached")?.unwrap_or(false),
        time_s: item(row, "time_s")?,
        path_over_shortest: item(row, "path_over_shortest")?,
        min_clearance: item(row, "min_clearance")?,
        collisions: item(row, "collisions")?,
        overshoot: item(row, "overshoot")?,
        steps,
        guarantees_held: item(row, "guarantees_held")?.unwrap_or(false),
        command_us: item(row, "command_us")?,
        outcome: item(row, "outcome")?,
        conservatism: item(row, "conservatism")?,
    })
}

/// The cells of `rows` (a list of dicts).
fn stats(rows: &Bound<'_, PyAny>) -> PyResult<Vec<CellStats>> {
    let list = rows
        .cast::<PyList>()
        .map_err(|_| PyTypeError::new_err("records must be a list of dicts"))?;
    let records = list
        .iter()
        .map(|r| {
            let row = r
                .cast::<PyDict>()
                .map_err(|_| PyTypeError::new_err("records must be a list of dicts"))?;
            record(row)
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok(table::cells(&records))
}

/// The Markdown table of the records `rows` (a list of dicts with the columns `world`,
/// `generator`, `obstacles`, `law`, `damping`, `speed`, `k`, `sensing`, `margin`, `physics`,
/// `max_time`, `start_index`, `error`, `reached`, `time_s`, `path_over_shortest`,
/// `min_clearance`, `collisions`, `overshoot`, `steps`, `rejected_steps`, `guarantees_held` and
/// optionally `command_us` (the cost of one command, µs, in a comparison of planners),
/// `outcome` (the outcome's kind: the runs that did not arrive are counted by it) and
/// `conservatism` (perceived over true obstacle area of a lidar run);
/// a missing column or `None` is a value the run does not have): the table of
/// docs/benchmarks.md, as `cargo xtask quality` prints it (`harmonav_bench::table::table`).
#[pyfunction]
pub fn study_table(rows: &Bound<'_, PyAny>) -> PyResult<String> {
    Ok(table::table(&stats(rows)?))
}

/// The cells of the records `rows` (as [`study_table`] takes them), in the table's order: one
/// dict each with the cell's `world` (`None` for generated worlds), `obstacles`, `law`,
/// `policy`, `k`, `sensing`, `margin`, `physics`, `max_time`, and its `runs`, `errors`,
/// `reached`, `guarantees_held`, `collisions`, `ratio`, `time`, `steps` (median, p90, max),
/// `min_clearance`, `overshoot`, `command_us` and `conservatism` (median, p90, max; NaN where
/// no run measured it), `not_arrived` (a dict of outcome to runs that did not arrive), and the
/// per-run `ratios` and `arrived_times` of the runs that arrived.
#[pyfunction]
pub fn study_cells<'py>(py: Python<'py>, rows: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for c in stats(rows)? {
        let d = PyDict::new(py);
        let k = &c.key;
        d.set_item("world", &k.world)?;
        d.set_item("obstacles", k.obstacles)?;
        d.set_item("law", &k.law)?;
        d.set_item("policy", &k.policy)?;
        d.set_item("k", &k.k)?;
        d.set_item("sensing", &k.sensing)?;
        d.set_item("margin", k.margin)?;
        d.set_item("physics", &k.physics)?;
        d.set_item("max_time", k.max_time)?;
        d.set_item("runs", c.runs)?;
        d.set_item("errors", c.errors)?;
        d.set_item("reached", c.reached)?;
        d.set_item("guarantees_held", c.guarantees_held)?;
        d.set_item("collisions", c.collisions)?;
        d.set_item("ratio", c.ratio)?;
        d.set_item("time", c.time)?;
        d.set_item("steps", c.steps)?;
        d.set_item("min_clearance", c.min_clearance)?;
        d.set_item("overshoot", c.overshoot)?;
        d.set_item("command_us", c.command_us)?;
        d.set_item("conservatism", c.conservatism)?;
        d.set_item("not_arrived", &c.not_arrived)?;
        d.set_item("ratios", &c.ratios)?;
        d.set_item("arrived_times", &c.arrived_times)?;
        out.append(d)?;
    }
    Ok(out)
}
