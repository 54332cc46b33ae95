//! The tables of a study from its per-run records: the one implementation of "tabulate many
//! runs" (issue 28). `cargo xtask quality`, `cargo xtask bench` and `cargo xtask verify`
//! (`quality.*`) turn their runs into [`Record`]s; `python -m harmonav.experiment report`
//! reads the same columns from its Parquet records and calls this module through the Python
//! extension (`harmonav.study_table`, `harmonav.study_cells`).
//!
//! A *cell* is one configuration over its worlds and starts: the generated worlds of one
//! obstacle count are one cell; a scenario file is its own ([`CellKey::world`]). Per cell:
//!
//! - `arrived/runs`, `guarantees held/runs`, collisions summed;
//! - path/shortest and time to goal over the runs that arrived, and integration steps over all
//!   runs: median, 90th percentile and maximum ([`quantiles`], nearest rank);
//! - the dynamic law's time over the kinematic law's under [`REFERENCE_SPEED`] in each world
//!   and start both ran ([`time_ratio`]; a run that did not arrive counts as `+∞`);
//! - the smallest clearance and the largest overshoot of all runs;
//! - when the records carry them: the outcomes of the runs that did not arrive (`stalled`,
//!   `scan-refused`, …: a refused scan is a typed outcome, not a collision) and the perceived
//!   over the true obstacle area of lidar runs (`summary.json`'s `perception.conservatism`).

use std::collections::{BTreeMap, HashMap};

use harmonav::{DampingPolicy, SpeedPolicy};

/// The speed policy of the kinematic law that the dynamic law's time is compared with (the
/// table's "time / kinematic" and the targets of `cargo xtask verify`): the paper's `K√(2Θ)`,
/// the reference the targets were set against (issue 12) before the kinematic law's default
/// speed became `"auto"`, which is 1.6× faster (`docs/benchmarks.md`).
pub const REFERENCE_SPEED: SpeedPolicy = SpeedPolicy::Paper;

/// One run as a study records it: the columns the table reads. `None` is a column the run does
/// not have (a run that could not be made has only its configuration and its `error`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Record {
    /// The world's name: with `start_index`, what pairs a run with its kinematic twin.
    pub world: String,
    /// The world was generated (a cell spans the generated worlds of one obstacle count);
    /// otherwise it is a scenario file, its own cell.
    pub generated: bool,
    /// Obstacle count.
    pub obstacles: Option<u64>,
    /// `"kinematic"` or `"dynamic"`.
    pub law: Option<String>,
    /// Damping policy (read for the dynamic law).
    pub damping: Option<String>,
    /// Speed policy (read for the kinematic law).
    pub speed: Option<String>,
    /// `k` policy.
    pub k: Option<String>,
    /// `"global"`, `"sector"` or `"lidar"`.
    pub sensing: Option<String>,
    /// `robot.margin`, m.
    pub margin: Option<f64>,
    /// `"builtin"` or `"rapier"`.
    pub physics: Option<String>,
    /// `sim.max_time`, s.
    pub max_time: Option<f64>,
    /// Which start of the world (`None`: the world's own).
    pub start_index: Option<i64>,
    /// Why the run could not be made.
    pub error: Option<String>,
    /// Goal reached.
    pub reached: bool,
    /// Time at the end of the run, s.
    pub time_s: Option<f64>,
    /// Path length over the shortest path.
    pub path_over_shortest: Option<f64>,
    /// Smallest clearance to the true shapes, m.
    pub min_clearance: Option<f64>,
    /// Recorded states in collision.
    pub collisions: Option<u64>,
    /// The largest distance the robot got away from the goal again near the end of the run, m
    /// (the benchmark's overshoot).
    pub overshoot: Option<f64>,
    /// Integration steps, accepted and rejected.
    pub steps: Option<u64>,
    /// Every guarantee monitor but arrival held.
    pub guarantees_held: bool,
    /// The cost of one command, µs (a comparison of planners measures it; a run does not).
    pub command_us: Option<f64>,
    /// The run's outcome, as `summary.json`'s `outcome.kind` names it (`reached`, `stalled`,
    /// `scan-refused`, `timed-out`, …; `None`: not recorded).
    pub outcome: Option<String>,
    /// Perceived over true obstacle area at the end of a lidar run (`summary.json`'s
    /// `perception.conservatism`; `None`: no perception, or nothing perceived).
    pub conservatism: Option<f64>,
}

/// What makes a cell: every configuration column but the world's seed and the start.
#[derive(Clone, Debug, PartialEq)]
pub struct CellKey {
    /// The scenario file (`None`: generated worlds, one cell per obstacle count).
    pub world: Option<String>,
    /// Obstacle count.
    pub obstacles: Option<u64>,
    /// Law.
    pub law: Option<String>,
    /// The law's own policy: damping (dynamic) or speed (kinematic).
    pub policy: Option<String>,
    /// `k` policy.
    pub k: Option<String>,
    /// Sensing.
    pub sensing: Option<String>,
    /// Margin, m.
    pub margin: Option<f64>,
    /// Physics.
    pub physics: Option<String>,
    /// Time budget, s.
    pub max_time: Option<f64>,
}

/// [`CellKey`] as something to hash and compare exactly (floats by their bits).
type KeyId = (
    Option<String>,
    Option<u64>,
    Option<String>,
    Option<String>,
    Option<String>,
    Option<String>,
    Option<u64>,
    Option<String>,
    Option<u64>,
);

impl CellKey {
    /// The cell of `r`.
    pub fn of(r: &Record) -> Self {
        let policy = if r.law.as_deref() == Some("dynamic") {
            &r.damping
        } else {
            &r.speed
        };
        Self {
            world: (!r.generated).then(|| r.world.clone()),
            obstacles: r.obstacles,
            law: r.law.clone(),
            policy: policy.clone(),
            k: r.k.clone(),
            sensing: r.sensing.clone(),
            margin: r.margin,
            physics: r.physics.clone(),
            max_time: r.max_time,
        }
    }

    fn id(&self) -> KeyId {
        (
            self.world.clone(),
            self.obstacles,
            self.law.clone(),
            self.policy.clone(),
            self.k.clone(),
            self.sensing.clone(),
            self.margin.map(f64::to_bits),
            self.physics.clone(),
            self.max_time.map(f64::to_bits),
        )
    }

    /// The key of the JSON figures (`cargo xtask bench --json`): `kinematic.auto.global.m12`,
    /// `dynamic.auto.global.m12` under the default speed and damping,
    /// `kinematic-speed-paper.auto.global.m12` and `dynamic-damping-paper.auto.global.m12`
    /// under others, with `.margin0.1` when a margin is set.
    pub fn figure_key(&self) -> String {
        let law = self.law.as_deref().unwrap_or("—");
        let policy = self.policy.as_deref().unwrap_or("—");
        let default = match law {
            "dynamic" => DampingPolicy::default().as_str(),
            _ => SpeedPolicy::default().as_str(),
        };
        let model = match law {
            _ if policy == default => law.to_string(),
            "dynamic" => format!("dynamic-damping-{policy}"),
            _ => format!("{law}-speed-{policy}"),
        };
        let mut key = format!(
            "{model}.{}.{}.m{}",
            self.k.as_deref().unwrap_or("—"),
            self.sensing.as_deref().unwrap_or("—"),
            self.obstacles.map_or("—".to_string(), |m| m.to_string()),
        );
        if let Some(margin) = self.margin.filter(|&m| m > 0.0) {
            key.push_str(&format!(".margin{margin}"));
        }
        key
    }

    /// The law is the dynamic one.
    pub fn is_dynamic(&self) -> bool {
        self.law.as_deref() == Some("dynamic")
    }
}

/// The statistics of one cell over its runs.
#[derive(Clone, Debug, PartialEq)]
pub struct CellStats {
    /// The cell.
    pub key: CellKey,
    /// Runs.
    pub runs: usize,
    /// Runs that could not be made (a record with an `error`).
    pub errors: usize,
    /// Runs that reached the goal.
    pub reached: usize,
    /// Runs in which every guarantee monitor except arrival held.
    pub guarantees_held: usize,
    /// Recorded states in collision, summed.
    pub collisions: u64,
    /// Path / shortest over the runs that arrived: median, 90th percentile, max.
    pub ratio: [f64; 3],
    /// Time to goal over the runs that arrived: median, 90th percentile, max.
    pub time: [f64; 3],
    /// Smallest clearance of all runs (`+∞` when no run measured one; printed `—`).
    pub min_clearance: f64,
    /// Largest overshoot of all runs.
    pub overshoot: f64,
    /// Integration steps (accepted and rejected) per run: median, 90th percentile, max.
    pub steps: [f64; 3],
    /// The cost of one command, µs: median, 90th percentile, max over the runs that measured
    /// it (NaN for none).
    pub command_us: [f64; 3],
    /// Path / shortest of each run that arrived, in record order.
    pub ratios: Vec<f64>,
    /// Time to goal of each run that arrived, in record order.
    pub arrived_times: Vec<f64>,
    /// Time to goal in each (world, start) (`None`: did not arrive), for [`time_ratio`].
    pub times: BTreeMap<(String, Option<i64>), Option<f64>>,
    /// The runs that did not arrive and recorded an outcome, counted by outcome (a run
    /// recorded as `reached` that did not arrive counts as `not-reached`).
    pub not_arrived: BTreeMap<String, usize>,
    /// Perceived over true area: median, 90th percentile, max over the runs that recorded it
    /// (NaN for none).
    pub conservatism: [f64; 3],
}

/// Median, 90th percentile (nearest rank) and maximum; NaN for no values.
pub fn quantiles(values: &[f64]) -> [f64; 3] {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return [f64::NAN; 3];
    }
    let rank = |q: f64| v[((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1];
    [rank(0.5), rank(0.9), v[v.len() - 1]]
}

impl CellStats {
    /// Summarises the runs `runs` of the cell `key`.
    pub fn new(key: CellKey, runs: &[&Record]) -> Self {
        let arrived: Vec<&&Record> = runs.iter().filter(|r| r.reached).collect();
        // A NaN measure is one the run does not have (no shortest path, no clearance of a
        // descent), as `None` is: it is left out, never sorted in as a value.
        let ratios: Vec<f64> = arrived
            .iter()
            .filter_map(|r| r.path_over_shortest)
            .filter(|x| !x.is_nan())
            .collect();
        let arrived_times: Vec<f64> = arrived.iter().filter_map(|r| r.time_s).collect();
        let steps: Vec<f64> = runs
            .iter()
            .filter_map(|r| r.steps)
            .map(|s| s as f64)
            .collect();
        let mut not_arrived = BTreeMap::new();
        for r in runs.iter().filter(|r| !r.reached) {
            if let Some(outcome) = &r.outcome {
                let name = if outcome == "reached" {
                    "not-reached"
                } else {
                    outcome.as_str()
                };
                *not_arrived.entry(name.to_string()).or_insert(0) += 1;
            }
        }
        let conservatism: Vec<f64> = runs
            .iter()
            .filter_map(|r| r.conservatism)
            .filter(|x| !x.is_nan())
            .collect();
        Self {
            key,
            runs: runs.len(),
            errors: runs.iter().filter(|r| r.error.is_some()).count(),
            reached: arrived.len(),
            guarantees_held: runs.iter().filter(|r| r.guarantees_held).count(),
            collisions: runs.iter().filter_map(|r| r.collisions).sum(),
            ratio: quantiles(&ratios),
            time: quantiles(&arrived_times),
            min_clearance: runs
                .iter()
                .filter_map(|r| r.min_clearance)
                .fold(f64::INFINITY, f64::min),
            overshoot: runs.iter().filter_map(|r| r.overshoot).fold(0.0, f64::max),
            steps: quantiles(&steps),
            command_us: quantiles(&runs.iter().filter_map(|r| r.command_us).collect::<Vec<_>>()),
            ratios,
            arrived_times,
            times: runs
                .iter()
                .map(|r| {
                    let t = if r.reached { r.time_s } else { None };
                    ((r.world.clone(), r.start_index), t)
                })
                .collect(),
            not_arrived,
            conservatism: quantiles(&conservatism),
        }
    }
}

/// The cells of `records`, ordered by world, obstacle count, law, sensing, `k`, margin, the
/// law's policy, physics and time budget, each in the order the records first give its values
/// (so records made in a plan's order keep the plan's order).
pub fn cells(records: &[Record]) -> Vec<CellStats> {
    // The rank of each distinct value of each key component, in order of first appearance (a
    // policy is ranked among its own law's policies): hashed, so that 10⁶ records over 10³
    // scenario files cost one lookup per component and record.
    let mut order: [HashMap<KeyPart, usize>; 9] = Default::default();
    let mut grouped: HashMap<KeyId, (CellKey, Vec<&Record>)> = HashMap::new();
    for r in records {
        let key = CellKey::of(r);
        let id = key.id();
        for (i, part) in key_parts(&id).into_iter().enumerate() {
            let next = order[i].len();
            order[i].entry(part).or_insert(next);
        }
        grouped
            .entry(id)
            .or_insert_with(|| (key, Vec::new()))
            .1
            .push(r);
    }
    let rank = |id: &KeyId| -> [usize; 9] {
        let parts = key_parts(id);
        // world, M, law, sensing, k, margin, policy, physics, max time
        [0, 1, 2, 5, 4, 6, 3, 7, 8].map(|i| order[i][&parts[i]])
    };
    let mut groups: Vec<_> = grouped
        .into_iter()
        .map(|(id, group)| (rank(&id), group))
        .collect();
    groups.sort_by_key(|(rank, _)| *rank);
    groups
        .into_iter()
        .map(|(_, (key, runs))| CellStats::new(key, &runs))
        .collect()
}

/// One component of a [`KeyId`], comparable with the others of its position.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum KeyPart {
    Text(Option<String>),
    Number(Option<u64>),
    Policy(Option<String>, Option<String>),
}

fn key_parts(id: &KeyId) -> [KeyPart; 9] {
    use KeyPart::{Number, Policy, Text};
    [
        Text(id.0.clone()),
        Number(id.1),
        Text(id.2.clone()),
        Policy(id.2.clone(), id.3.clone()),
        Text(id.4.clone()),
        Text(id.5.clone()),
        Number(id.6),
        Text(id.7.clone()),
        Number(id.8),
    ]
}

/// The time of `cell` over the time of `reference` in each world and start both ran: median,
/// 90th percentile and maximum. A run that `cell` did not finish counts as `+∞` (so arrival
/// failures show in the quantiles instead of vanishing); one that `reference` did not finish
/// is left out.
pub fn time_ratio(cell: &CellStats, reference: &CellStats) -> [f64; 3] {
    let ratios: Vec<f64> = cell
        .times
        .iter()
        .filter_map(|(at, t)| {
            let r = (*reference.times.get(at)?)?;
            Some(t.unwrap_or(f64::INFINITY) / r)
        })
        .collect();
    quantiles(&ratios)
}

/// The kinematic cell under the speed policy `speed` with the same worlds, sensing, `k`,
/// margin, physics and time budget as `cell`, if `cells` has it.
pub fn kinematic_twin<'a>(
    cells: &'a [CellStats],
    cell: &CellKey,
    speed: SpeedPolicy,
) -> Option<&'a CellStats> {
    let twin = CellKey {
        law: Some("kinematic".to_string()),
        policy: Some(speed.as_str().to_string()),
        ..cell.clone()
    };
    cells.iter().find(|c| c.key == twin)
}

fn fixed(x: f64, digits: usize) -> String {
    format!("{x:.digits$}")
}

fn fmt3(v: [f64; 3], digits: usize) -> String {
    v.map(|x| fixed(x, digits)).join(" / ")
}

fn text(v: &Option<String>) -> String {
    v.clone().unwrap_or_else(|| "—".to_string())
}

/// The header of [`table`] without its optional columns.
pub const HEADER: &str = "| law | damping or speed | k | sensing | margin | M | arrived | \
guarantees held | collisions | path/shortest median / p90 / max | time to goal median / p90 / \
max (s) | time / kinematic (paper speed) median / p90 / max | min clearance (m) | overshoot (m) \
| steps median / p90 / max |";

/// The outcomes of the runs that did not arrive, `scan-refused 3, stalled 1` (`—`: none).
pub fn not_arrived_text(c: &CellStats) -> String {
    if c.not_arrived.is_empty() {
        return "—".to_string();
    }
    c.not_arrived
        .iter()
        .map(|(outcome, n)| format!("{outcome} {n}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The Markdown table of `cells` (docs/benchmarks.md), with a leading `world` column when a cell
/// is a scenario file, and `physics`, `max time (s)`, `µs per command`, `not arrived` (the
/// outcomes of the runs that did not arrive), `perceived/true area` and `errors` columns when
/// they vary or occur.
pub fn table(cells: &[CellStats]) -> String {
    let world_col = cells.iter().any(|c| c.key.world.is_some());
    let varies = |f: fn(&CellKey) -> KeyPart| {
        cells
            .first()
            .is_some_and(|a| cells.iter().any(|c| f(&c.key) != f(&a.key)))
    };
    let physics_col = varies(|k| KeyPart::Text(k.physics.clone()));
    let time_col = varies(|k| KeyPart::Number(k.max_time.map(f64::to_bits)));
    let cost_col = cells.iter().any(|c| !c.command_us[0].is_nan());
    let outcome_col = cells.iter().any(|c| !c.not_arrived.is_empty());
    let area_col = cells.iter().any(|c| !c.conservatism[0].is_nan());
    let error_col = cells.iter().any(|c| c.errors > 0);
    let front: Vec<&str> = if world_col { vec!["world"] } else { vec![] };
    let mut back: Vec<&str> = Vec::new();
    if physics_col {
        back.push("physics");
    }
    if time_col {
        back.push("max time (s)");
    }
    if cost_col {
        back.push("µs per command median / p90 / max");
    }
    if outcome_col {
        back.push("not arrived");
    }
    if area_col {
        back.push("perceived/true area median / p90 / max");
    }
    if error_col {
        back.push("errors");
    }
    let mut head = HEADER.to_string();
    if !front.is_empty() {
        head = format!("| {} {head}", front.join(" | "));
    }
    if !back.is_empty() {
        head = format!("{head} {} |", back.join(" | "));
    }
    let columns = HEADER.matches('|').count() - 1 + front.len() + back.len();
    let mut out = format!("{head}\n|{}\n", "---|".repeat(columns));
    for c in cells {
        let k = &c.key;
        let ratio = match kinematic_twin(cells, k, REFERENCE_SPEED) {
            Some(twin) if k.is_dynamic() => fmt3(time_ratio(c, twin), 2),
            _ => "—".to_string(),
        };
        let law = k.law.as_deref().map_or("—".to_string(), capitalised);
        let mut row: Vec<String> = Vec::new();
        if world_col {
            row.push(text(&k.world));
        }
        row.extend([
            law,
            text(&k.policy),
            text(&k.k),
            text(&k.sensing),
            k.margin.map_or("—".to_string(), |m| m.to_string()),
            k.obstacles.map_or("—".to_string(), |m| m.to_string()),
            format!("{}/{}", c.reached, c.runs),
            format!("{}/{}", c.guarantees_held, c.runs),
            c.collisions.to_string(),
            fmt3(c.ratio, 3),
            fmt3(c.time, 1),
            ratio,
            if c.min_clearance.is_finite() {
                fixed(c.min_clearance, 4)
            } else {
                "—".to_string()
            },
            format!("{:.1e}", c.overshoot),
            fmt3(c.steps, 0),
        ]);
        if physics_col {
            row.push(text(&k.physics));
        }
        if time_col {
            row.push(k.max_time.map_or("—".to_string(), |t| t.to_string()));
        }
        if cost_col {
            row.push(fmt3(c.command_us, 1));
        }
        if outcome_col {
            row.push(not_arrived_text(c));
        }
        if area_col {
            row.push(if c.conservatism[0].is_nan() {
                "—".to_string()
            } else {
                fmt3(c.conservatism, 2)
            });
        }
        if error_col {
            row.push(c.errors.to_string());
        }
        out.push_str(&format!("| {} |\n", row.join(" | ")));
    }
    out
}

/// `kinematic` → `Kinematic`.
fn capitalised(s: &str) -> String {
    let mut chars = s.chars();
    chars.next().map_or(String::new(), |f| {
        f.to_uppercase().chain(chars.as_str().chars()).collect()
    })
}
