//! Golden command traces (issue 51): the user's loop driven for a fixed number of control
//! periods, every state and command written as raw bits, so that a refactor that must not
//! change behaviour can be checked bit for bit (`cargo xtask traces OUT`, then `cmp`).
//!
//! The loop is the one a user writes: at every period `h` (the navigator's control period)
//! the robot perceives, asks the navigator for its command, and holds it — `x += h·u`
//! (kinematic) or `v += h·f/m, x += h·v` (dynamic, semi-implicit Euler). Perception is the
//! file's: the sector sensor of a star world (its discoveries at the state of the last
//! command), the exact obstacles within `sim.sensor_range` on a floor plan, or the lidar's
//! scans when they are due. Nothing is judged: a trace records what the navigator did.
//!
//! One line per period: `t x.x x.y v.x v.y command.x command.y mode`, each number as the 16
//! hex digits of `f64::to_bits`; then `end <why>` (the periods ran out, the goal was reached
//! within 1e-9 m, or the navigator's error).

use std::fmt::Write as _;

use harmonav::Controller;
use harmonav::perception::sim::Enclosure;
use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_scenario::{Model, Prepared};
use nalgebra::Vector2;

use crate::closed_loop::ClosedLoop;
use crate::scanner::{Scanner, Scene};

/// One period of a trace, appended to `out` as a line of raw bits.
fn line(out: &mut String, t: f64, x: Vector2<f64>, v: Vector2<f64>, c: Vector2<f64>, mode: &str) {
    for z in [t, x.x, x.y, v.x, v.y, c.x, c.y] {
        let _ = write!(out, "{:016x} ", z.to_bits());
    }
    let _ = writeln!(out, "{mode}");
}

/// The held step of `controller` over `h` from `(x, v)` under `command`.
pub(crate) fn held(
    controller: &Controller,
    h: f64,
    x: Vector2<f64>,
    v: Vector2<f64>,
    command: Vector2<f64>,
) -> (Vector2<f64>, Vector2<f64>) {
    match controller {
        Controller::Kinematic(_) => (x + h * command, command),
        Controller::Dynamic(law) => {
            let v = v + h * command / law.mass();
            (x + h * v, v)
        }
    }
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
    for n in 0..periods {
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
        let c = match lp.nav.command(x, v) {
            Ok(c) => c,
            Err(e) => {
                let _ = writeln!(out, "end {e}");
                return Ok(out);
            }
        };
        line(&mut out, t, x, v, c.value, c.mode.as_str());
        (x, v) = held(lp.nav.controller(), h, x, v, c.value);
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
    let mut yaw = 0.0;
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
        let c = match nav.command(x, v) {
            Ok(c) => c,
            Err(e) => {
                let _ = writeln!(out, "end {e}");
                return Ok(out);
            }
        };
        line(&mut out, t, x, v, c.value, c.mode.as_str());
        let next;
        (next, v) = held(nav.controller(), h, x, v, c.value);
        if next != x {
            yaw = (next.y - x.y).atan2(next.x - x.x);
        }
        x = next;
    }
    out.push_str("end periods\n");
    Ok(out)
}
