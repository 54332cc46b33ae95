//! Python bindings of harmonav (module `harmonav`): shapes, `Θ` evaluated in batches over
//! NumPy arrays, the online `Navigator` (and `FloorNavigator` on a floor plan), scenario runs and sweeps, floor-plan runs. Every call wraps the Rust
//! API of the `harmonav` facade and `harmonav-sim`; nothing here re-implements the maths.
//!
//! Errors: bad arguments raise `ValueError` (with the Rust error's message, which names the
//! field or the file, field and line, its control characters escaped: `convert::escape`), wrong
//! types `TypeError`. Points outside the free space
//! in a batch evaluation give NaN rows (`Field.eval`) and `False` in `Field.free`.

mod convert;
mod experiment;
mod field;
mod floor_navigator;
mod floorplan;
mod movers;
mod navigator;
mod options;
mod report;
mod scenario;
mod shapes;

use pyo3::prelude::*;

/// harmonav: provably correct robot navigation with the harmonic navigation functions of
/// Loizou & Rimon, `Θ = σ∘φ_k∘Φ`, with NumPy arrays in and out.
#[pymodule]
fn harmonav(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<shapes::Shape>()?;
    m.add_function(wrap_pyfunction!(shapes::circle, m)?)?;
    m.add_function(wrap_pyfunction!(shapes::ellipse, m)?)?;
    m.add_function(wrap_pyfunction!(shapes::polygon, m)?)?;
    m.add_function(wrap_pyfunction!(shapes::star, m)?)?;
    m.add_function(wrap_pyfunction!(shapes::tabulated, m)?)?;
    m.add_class::<field::Field>()?;
    m.add_class::<navigator::Navigator>()?;
    m.add_class::<navigator::ScanUpdate>()?;
    m.add_class::<movers::Mover>()?;
    m.add_class::<movers::MoverFilter>()?;
    m.add_class::<floor_navigator::FloorNavigator>()?;
    m.add_class::<scenario::Scenario>()?;
    m.add_class::<scenario::RunResult>()?;
    m.add_class::<scenario::SweepResult>()?;
    m.add_function(wrap_pyfunction!(scenario::sweep, m)?)?;
    m.add_class::<floorplan::FloorPlan>()?;
    m.add_class::<floorplan::FloorRunResult>()?;
    m.add_function(wrap_pyfunction!(experiment::run_batch, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::random_start_points, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::check_run_config, m)?)?;
    m.add_function(wrap_pyfunction!(report::study_table, m)?)?;
    m.add_function(wrap_pyfunction!(report::study_cells, m)?)?;
    Ok(())
}
