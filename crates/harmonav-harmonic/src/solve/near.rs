//! The near block `G_near` of the iterative solve, rows by collocation point, stored by runs of
//! consecutive columns.
//!
//! A collocation point's near elements are the pieces of the rings that cross the 3 × 3 leaves
//! about it, and a ring's elements are numbered along it, so a row's sorted columns come in a
//! few runs of consecutive elements (a wall passing by, its facing wall, a pillar). Storing each
//! run as `(first column, length)` instead of one `u32` per entry leaves 8 bytes per entry
//! instead of 12: the product streams the whole block once per GMRES iteration (30 million
//! entries, 360 MB on `willow-full`), which was a quarter of its set-up (docs/benchmarks.md,
//! "Set-up of the large maps"). A row is summed in four interleaved partial sums
//! ([`NearMatrix::add_row`]), which the processor overlaps: 3 % of `willow-full`'s set-up.

/// The partial sums of a row ([`NearMatrix::add_row`]).
const LANES: usize = 4;

/// `acc[k mod LANES] += v_k·x_k` over a run, its remainder into lane 0.
fn lanes(acc: &mut [f64; LANES], values: &[f64], x: &[f64]) {
    let (mut v, mut p) = (values.chunks_exact(LANES), x.chunks_exact(LANES));
    for (v, p) in (&mut v).zip(&mut p) {
        for k in 0..LANES {
            acc[k] += v[k] * p[k];
        }
    }
    for (v, p) in v.remainder().iter().zip(p.remainder()) {
        acc[0] += v * p;
    }
}

/// The lanes' sum, pairwise.
fn total(acc: [f64; LANES]) -> f64 {
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// A run of consecutive columns `first..first + len` of one row.
#[derive(Clone, Copy, Debug)]
struct Run {
    first: u32,
    len: u32,
}

/// `G_near`: row `i`'s runs are `runs[run_start[i]..run_start[i + 1]]`, their values
/// `values[value_start[i]..]` in the same order.
#[derive(Debug, Default)]
pub(super) struct NearMatrix {
    run_start: Vec<usize>,
    value_start: Vec<usize>,
    runs: Vec<Run>,
    values: Vec<f64>,
}

impl NearMatrix {
    /// An empty matrix of no rows.
    pub(super) fn new() -> Self {
        Self {
            run_start: vec![0],
            value_start: vec![0],
            runs: Vec::new(),
            values: Vec::new(),
        }
    }

    /// Appends a row: `columns` strictly increasing, one value each.
    pub(super) fn push_row(&mut self, columns: &[u32], values: &[f64]) {
        debug_assert_eq!(columns.len(), values.len());
        let mut k = 0;
        while k < columns.len() {
            let first = columns[k];
            let mut len = 1;
            while k + len < columns.len() && columns[k + len] == first + len as u32 {
                len += 1;
            }
            self.runs.push(Run {
                first,
                len: len as u32,
            });
            k += len;
        }
        self.values.extend_from_slice(values);
        self.run_start.push(self.runs.len());
        self.value_start.push(self.values.len());
    }

    /// Appends every row of `other` after this matrix's rows.
    pub(super) fn append(&mut self, other: Self) {
        let (runs, values) = (self.runs.len(), self.values.len());
        self.run_start
            .extend(other.run_start[1..].iter().map(|s| s + runs));
        self.value_start
            .extend(other.value_start[1..].iter().map(|s| s + values));
        self.runs.extend(other.runs);
        self.values.extend(other.values);
    }

    /// `s + Σ_e G_near[i][col_e]·x[col_e]`, the entries summed in [`LANES`] interleaved
    /// partial sums (entry `k` of each run into lane `k mod LANES`, the run's remainder into
    /// lane 0), added pairwise at the end: independent chains the processor overlaps, where one
    /// running sum waited on each addition before the next.
    pub(super) fn add_row(&self, i: usize, x: &[f64], s: f64) -> f64 {
        let mut acc = [0.0; LANES];
        let mut e = self.value_start[i];
        for run in &self.runs[self.run_start[i]..self.run_start[i + 1]] {
            let (first, len) = (run.first as usize, run.len as usize);
            lanes(&mut acc, &self.values[e..e + len], &x[first..first + len]);
            e += len;
        }
        s + total(acc)
    }

    /// [`NearMatrix::add_row`] for two vectors in one pass over the row's entries: each sum
    /// is `add_row`'s bit for bit (the same lanes in the same order).
    pub(super) fn add_row2(&self, i: usize, x: [&[f64]; 2], s: [f64; 2]) -> [f64; 2] {
        let (mut a0, mut a1) = ([0.0; LANES], [0.0; LANES]);
        let mut e = self.value_start[i];
        for run in &self.runs[self.run_start[i]..self.run_start[i + 1]] {
            let (first, len) = (run.first as usize, run.len as usize);
            let values = &self.values[e..e + len];
            let (x0, x1) = (&x[0][first..first + len], &x[1][first..first + len]);
            let mut v = values.chunks_exact(LANES);
            let (mut p, mut q) = (x0.chunks_exact(LANES), x1.chunks_exact(LANES));
            for ((v, p), q) in (&mut v).zip(&mut p).zip(&mut q) {
                for k in 0..LANES {
                    a0[k] += v[k] * p[k];
                    a1[k] += v[k] * q[k];
                }
            }
            for ((v, p), q) in v.remainder().iter().zip(p.remainder()).zip(q.remainder()) {
                a0[0] += v * p;
                a1[0] += v * q;
            }
            e += len;
        }
        [s[0] + total(a0), s[1] + total(a1)]
    }

    /// The stored entries.
    #[cfg(test)]
    fn entries(&self) -> usize {
        self.values.len()
    }

    /// The stored runs.
    #[cfg(test)]
    fn run_count(&self) -> usize {
        self.runs.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows of scattered and consecutive columns (runs shorter and longer than the lanes)
    /// give the sums of their entries (small integers and halves, so every order of summing
    /// is exact), and two appended halves the whole.
    #[test]
    fn rows_by_runs_are_the_rows_of_entries() {
        let long: Vec<u32> = (3..16).collect();
        let rows: Vec<(Vec<u32>, Vec<f64>)> = vec![
            (vec![0, 1, 2, 5, 7, 8], vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
            (vec![], vec![]),
            (vec![3], vec![0.5]),
            (
                long.clone(),
                long.iter().map(|&c| f64::from(c) - 7.5).collect(),
            ),
            (
                [0, 1].into_iter().chain(long.iter().copied()).collect(),
                (0..15).map(|k| f64::from(k % 5) - 2.0).collect(),
            ),
        ];
        let x: Vec<f64> = (0..16).map(|k| f64::from(k % 7) - 3.0).collect();
        let mut first = NearMatrix::new();
        let mut second = NearMatrix::new();
        for (i, (c, v)) in rows.iter().enumerate() {
            if i < 2 {
                first.push_row(c, v);
            } else {
                second.push_row(c, v);
            }
        }
        first.append(second);
        assert_eq!(first.entries(), 6 + 1 + 13 + 15);
        // Runs: [0..3], [5], [7..9]; none; [3]; [3..16]; [0..2], [3..16].
        assert_eq!(first.run_count(), 7);
        for (i, (c, v)) in rows.iter().enumerate() {
            let mut s = 0.25;
            for (cj, vj) in c.iter().zip(v) {
                s += vj * x[*cj as usize];
            }
            assert_eq!(first.add_row(i, &x, 0.25), s, "row {i}");
        }
    }

    /// The pair's sums are the single ones bit for bit, on values whose rounding depends on
    /// the order.
    #[test]
    fn the_pair_of_rows_is_two_single_rows() {
        let columns: Vec<u32> = (0..40).filter(|c| c % 11 != 3).collect();
        let values: Vec<f64> = columns
            .iter()
            .map(|&c| (f64::from(c) * 0.37).sin() * 10f64.powi((c % 9) as i32 - 4))
            .collect();
        let mut m = NearMatrix::new();
        m.push_row(&columns, &values);
        let x: Vec<f64> = (0..40).map(|k| (f64::from(k) * 1.3).cos()).collect();
        let y: Vec<f64> = x.iter().map(|a| 0.1 - a * a).collect();
        let [p, q] = m.add_row2(0, [&x, &y], [0.25, -1.0]);
        assert_eq!(p.to_bits(), m.add_row(0, &x, 0.25).to_bits());
        assert_eq!(q.to_bits(), m.add_row(0, &y, -1.0).to_bits());
    }
}
