//! The states a run keeps, in bounded memory whatever its length.
//!
//! The monitors judge every state online (`monitor.rs`) and the recording may stream every
//! state to disk ([`crate::run::run_observed`]); what stays in memory is only what the figures
//! and the bindings draw. [`Trajectory`] keeps the `sim.dt` grid while it fits in
//! [`MAX_KEPT_STATES`], then decimates it online by **stride doubling**: when full, it drops
//! every other grid state and from then on keeps one state in `2s` instead of one in `s`. So
//! after `N` grid states it holds between `C/2` and `C` of them (`C` the capacity), evenly
//! spaced in time at the stride `s = 2^⌈log₂(N/C)⌉`, and its memory never exceeds
//! `C · size_of::<Sample>()` (≈ 11 MB), plus the pinned states.
//!
//! **Pinned states** are never dropped: both sides of each discovery and of each lidar event
//! (`Θ`, `k` and `λ` jump there), the arrival and the last state. There are at most `2M + 2`
//! of them for `M` obstacles under a sector, so they do not grow with the run's length; a
//! lidar's events are finitely many in a bounded world (docs/maths.md §12.6), two states each.

use crate::trace::Sample;

/// The most grid states a [`Trajectory`] keeps (see the module's doc): 2¹⁷, about 15 MB of
/// [`Sample`]s, far more than a figure can draw and enough for any run of up to 1 300 s at
/// `sim.dt = 0.01` to be kept whole.
pub const MAX_KEPT_STATES: usize = 1 << 17;

/// Whether a state may be dropped by the decimation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keep {
    /// A state on the `sim.dt` grid: kept at the current stride.
    Grid,
    /// An event's state (a discovery's two sides, the arrival, the end): always kept.
    Pinned,
}

/// The kept states of a run, in time order (see the module's doc): [`Sample`]s by default,
/// or any state type `T` (the floor-plan loop keeps its positions, `crate::floor`).
#[derive(Clone, Debug)]
pub struct Trajectory<T = Sample> {
    /// `(state, pinned)` in time order.
    kept: Vec<(T, bool)>,
    /// Grid states kept in a row of `stride` (a power of two).
    stride: usize,
    /// Grid states offered so far.
    offered: usize,
    /// Grid states currently kept.
    grid: usize,
    capacity: usize,
}

impl<T> Default for Trajectory<T> {
    fn default() -> Self {
        Self::with_capacity(MAX_KEPT_STATES)
    }
}

impl<T> Trajectory<T> {
    /// An empty trajectory that keeps at most `capacity` grid states (at least 2).
    pub fn with_capacity(capacity: usize) -> Self {
        Self {
            kept: Vec::new(),
            stride: 1,
            offered: 0,
            grid: 0,
            capacity: capacity.max(2),
        }
    }

    /// Offers a state; a grid state is kept if its index is a multiple of the stride.
    pub fn push(&mut self, s: T, keep: Keep) {
        match keep {
            Keep::Pinned => self.kept.push((s, true)),
            Keep::Grid => {
                let index = self.offered;
                self.offered += 1;
                if !index.is_multiple_of(self.stride) {
                    return;
                }
                if self.grid == self.capacity {
                    self.halve();
                    if !index.is_multiple_of(self.stride) {
                        return;
                    }
                }
                self.kept.push((s, false));
                self.grid += 1;
            }
        }
    }

    /// Doubles the stride: keeps the grid states whose index is a multiple of the new stride
    /// (every other one of those kept), in place.
    fn halve(&mut self) {
        let mut nth = 0usize;
        self.kept.retain(|(_, pinned)| {
            if *pinned {
                return true;
            }
            nth += 1;
            (nth - 1).is_multiple_of(2)
        });
        self.grid = self.grid.div_ceil(2);
        self.stride *= 2;
    }

    /// One grid state in `stride` is kept (1: the whole `sim.dt` grid).
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// The kept states, in time order.
    pub fn into_samples(self) -> Vec<T> {
        self.kept.into_iter().map(|(s, _)| s).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(t: f64) -> Sample {
        Sample {
            t,
            x: [t, 0.0],
            v: [0.0; 2],
            theta: 0.5,
            energy: None,
            k: 1.0,
            lambda: None,
            energy_tolerance: 0.0,
            critical: false,
            yaw: None,
        }
    }

    #[test]
    fn short_runs_are_kept_whole() {
        let mut tr = Trajectory::with_capacity(8);
        for i in 0..8 {
            tr.push(at(i as f64), Keep::Grid);
        }
        assert_eq!(tr.stride(), 1);
        let t: Vec<f64> = tr.into_samples().iter().map(|s| s.t).collect();
        assert_eq!(t, (0..8).map(f64::from).collect::<Vec<_>>());
    }

    #[test]
    fn long_runs_keep_an_even_grid_within_the_capacity() {
        for (capacity, n) in [(8usize, 9usize), (8, 100), (16, 1000), (1000, 123_457)] {
            let mut tr = Trajectory::with_capacity(capacity);
            for i in 0..n {
                tr.push(at(i as f64), Keep::Grid);
            }
            let stride = tr.stride();
            let t: Vec<usize> = tr.into_samples().iter().map(|s| s.t as usize).collect();
            // Exactly the multiples of the stride, in order, and no more than the capacity.
            let expected: Vec<usize> = (0..n).step_by(stride).collect();
            assert_eq!(t, expected, "capacity {capacity}, {n} states");
            assert!(
                t.len() <= capacity && t.len() > capacity / 2 - 1,
                "{}",
                t.len()
            );
            assert!(stride.is_power_of_two() && stride >= n.div_ceil(capacity));
        }
    }

    #[test]
    fn pinned_states_survive_every_halving() {
        let mut tr = Trajectory::with_capacity(4);
        for i in 0..1000 {
            tr.push(at(i as f64), Keep::Grid);
            if i % 97 == 1 {
                tr.push(at(i as f64 + 0.5), Keep::Pinned);
            }
        }
        let kept = tr.into_samples();
        let pinned: Vec<f64> = kept
            .iter()
            .map(|s| s.t)
            .filter(|t| t.fract() != 0.0)
            .collect();
        assert_eq!(
            pinned,
            (0..1000)
                .filter(|i| i % 97 == 1)
                .map(|i| i as f64 + 0.5)
                .collect::<Vec<_>>()
        );
        assert!(kept.windows(2).all(|w| w[0].t < w[1].t), "time order");
        assert!(kept.len() - pinned.len() <= 4);
    }
}
