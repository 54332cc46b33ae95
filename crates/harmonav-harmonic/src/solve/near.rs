//! The near block `G_near` of the iterative solve, rows by collocation point, stored by runs of
//! consecutive columns.
//!
//! A collocation point's near elements are the pieces of the rings that cross the 3 × 3 leaves
//! about it, and a ring's elements are numbered along it, so a row's sorted columns come in a
//! few runs of consecutive elements (a wall passing by, its facing wall, a pillar). Storing each
//! run as `(first column, length)` instead of one `u32` per entry leaves 8 bytes per entry
//! instead of 12: the product streams the whole block once per GMRES iteration (30 million
//! entries, 360 MB on `willow-full`), which was a quarter of its set-up (docs/benchmarks.md,
//! "Set-up of the large maps"). The entries are added in the same order as before, so the
//! product is the same bit for bit.

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

    /// `s + Σ_e G_near[i][col_e]·x[col_e]`, the entries added one by one in increasing column
    /// order (the order of a row of `(column, value)` pairs, so the result is theirs bit for
    /// bit).
    pub(super) fn add_row(&self, i: usize, x: &[f64], mut s: f64) -> f64 {
        let mut e = self.value_start[i];
        for run in &self.runs[self.run_start[i]..self.run_start[i + 1]] {
            let first = run.first as usize;
            let len = run.len as usize;
            for (v, xj) in self.values[e..e + len].iter().zip(&x[first..first + len]) {
                s += v * xj;
            }
            e += len;
        }
        s
    }

    /// [`NearMatrix::add_row`] for two vectors in one pass over the row's entries: each sum
    /// is added in the same order as alone, so each is `add_row`'s bit for bit.
    pub(super) fn add_row2(&self, i: usize, x: [&[f64]; 2], s: [f64; 2]) -> [f64; 2] {
        let [mut s0, mut s1] = s;
        let mut e = self.value_start[i];
        for run in &self.runs[self.run_start[i]..self.run_start[i + 1]] {
            let first = run.first as usize;
            let len = run.len as usize;
            let values = &self.values[e..e + len];
            let (x0, x1) = (&x[0][first..first + len], &x[1][first..first + len]);
            for ((v, a), b) in values.iter().zip(x0).zip(x1) {
                s0 += v * a;
                s1 += v * b;
            }
            e += len;
        }
        [s0, s1]
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

    /// Rows of scattered and consecutive columns give the sums of their entries, in order,
    /// and two appended halves the whole.
    #[test]
    fn rows_by_runs_are_the_rows_of_entries() {
        let rows: Vec<(Vec<u32>, Vec<f64>)> = vec![
            (vec![0, 1, 2, 5, 7, 8], vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
            (vec![], vec![]),
            (vec![3], vec![0.5]),
            (vec![1, 3, 5, 6], vec![1e16, 1.0, -1e16, 1.0]),
        ];
        let x = [0.5, -1.0, 2.0, 3.0, 0.25, 1.0, 1.0, -2.0, 4.0];
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
        assert_eq!(first.entries(), 11);
        // Runs: [0..3], [5], [7..9]; none; [3]; [1], [3], [5..7].
        assert_eq!(first.run_count(), 7);
        for (i, (c, v)) in rows.iter().enumerate() {
            let mut s = 0.25;
            for (cj, vj) in c.iter().zip(v) {
                s += vj * x[*cj as usize];
            }
            assert_eq!(first.add_row(i, &x, 0.25).to_bits(), s.to_bits(), "row {i}");
            let y: Vec<f64> = x.iter().map(|xi| 3.0 - xi).collect();
            let [p, q] = first.add_row2(i, [&x, &y], [0.25, -1.0]);
            assert_eq!(p.to_bits(), s.to_bits(), "row {i}");
            assert_eq!(q.to_bits(), first.add_row(i, &y, -1.0).to_bits(), "row {i}");
        }
    }
}
