//! The options every navigator takes, parsed and checked once: `Navigator(boundary, goal, …)`
//! and `FloorNavigator(outer, goal, holes, **options)` / `FloorNavigator.from_map(…)` all go
//! through [`Keywords::parse`] and [`Keywords::check`].

use harmonav_rs::transform::Shown;
use harmonav_rs::{
    Base, CentrePolicy, DampingPolicy, FloorOptions, HeadingPolicy, HoldPolicy, KPolicy, Law,
    NavError, Options, ScanOptions, SpeedPolicy,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert::{integer, policy, value_error};

/// The names of the options, in `Navigator(boundary, goal, …)`'s positional order.
pub(crate) const NAMES: [&str; 25] = [
    "law",
    "gain",
    "mass",
    "mu",
    "sensor",
    "radius",
    "margin",
    "k",
    "damping",
    "rho_min",
    "control_period",
    "hold",
    "speed",
    "v_max",
    "range_noise",
    "max_obstacle_depth",
    "growth_threshold",
    "fit_range",
    "free_memory",
    "base",
    "omega_max",
    "a_max",
    "alpha_max",
    "force_bound",
    "comfort",
];

/// The options of a navigator over either world, as given (what pickle rebuilds it with):
/// the law and its parameters, the robot, the sensor, the policies and the scan's priors.
/// Their defaults are the Rust [`Options::default`] and [`ScanOptions::default`].
#[derive(Clone, Debug)]
pub(crate) struct Keywords {
    law: String,
    gain: f64,
    mass: f64,
    mu: f64,
    sensor: (f64, f64),
    radius: f64,
    margin: f64,
    k: String,
    damping: String,
    rho_min: f64,
    control_period: Option<f64>,
    hold: String,
    speed: String,
    v_max: Option<f64>,
    range_noise: f64,
    max_obstacle_depth: f64,
    growth_threshold: f64,
    fit_range: Option<f64>,
    free_memory: usize,
    /// `"holonomic"` or `"diff"` (issue 53).
    base: String,
    /// A differential-drive base's top turn rate, rad/s.
    omega_max: Option<f64>,
    /// A differential-drive base's acceleration limits, m/s² and rad/s² (both or neither).
    a_max: Option<f64>,
    alpha_max: Option<f64>,
    /// The dynamic law's force bound `F`, N (issue 54: the braking certificate).
    force_bound: Option<f64>,
    /// The comfort distance from non-cooperative movers, m (docs/movers.md §7).
    comfort: f64,
}

impl Default for Keywords {
    fn default() -> Self {
        let o = Options::default();
        let s = &o.scan;
        Self {
            law: "kinematic".to_owned(),
            gain: 1.0,
            mass: 1.0,
            mu: 10.0,
            sensor: (o.sensor_range, o.sensor_aperture_deg),
            radius: o.radius,
            margin: o.margin,
            k: o.k.as_str().to_owned(),
            damping: o.damping.as_str().to_owned(),
            rho_min: o.rho_min,
            control_period: o.control_period,
            hold: o.hold.as_str().to_owned(),
            speed: o.speed.as_str().to_owned(),
            v_max: o.v_max,
            range_noise: s.range_noise,
            max_obstacle_depth: s.max_obstacle_depth,
            growth_threshold: s.growth_threshold,
            fit_range: Some(s.fit_range).filter(|r| r.is_finite()),
            free_memory: s.free_memory,
            base: o.base.as_str().to_owned(),
            omega_max: None,
            a_max: None,
            alpha_max: None,
            force_bound: o.force_bound,
            comfort: o.comfort,
        }
    }
}

impl Keywords {
    /// The options of a call of `class`: `positional` in [`NAMES`]' order, then `keywords`;
    /// the rest at their defaults. A name that is not an option, given twice, or more values
    /// than there are options is a `TypeError` naming it, as Python's own calls.
    pub(crate) fn parse(
        class: &str,
        positional: &Bound<'_, PyTuple>,
        keywords: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        // `boundary` and `goal` come first in `Navigator(...)`.
        if positional.len() > NAMES.len() {
            return Err(PyTypeError::new_err(format!(
                "{class}() takes at most {} positional arguments ({} given)",
                NAMES.len() + 2,
                positional.len() + 2
            )));
        }
        let mut parsed = Self::default();
        for (name, value) in NAMES.iter().zip(positional.iter()) {
            parsed.set(class, name, &value)?;
        }
        for (key, value) in keywords.into_iter().flat_map(|d| d.iter()) {
            let name = key.extract::<String>()?;
            if NAMES[..positional.len()].contains(&name.as_str()) {
                return Err(PyTypeError::new_err(format!(
                    "{class}() got multiple values for argument '{name}'"
                )));
            }
            parsed.set(class, &name, &value)?;
        }
        Ok(parsed)
    }

    /// Sets the option `name` to `value`, converted as its type is (a `TypeError` names it).
    fn set(&mut self, class: &str, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let set = match name {
            "law" => value.extract().map(|v| self.law = v),
            "gain" => value.extract().map(|v| self.gain = v),
            "mass" => value.extract().map(|v| self.mass = v),
            "mu" => value.extract().map(|v| self.mu = v),
            "sensor" => value.extract().map(|v| self.sensor = v),
            "radius" => value.extract().map(|v| self.radius = v),
            "margin" => value.extract().map(|v| self.margin = v),
            "k" => value.extract().map(|v| self.k = v),
            "damping" => value.extract().map(|v| self.damping = v),
            "rho_min" => value.extract().map(|v| self.rho_min = v),
            "control_period" => value.extract().map(|v| self.control_period = v),
            "hold" => value.extract().map(|v| self.hold = v),
            "speed" => value.extract().map(|v| self.speed = v),
            "v_max" => value.extract().map(|v| self.v_max = v),
            "range_noise" => value.extract().map(|v| self.range_noise = v),
            "max_obstacle_depth" => value.extract().map(|v| self.max_obstacle_depth = v),
            "growth_threshold" => value.extract().map(|v| self.growth_threshold = v),
            "fit_range" => value.extract().map(|v| self.fit_range = v),
            "free_memory" => free_memory_count(value).map(|v| self.free_memory = v),
            "base" => value.extract().map(|v| self.base = v),
            "omega_max" => value.extract().map(|v| self.omega_max = v),
            "a_max" => value.extract().map(|v| self.a_max = v),
            "alpha_max" => value.extract().map(|v| self.alpha_max = v),
            "force_bound" => value.extract().map(|v| self.force_bound = v),
            "comfort" => value.extract().map(|v| self.comfort = v),
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "{class}() got an unexpected keyword argument '{name}'"
                )));
            }
        };
        set.map_err(|e| while_processing(value.py(), name, e))
    }

    /// The values, in [`NAMES`]' order (what `Navigator`'s pickle passes positionally).
    pub(crate) fn values<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        Ok(vec![
            self.law.clone().into_pyobject(py)?.into_any(),
            self.gain.into_pyobject(py)?.into_any(),
            self.mass.into_pyobject(py)?.into_any(),
            self.mu.into_pyobject(py)?.into_any(),
            self.sensor.into_pyobject(py)?.into_any(),
            self.radius.into_pyobject(py)?.into_any(),
            self.margin.into_pyobject(py)?.into_any(),
            self.k.clone().into_pyobject(py)?.into_any(),
            self.damping.clone().into_pyobject(py)?.into_any(),
            self.rho_min.into_pyobject(py)?.into_any(),
            self.control_period.into_pyobject(py)?.into_any(),
            self.hold.clone().into_pyobject(py)?.into_any(),
            self.speed.clone().into_pyobject(py)?.into_any(),
            self.v_max.into_pyobject(py)?.into_any(),
            self.range_noise.into_pyobject(py)?.into_any(),
            self.max_obstacle_depth.into_pyobject(py)?.into_any(),
            self.growth_threshold.into_pyobject(py)?.into_any(),
            self.fit_range.into_pyobject(py)?.into_any(),
            self.free_memory.into_pyobject(py)?.into_any(),
            self.base.clone().into_pyobject(py)?.into_any(),
            self.omega_max.into_pyobject(py)?.into_any(),
            self.a_max.into_pyobject(py)?.into_any(),
            self.alpha_max.into_pyobject(py)?.into_any(),
            self.force_bound.into_pyobject(py)?.into_any(),
            self.comfort.into_pyobject(py)?.into_any(),
        ])
    }

    /// The options as keyword arguments (what `FloorNavigator`'s pickle passes).
    pub(crate) fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, value) in NAMES.iter().zip(self.values(py)?) {
            d.set_item(name, value)?;
        }
        Ok(d)
    }

    /// The law and the navigator's options, checked: every navigator's one validation path.
    /// The law's name first, then its parameters, the policies' names, and every option
    /// against its range ([`Options::validate`], the scenario files' ranges); each error
    /// names the keyword. A floor plan checks them before its map is solved.
    pub(crate) fn check(&self) -> PyResult<(Law, Options)> {
        let law = law_named(&self.law, self.gain, self.mass, self.mu)?;
        let mut options = Options::default()
            .with_sensor(self.sensor.0, self.sensor.1)
            .with_robot(self.radius, self.margin)
            .with_rho_min(self.rho_min)
            .with_k(policy::<KPolicy>(&self.k)?)
            .with_damping(policy::<DampingPolicy>(&self.damping)?)
            .with_hold(policy::<HoldPolicy>(&self.hold)?)
            .with_speed(policy::<SpeedPolicy>(&self.speed)?)
            .with_scan(ScanOptions {
                range_noise: self.range_noise,
                max_obstacle_depth: self.max_obstacle_depth,
                growth_threshold: self.growth_threshold,
                fit_range: self.fit_range.unwrap_or(f64::INFINITY),
                free_memory: self.free_memory,
                ..ScanOptions::default()
            });
        if let Some(h) = self.control_period {
            options = options.with_control_period(h);
        }
        if let Some(v) = self.v_max {
            options = options.with_v_max(v);
        }
        // After `with_v_max`: a differential-drive base caps the law's speed at its own bound.
        options = options.with_base(self.base()?);
        if let Some(f) = self.force_bound {
            options = options.with_force_bound(f);
        }
        options = options.with_comfort(self.comfort);
        options.validate(&law).map_err(value_error)?;
        Ok((law, options))
    }
}

impl Keywords {
    /// The base named `base` with its bounds: `"holonomic"` (today's robot; `omega_max`,
    /// `a_max` and `alpha_max` must not be given) or `"diff"` (`v_max` and `omega_max`
    /// required, `a_max` and `alpha_max` both or neither, each finite and positive). Each
    /// error names the argument; the ranges are then checked by [`Options::validate`].
    fn base(&self) -> PyResult<Base> {
        match self.base.as_str() {
            "holonomic" => {
                let given = [
                    ("omega_max", self.omega_max, "turn rate"),
                    ("a_max", self.a_max, "acceleration"),
                    ("alpha_max", self.alpha_max, "turn acceleration"),
                ];
                match given.iter().find(|(_, v, _)| v.is_some()) {
                    None => Ok(Base::Holonomic),
                    Some((name, _, what)) => Err(value_error(format!(
                        "`{name}` bounds a differential-drive base's {what}: give \
                         base=\"diff\" with it"
                    ))),
                }
            }
            "diff" => {
                let bound = |name: &str, value: Option<f64>| match value {
                    None => Err(value_error(format!(
                        "`{name}` is required with base=\"diff\" (the base's bound)"
                    ))),
                    Some(v) if v.is_finite() && v > 0.0 => Ok(v),
                    Some(v) => Err(value_error(format!(
                        "`{name}` must be finite and positive, got {}",
                        Shown(v)
                    ))),
                };
                let base = Base::diff(
                    bound("v_max", self.v_max)?,
                    bound("omega_max", self.omega_max)?,
                );
                match (self.a_max, self.alpha_max) {
                    (None, None) => Ok(base),
                    (a, alpha) => {
                        let need = |name: &str, value: Option<f64>| match value {
                            None => Err(value_error(format!(
                                "`{name}` is required with the other acceleration limit \
                                 (a_max, m/s², and alpha_max, rad/s²: both or neither)"
                            ))),
                            v => bound(name, v),
                        };
                        Ok(base.with_accel(need("a_max", a)?, need("alpha_max", alpha)?))
                    }
                }
            }
            other => Err(value_error(format!(
                "unknown base \"{other}\": expected \"holonomic\" or \"diff\""
            ))),
        }
    }
}

/// The options of a floor plan alone, as given: `max_element` (m, the boundary elements'
/// length and the width `δ` of the boundary layer), `centre` and `heading` (a star world has
/// no shortest path to turn towards), and `funnels`.
#[derive(Clone, Debug)]
pub(crate) struct FloorKeywords {
    pub(crate) max_element: f64,
    pub(crate) centre: String,
    pub(crate) heading: String,
    /// Follow a chain of certified funnels (`funnels=True`, docs/maths.md §13.10).
    pub(crate) funnels: bool,
}

impl FloorKeywords {
    /// The floor plan's options for a robot that keeps `options`' `radius + margin` from the
    /// walls, and `options` with the heading policy; the names checked.
    pub(crate) fn check(&self, options: Options) -> PyResult<(FloorOptions, Options)> {
        let floor = FloorOptions::new(self.max_element, options.radius + options.margin)
            .with_centre(policy::<CentrePolicy>(&self.centre)?);
        let options = options.with_heading(policy::<HeadingPolicy>(&self.heading)?);
        Ok((floor, options))
    }

    /// Adds them to `d`, keyword arguments.
    pub(crate) fn add_to(&self, d: &Bound<'_, PyDict>) -> PyResult<()> {
        d.set_item("max_element", self.max_element)?;
        d.set_item("centre", &self.centre)?;
        d.set_item("heading", &self.heading)?;
        d.set_item("funnels", self.funnels)
    }
}

/// `error` raised converting the argument `name`, with the note `while processing 'name'`
/// that pyo3 adds to its own arguments' errors.
fn while_processing(py: Python<'_>, name: &str, error: PyErr) -> PyErr {
    let _ = error.value(py).call_method1(
        intern!(py, "add_note"),
        (format!("while processing '{name}'"),),
    );
    error
}

/// The law named `law` (`"kinematic"` with `gain`, `"dynamic"` with `mass` and `mu`). The
/// arguments the law does not use must still be finite and positive: a NaN left in one is a
/// mistake that would only surface when the law is switched.
fn law_named(law: &str, gain: f64, mass: f64, mu: f64) -> PyResult<Law> {
    let named = match law {
        "kinematic" => Law::kinematic(gain),
        "dynamic" => Law::dynamic(mass, mu),
        other => {
            return Err(value_error(format!(
                "unknown law \"{other}\": expected \"kinematic\" or \"dynamic\""
            )));
        }
    };
    for (name, value) in [("gain", gain), ("mass", mass), ("mu", mu)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(value_error(format!(
                "`{name}` must be finite and positive, got {}",
                Shown(value)
            )));
        }
    }
    Ok(named)
}

/// `free_memory` as a count: a negative one or one beyond 64 bits is refused by name (as
/// `NavError::InvalidOption`, whose message gives the range), not with pyo3's unnamed
/// `OverflowError`; one that is not an integer is a `TypeError` naming it.
fn free_memory_count(free_memory: &Bound<'_, PyAny>) -> PyResult<usize> {
    let invalid = |value: f64| {
        value_error(NavError::InvalidOption {
            field: "free_memory",
            value,
        })
    };
    match integer::<i64>(free_memory, "free_memory", "an integer") {
        Ok(n) => usize::try_from(n).map_err(|_| invalid(n as f64)),
        Err(e) if e.is_instance_of::<PyValueError>(free_memory.py()) => {
            // Beyond i64: its value as a float (±inf beyond the floats) for the message.
            let value = free_memory.extract::<f64>().unwrap_or_else(|_| {
                if free_memory.lt(0).unwrap_or(false) {
                    f64::NEG_INFINITY
                } else {
                    f64::INFINITY
                }
            });
            Err(invalid(value))
        }
        Err(e) => Err(e),
    }
}
