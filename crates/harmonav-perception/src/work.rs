//! Counts of the perception's costly steps on the calling thread, so that tests can bound the
//! work of a scan without timing it (timed unit tests are not used in this workspace).
//!
//! The counts are per thread (a [`std::thread_local`] cell): a test reads [`work`] before and
//! after a call on its own thread and compares the difference, whatever other tests run
//! meanwhile. Counting costs one cell update per step, next to the milliseconds the step takes.

use std::cell::Cell;

/// How many of the perception's costly steps ran on this thread (since it started): read it
/// before and after a call and take the difference ([`Work::since`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Work {
    /// Segments fitted ([`crate::fit_in_scan`]).
    pub fits: usize,
    /// Merges of two shapes ([`crate::merge_clear_of`]).
    pub merges: usize,
    /// Certified stars built, one per candidate centre of a fit or a merge
    /// ([`crate::certified_star`], [`crate::certified_hull`]): each builds its star (its
    /// raises included) and checks eq. certify over every sample, the unit of a fit's or a
    /// merge's cost.
    pub certifications: usize,
    /// Candidate centres of a merge of radial hulls, or of a search for a star clear of the
    /// sensor, skipped without building their star (`perceived::least_hull`): a segment from
    /// the centre to a sample passes nearer the sensor than the star must keep, or the star's
    /// area floor exceeds the least area found.
    pub skipped: usize,
}

impl Work {
    /// The steps counted between `earlier` and `self`.
    #[must_use]
    pub fn since(self, earlier: Self) -> Self {
        Self {
            fits: self.fits - earlier.fits,
            merges: self.merges - earlier.merges,
            certifications: self.certifications - earlier.certifications,
            skipped: self.skipped - earlier.skipped,
        }
    }
}

thread_local! {
    static WORK: Cell<Work> = const {
        Cell::new(Work {
            fits: 0,
            merges: 0,
            certifications: 0,
            skipped: 0,
        })
    };
}

/// The steps counted on this thread so far.
#[must_use]
pub fn work() -> Work {
    WORK.with(Cell::get)
}

/// Counts a step on this thread.
pub(crate) fn count(step: impl FnOnce(&mut Work)) {
    WORK.with(|w| {
        let mut v = w.get();
        step(&mut v);
        w.set(v);
    });
}
