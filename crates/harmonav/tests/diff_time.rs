//! A measurement, not a test of a claim (ignored): the time a differential-drive robot takes
//! in the worlds of a `bench/diff/run.py` record, against the record's HL and holonomic
//! times, without navground (docs/unicycle.md section 11). The worlds come from
//! `scripts/diff_worlds.py` (the record's worlds bit for bit, with its reference times):
//!
//! ```sh
//! python3 scripts/diff_worlds.py diff-uniform.json > /tmp/uniform.txt
//! HARMONAV_DIFF_WORLDS=/tmp/uniform.txt cargo test -p harmonav --release --test diff_time \
//!     -- --ignored --nocapture
//! ```
//!
//! The loop is `run.py`'s harmonav entry: arrival (centre within 1 cm) is checked before each
//! command, 120 s at most, each `(v, ω)` held on its exact arc, the body's true clearance to the
//! discs and the arena sampled at 201 points of every arc. `HARMONAV_DIFF_TRACE=SEED` prints
//! that world's commands one per line; `HARMONAV_DIFF_ACCEL=a,alpha` gives
//! the base acceleration limits; `HARMONAV_DIFF_HEADINGS=away` only that heading.

use harmonav::{Base, Law, Navigator, Options, StarShape, Steer, Vector2, unicycle_arc};

const ARENA: f64 = 5.0;
const RADIUS: f64 = 0.18;
const V_MAX: f64 = 0.5;
const OMEGA_MAX: f64 = 2.0;
const PERIOD: f64 = 0.1;
const T_MAX: f64 = 120.0;
const ARC_POINTS: usize = 201;

struct World {
    seed: u64,
    margin: f64,
    hl: [f64; 2],
    holonomic: f64,
    recorded: [f64; 2],
    start: Vector2<f64>,
    goal: Vector2<f64>,
    yaw: f64,
    discs: Vec<(Vector2<f64>, f64)>,
}

fn parse(line: &str) -> World {
    let f: Vec<f64> = line
        .split_whitespace()
        .map(|s| s.parse().expect("a number"))
        .collect();
    let n = f[12] as usize;
    World {
        seed: f[0] as u64,
        margin: f[1],
        hl: [f[2], f[3]],
        holonomic: f[4],
        recorded: [f[5], f[6]],
        start: Vector2::new(f[7], f[8]),
        goal: Vector2::new(f[9], f[10]),
        yaw: f[11],
        discs: (0..n)
            .map(|i| (Vector2::new(f[13 + 3 * i], f[14 + 3 * i]), f[15 + 3 * i]))
            .collect(),
    }
}

fn clearance(w: &World, p: Vector2<f64>) -> f64 {
    w.discs
        .iter()
        .map(|(c, r)| (p - c).norm() - r)
        .fold(ARENA - p.norm(), f64::min)
        - RADIUS
}

#[derive(Debug, Default)]
struct Run {
    time: Option<f64>,
    least: f64,
    contacts: usize,
    below: usize,
    path: f64,
    steer: [usize; 5],
}

fn fly(w: &World, yaw: f64, accel: Option<(f64, f64)>, trace: bool) -> Run {
    let mut base = Base::diff(V_MAX, OMEGA_MAX);
    if let Some((a, alpha)) = accel {
        base = base.with_accel(a, alpha);
    }
    let options = Options::default()
        .with_robot(RADIUS, w.margin)
        .with_control_period(PERIOD)
        .with_v_max(V_MAX)
        .with_base(base);
    let boundary = StarShape::circle(Vector2::zeros(), ARENA).unwrap();
    let mut nav = Navigator::new(boundary, w.goal, Law::kinematic(1.0), options).unwrap();
    for (c, r) in &w.discs {
        nav.add_obstacle(StarShape::circle(*c, *r).unwrap())
            .unwrap();
    }
    let (mut x, mut yaw) = (w.start, yaw);
    let mut run = Run {
        least: f64::INFINITY,
        ..Run::default()
    };
    let steps = (T_MAX / PERIOD).round() as usize;
    let mut t = 0.0;
    for _ in 0..=steps {
        if (x - w.goal).norm() <= 0.01 {
            run.time = Some(t);
            break;
        }
        if t >= T_MAX - 1e-9 {
            break;
        }
        let held = if trace {
            let u = nav.clone().command(x, Vector2::zeros()).unwrap().value;
            let f = nav.evaluate(x, Vector2::zeros()).unwrap().field;
            let d = f.direction.unwrap_or_default();
            (u.y.atan2(u.x), u.norm(), f.phi, d.y.atan2(d.x))
        } else {
            (0.0, 0.0, 0.0, 0.0)
        };
        let c = nav.command_pose(x, yaw).unwrap();
        run.steer[match c.steer {
            Steer::Ahead => 0,
            Steer::Shortened { .. } => 1,
            Steer::Turning => 2,
            Steer::Stopped => 3,
            _ => 4,
        }] += 1;
        let low = (0..ARC_POINTS)
            .map(|i| {
                let s = PERIOD * i as f64 / (ARC_POINTS - 1) as f64;
                clearance(w, unicycle_arc(x, yaw, c.v, c.omega, s).0)
            })
            .fold(f64::INFINITY, f64::min);
        if trace {
            println!(
                "t {t:6.1} x ({:+.4}, {:+.4}) yaw {:+.3} d_h {:+.3} d {:+.3} |u_h| {:.2e} phi_k {:.6} v {:.4} w {:+.3} {:?} {:?} clear {:.4} goal {:.3}",
                x.x,
                x.y,
                yaw.sin().atan2(yaw.cos()),
                held.0,
                held.3,
                held.1,
                held.2,
                c.v,
                c.omega,
                c.steer,
                c.mode,
                low,
                (x - w.goal).norm()
            );
        }
        run.least = run.least.min(low);
        run.contacts += usize::from(low <= 0.0);
        run.below += usize::from(low < w.margin - 1e-6);
        run.path += c.v * PERIOD;
        (x, yaw) = unicycle_arc(x, yaw, c.v, c.omega, PERIOD);
        t += PERIOD;
    }
    run
}

/// numpy's `percentile` (linear interpolation).
fn percentile(v: &[f64], p: f64) -> f64 {
    let mut v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let r = p / 100.0 * (v.len() - 1) as f64;
    let (lo, hi) = (r.floor() as usize, r.ceil() as usize);
    v[lo] + (v[hi] - v[lo]) * (r - lo as f64)
}

#[test]
#[ignore = "a measurement: give HARMONAV_DIFF_WORLDS"]
fn time_against_the_record() {
    let Ok(path) = std::env::var("HARMONAV_DIFF_WORLDS") else {
        println!("HARMONAV_DIFF_WORLDS not given");
        return;
    };
    let worlds: Vec<World> = std::fs::read_to_string(&path)
        .unwrap()
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(parse)
        .collect();
    let trace: Option<u64> = std::env::var("HARMONAV_DIFF_TRACE")
        .ok()
        .and_then(|s| s.parse().ok());
    let accel = std::env::var("HARMONAV_DIFF_ACCEL").ok().map(|s| {
        let v: Vec<f64> = s.split(',').map(|p| p.parse().unwrap()).collect();
        (v[0], v[1])
    });
    let headings = std::env::var("HARMONAV_DIFF_HEADINGS").unwrap_or("random,away".into());
    for (h, heading) in ["random", "away"].iter().enumerate() {
        if !headings.contains(heading) {
            continue;
        }
        let (mut hl, mut holo, mut rec, mut times) = (vec![], vec![], vec![], vec![]);
        let (mut arrived, mut contacts, mut below) = (0, 0, 0);
        let mut least = f64::INFINITY;
        let mut steer = [0; 5];
        for w in &worlds {
            if trace.is_some_and(|s| s != w.seed) {
                continue;
            }
            let yaw = if h == 0 {
                w.yaw
            } else {
                let d = w.start - w.goal;
                d.y.atan2(d.x)
            };
            let run = fly(w, yaw, accel, trace == Some(w.seed));
            let t = run.time.unwrap_or(f64::NAN);
            println!(
                "{heading} seed {:2}: time {t:6.1} (recorded {:6.1}) HL {:5.1} ratio {:.3} holonomic {:5.1} least {:+.4} steer {:?}",
                w.seed,
                w.recorded[h],
                w.hl[h],
                t / w.hl[h],
                w.holonomic,
                run.least,
                run.steer
            );
            arrived += usize::from(run.time.is_some());
            contacts += usize::from(run.contacts > 0);
            below += usize::from(run.below > 0);
            least = least.min(run.least);
            for (a, b) in steer.iter_mut().zip(run.steer) {
                *a += b;
            }
            hl.push(t / w.hl[h]);
            holo.push(t / w.holonomic);
            rec.push(t / w.recorded[h]);
            times.push(t);
        }
        let total: usize = steer.iter().sum();
        println!(
            "{heading}: arrived {arrived}/{}, runs with contact {contacts}, below the margin {below}, \
             least clearance {:+.1} mm; time median {:.1} p90 {:.1} s; / HL median {:.3} p90 {:.3}; \
             / holonomic median {:.3} p90 {:.3}; / recorded harmonav median {:.3}; \
             steer ahead/shortened/turning/stopped/braking {:?} of {total}",
            worlds.len(),
            least * 1e3,
            percentile(&times, 50.0),
            percentile(&times, 90.0),
            percentile(&hl, 50.0),
            percentile(&hl, 90.0),
            percentile(&holo, 50.0),
            percentile(&holo, 90.0),
            percentile(&rec, 50.0),
            steer
        );
    }
}
