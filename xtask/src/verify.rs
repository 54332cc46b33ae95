//! `cargo xtask verify`: named guarantee checks, each measuring a property of the paper on
//! seeded random inputs and reporting the figure it measured.

mod control;
mod field;
mod potential;
mod scenarios;
mod transform;

use std::process::ExitCode;
use std::sync::Mutex;
use std::time::Instant;

/// What a check measured: `Ok(detail)` if the guarantee holds, `Err(detail)` if not.
pub type Outcome = Result<String, String>;

/// A named guarantee check.
pub struct Check {
    pub name: String,
    pub run: Box<dyn Fn() -> Outcome + Send + Sync>,
}

impl Check {
    /// A check from a name and a function.
    pub fn new(name: impl Into<String>, run: impl Fn() -> Outcome + Send + Sync + 'static) -> Self {
        Self {
            name: name.into(),
            run: Box::new(run),
        }
    }
}

/// Every check, in report order. Later crates append their suites here.
fn checks() -> Vec<Check> {
    let mut all = potential::checks();
    all.extend(transform::checks());
    all.extend(field::checks());
    all.extend(control::checks());
    all.extend(scenarios::checks());
    all
}

pub fn run() -> ExitCode {
    let checks = checks();
    let started = Instant::now();
    let results: Vec<Mutex<Option<(Outcome, f64)>>> =
        checks.iter().map(|_| Mutex::new(None)).collect();
    let next = Mutex::new(0usize);
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get());
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| {
                loop {
                    let i = {
                        let mut next = next.lock().expect("work queue");
                        let i = *next;
                        *next += 1;
                        i
                    };
                    let Some(check) = checks.get(i) else { break };
                    let t = Instant::now();
                    let outcome =
                        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| (check.run)()))
                            .unwrap_or_else(|_| Err("the check panicked".to_string()));
                    *results[i].lock().expect("result slot") =
                        Some((outcome, t.elapsed().as_secs_f64()));
                }
            });
        }
    });
    let width = checks.iter().map(|c| c.name.len()).max().unwrap_or(0);
    println!("{:width$}  result  time    measured", "guarantee");
    let (mut passed, mut failed) = (0, 0);
    for (check, slot) in checks.iter().zip(&results) {
        let (outcome, secs) = slot
            .lock()
            .expect("result slot")
            .take()
            .expect("every check ran");
        let (label, detail) = match outcome {
            Ok(d) => {
                passed += 1;
                ("pass", d)
            }
            Err(d) => {
                failed += 1;
                ("FAIL", d)
            }
        };
        println!("{:width$}  {label:6}  {secs:5.2}s  {detail}", check.name);
    }
    println!(
        "verify: {passed} passed, {failed} failed ({:.1} s)",
        started.elapsed().as_secs_f64()
    );
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// `Ok(detail)` if `ok`, else `Err(detail)`.
pub fn outcome(ok: bool, detail: String) -> Outcome {
    if ok { Ok(detail) } else { Err(detail) }
}
