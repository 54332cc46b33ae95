//! Golden command traces (issue 51): the user's loop driven for a fixed number of control
//! periods, every state and command written as raw bits, so that a refactor that must not
//! change behaviour can be checked bit for bit (`cargo xtask traces OUT`, then `cmp`).
//!
//! The loop is the one a user writes: at every period `h` (the navigator's control period)
//! the robot perceives, asks the navigator for its command, and holds it — `x += h·u`
//! (kinematic) or `v += h·f/m, x += h·v` (dynamic, semi-implicit Euler). Perception is the
//! file's: the sector sensor of a star world (its discoveries at the state of the last
//! command), the exact obstacles within `sim.sensor_range` on a floor plan, or the lidar's
//! scans when they are due. A file's movers (`[[movers]]`) are reported to the navigator
//! before every command (`set_movers`, as `crate::held` does) and move by their scripts; a
//! differential drive (`[robot] base = "diff"`) asks `command_pose` from its heading and moves
//! on the exact arc. (`[[robots]]`: the first robot alone.) Nothing is judged: a trace records
//! what the navigator did.
//!
//! One line per period: `t x.x x.y v.x v.y command.x command.y mode`, each number as the 16
//! hex digits of `f64::to_bits` (a differential drive's command is `(v, ω)`); then `end <why>`
//! (the periods ran out, the goal was reached within 1e-9 m, or the navigator's error).

use std::fmt::Write as _;

use harmonav::perception::sim::Enclosure;
use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_scenario::{Model, Prepared};
use nalgebra::Vector2;

use crate::closed_loop::ClosedLoop;
use crate::movers::MoverWorld;
use crate::scanner::{Scanner, Scene};
use crate::step::{arc_step, held};

/// One period of a trace, appended to `out` as a line of raw bits.
fn line(out: &mut String, t: f64, x: Vector2<f64>, v: Vector2<f64>, c: Vector2<f64>, mode: &str) {
    for z in [t, x.x, x.y, v.x, v.y, c.x, c.y] {
        let _ = write!(out, "{:016x} ", z.to_bits());
    }
    let _ = writeln!(out, "{mode}");
}

/// One period of a trace: the command (a differential drive's `(v, ω)`), its mode, and the
/// position and velocity after its hold.
struct Step {
    command: Vector2<f64>,
    mode: &'static str,
    x: Vector2<f64>,
    v: Vector2<f64>,
}

/// A period's command, either base's, from `(x, v)` and the heading `yaw` (a differential
/// drive's, updated to the arc's end), held for the control period.
fn command_and_hold<W: harmonav::World>(
    nav: &mut harmonav::Navigator<W>,
    diff: bool,
    (x, v): (Vector2<f64>, Vector2<f64>),
    yaw: &mut f64,
) -> Result<Step, harmonav::NavError> {
    let h = nav.control_period();
    if diff {
        let c = nav.command_pose(x, *yaw)?;
        let (next, turned, vel) = arc_step(x, *yaw, c.v, c.omega, h);
        *yaw = turned;
        return Ok(Step {
            command: Vector2::new(c.v, c.omega),
            mode: c.mode.as_str(),
            x: next,
            v: vel,
        });
    }
    let c = nav.command(x, v)?;
    let (next, vel) = held(nav.controller(), h, x, v, c.value);
    Ok(Step {
        command: c.value,
        mode: c.mode.as_str(),
        x: next,
        v: vel,
    })
}

/// The trace of a star world's robot under `model` from the file's start, `periods` periods.
///
/// # Errors
/// The navigator could not be built or take its first discoveries (the message).
pub fn star(prepared: &Prepared, model: Model, periods: usize) -> Result<String, String> {
    let (mut lp, _) = ClosedLoop::start(prepared, Some(model), None).map_err(|e| e.to_string())?;
    let h = lp.nav.control_period();
    let (mut x, mut v) = (prepared.start(), Vector2::zeros());
    let goal = lp.nav.goal();
    let mut out = String::new();
    let mut log = Vec::new();
    let mut movers = MoverWorld::new(&prepared.scenario.sim.movers, prepared.truth.radius);
    let diff = prepared.base().is_some();
    let mut yaw = prepared.start_yaw();
    for n in 0..periods {
        lp.heading = diff.then_some(yaw);
        let t = n as f64 * h;
        if (x - goal).norm() < 1e-9 {
            out.push_str("end reached\n");
            return Ok(out);
        }
        let scanned = match lp.scanner.as_ref().map(|s| s.due(t)) {
            Some(true) => lp.scan(t, x, v).map(|r| r.map(|_| ())),
            _ => None,
        };
        if let Some(Err(e)) = scanned {
            let _ = writeln!(out, "end scan refused: {e}");
            return Ok(out);
        }
        if lp.scanner.is_none() {
            let seen = lp.sees(x, v);
            let axis = lp.axis(x, v);
            if lp.discover(t, &seen, (x, v), axis, &mut log).is_err() {
                out.push_str("end discovery refused\n");
                return Ok(out);
            }
        }
        if !movers.is_empty()
            && let Err(e) = lp.nav.set_movers(movers.reports())
        {
            let _ = writeln!(out, "end {e}");
            return Ok(out);
        }
        let step = match command_and_hold(&mut lp.nav, diff, (x, v), &mut yaw) {
            Ok(step) => step,
            Err(e) => {
                let _ = writeln!(out, "end {e}");
                return Ok(out);
            }
        };
        line(&mut out, t, x, v, step.command, step.mode);
        movers.period(x, step.x, h, true);
        (x, v) = (step.x, step.v);
    }
    out.push_str("end periods\n");
    Ok(out)
}

/// The trace of a floor plan's robot under `model` from `start`, `periods` periods.
///
/// # Errors
/// The navigator could not be built (the message).
pub fn floor(
    prepared: &FloorPrepared,
    model: Model,
    start: Vector2<f64>,
    periods: usize,
) -> Result<String, String> {
    let (mut nav, lidar) =
        crate::floor::navigator_and_lidar(prepared, Some(model)).map_err(|e| e.to_string())?;
    let mut scanner = lidar.map(Scanner::new);
    let walls = nav.walls().clone();
    let h = nav.control_period();
    let range = prepared.scenario.sim.sensor_range;
    let radius = prepared.scenario.robot.radius;
    let (mut x, mut v) = (start, Vector2::zeros());
    let goal = nav.goal();
    let mut known = vec![false; prepared.obstacles.len()];
    let diff = prepared.base().is_some();
    let mut yaw = if diff { prepared.start_yaw() } else { 0.0 };
    let mut movers = MoverWorld::new(&prepared.scenario.movers, radius);
    let mut out = String::new();
    for n in 0..periods {
        let t = n as f64 * h;
        if (x - goal).norm() < 1e-9 {
            out.push_str("end reached\n");
            return Ok(out);
        }
        if let Some(s) = scanner.as_mut().filter(|s| s.due(t)) {
            let scene = Scene {
                obstacles: &prepared.obstacles,
                enclosure: Enclosure::Walls(&walls),
            };
            if let Err(e) = s.scan(&mut nav, scene, t, x, yaw) {
                let _ = writeln!(out, "end scan refused: {e}");
                return Ok(out);
            }
        }
        if scanner.is_none() {
            for (o, seen) in prepared.obstacles.iter().zip(&mut known) {
                if !*seen && o.signed_distance(x) - radius < range {
                    if let Err(e) = nav.add_obstacle(o.clone()) {
                        let _ = writeln!(out, "end discovery refused: {e}");
                        return Ok(out);
                    }
                    *seen = true;
                }
            }
        }
        if !movers.is_empty()
            && let Err(e) = nav.set_movers(movers.reports())
        {
            let _ = writeln!(out, "end {e}");
            return Ok(out);
        }
        let step = match command_and_hold(&mut nav, diff, (x, v), &mut yaw) {
            Ok(step) => step,
            Err(e) => {
                let _ = writeln!(out, "end {e}");
                return Ok(out);
            }
        };
        line(&mut out, t, x, v, step.command, step.mode);
        movers.period(x, step.x, h, true);
        if !diff && step.x != x {
            yaw = (step.x.y - x.y).atan2(step.x.x - x.x);
        }
        (x, v) = (step.x, step.v);
    }
    out.push_str("end periods\n");
    Ok(out)
}
