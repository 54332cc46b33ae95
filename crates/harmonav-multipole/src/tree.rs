//! The uniform quadtree: pieces, the upward and downward passes, evaluation and insertion.

use crate::expansion::{
    C64, MAX_TERMS, P2L_BATCH, Values, eval_local, eval_multipole, l2l, m2l, m2l_table, m2m,
    p2l_point_batch, p2m_point, p2m_segment, pascal,
};

/// A source: a point charge or a segment of uniform density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Source {
    /// `G(z) = log(z − z_0)`.
    Point(C64),
    /// `G(z) = ∫_{[A,B]} log(z − s)|ds|`: charge `q·|B − A|` for a weight `q`.
    Segment(C64, C64),
}

/// The geometry of a [`Piece`]: a point, or the part of a segment inside one leaf.
pub type Shape = Source;

/// A source, or the part of a segment source inside one leaf box, as the near-field closure of
/// [`Fmm::eval`] receives it: the caller evaluates its exact kernel on `shape` with the weights
/// of source `source`. The pieces of one segment add up to the segment (the integral is
/// additive).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// The index of the source (as given to [`Fmm::new`] or numbered by [`Fmm::push_point`]).
    pub source: usize,
    /// The point, or the sub-segment.
    pub shape: Shape,
}

/// Options of [`Fmm::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// The absolute error of `Re F` per unit of absolute charge (`|ΔRe F| ≤ tol·A`); sets the
    /// order `p = ⌈ln(tol)/ln 0.55⌉ + 2`. In `[1e-15, 1e-2]`; default `1e-13`.
    pub tolerance: f64,
    /// The number of pieces per occupied leaf the depth aims at (the depth grows while the mean
    /// is larger). Default 8.
    pub leaf_size: usize,
    /// The deepest leaf level (`4^L` leaves, each with `C(p + 1)` local coefficients). In
    /// `[2, 8]`; default 6.
    pub max_level: u32,
    /// A region the evaluations will come from (lower-left and upper-right corners); the root
    /// box covers it and the sources, so evaluations there take the leaves' local expansions.
    pub region: Option<(C64, C64)>,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            tolerance: 1e-13,
            leaf_size: 8,
            max_level: 6,
            region: None,
        }
    }
}

/// Why an [`Fmm`] could not be built or a point not added.
#[derive(Clone, Debug, PartialEq)]
pub enum FmmError {
    /// `sources` and `weights` differ in length.
    LengthMismatch {
        /// `sources.len()`.
        sources: usize,
        /// `weights.len()`.
        weights: usize,
    },
    /// A coordinate or a weight is not finite.
    NotFinite {
        /// The source's index.
        source: usize,
    },
    /// An option is out of its range.
    BadOption {
        /// The option's name.
        name: &'static str,
        /// Its allowed range.
        range: &'static str,
    },
    /// [`Fmm::push_point`]: the point lies outside the root box; rebuild with it.
    OutsideRoot,
    /// The sources (and region) span more than an `f64` holds: no root box.
    TooLarge,
}

impl std::fmt::Display for FmmError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::LengthMismatch { sources, weights } => write!(
                f,
                "{sources} sources but {weights} weights: one weight per source"
            ),
            Self::NotFinite { source } => {
                write!(
                    f,
                    "source {source} has a coordinate or a weight that is not finite"
                )
            }
            Self::BadOption { name, range } => write!(f, "option `{name}` must lie in {range}"),
            Self::OutsideRoot => write!(f, "the point lies outside the multipole tree's root box"),
            Self::TooLarge => write!(f, "the sources span more than an f64 holds"),
        }
    }
}

impl std::error::Error for FmmError {}

/// The deepest leaf level [`Options::max_level`] allows.
const MAX_LEVEL: u32 = 8;

/// The first level whose downward pass runs on two threads (`4^5` boxes: below it a thread
/// costs more than it saves, and the point world's small trees stay on the caller's thread).
const PARALLEL_LEVEL: u32 = 5;

/// The Barnes–Hut acceptance ratio outside the root box: a box's multipole serves `z` when the
/// disc about its centre that holds its pieces (radius `w/√2`) is at most `ρ` of the distance.
const RHO_OUTSIDE: f64 = 0.5;

/// Fast multipole sums over a fixed set of sources in `C` channels (see the crate docs).
#[derive(Clone, Debug)]
pub struct Fmm<const C: usize> {
    p: usize,
    levels: u32,
    origin: C64,
    side: f64,
    /// The pieces, grouped by leaf (row-major leaf order).
    pieces: Vec<Piece>,
    weights: Vec<[f64; C]>,
    /// `leaf_start[i]..leaf_start[i + 1]` are leaf `i`'s pieces.
    leaf_start: Vec<usize>,
    /// Per level `l`: `4^l` boxes × `C` channels × `p + 1` coefficients.
    multipoles: Vec<Vec<C64>>,
    /// Per level: the number of pieces under each box.
    counts: Vec<Vec<usize>>,
    /// The leaves' local expansions: `4^L × C × (p + 1)`.
    locals: Vec<C64>,
    sources: usize,
}

impl<const C: usize> Fmm<C> {
    /// Builds the tree over `sources` with one `[f64; C]` of weights each.
    ///
    /// Errors: [`FmmError::LengthMismatch`], [`FmmError::NotFinite`],
    /// [`FmmError::BadOption`]. No sources is allowed (every sum is then 0).
    pub fn new(
        sources: &[Source],
        weights: &[[f64; C]],
        options: &Options,
    ) -> Result<Self, FmmError> {
        if sources.len() != weights.len() {
            return Err(FmmError::LengthMismatch {
                sources: sources.len(),
                weights: weights.len(),
            });
        }
        if !(1e-15..=1e-2).contains(&options.tolerance) {
            return Err(FmmError::BadOption {
                name: "tolerance",
                range: "[1e-15, 1e-2]",
            });
        }
        if !(2..=MAX_LEVEL).contains(&options.max_level) {
            return Err(FmmError::BadOption {
                name: "max_level",
                range: "[2, 8]",
            });
        }
        if options.leaf_size == 0 {
            return Err(FmmError::BadOption {
                name: "leaf_size",
                range: "[1, ∞)",
            });
        }
        let finite = |z: C64| z.re.is_finite() && z.im.is_finite();
        for (j, (s, w)) in sources.iter().zip(weights).enumerate() {
            let ok = match s {
                Source::Point(z) => finite(*z),
                Source::Segment(a, b) => finite(*a) && finite(*b),
            } && w.iter().all(|x| x.is_finite());
            if !ok {
                return Err(FmmError::NotFinite { source: j });
            }
        }
        if let Some((lo, hi)) = options.region
            && !(finite(lo) && finite(hi))
        {
            return Err(FmmError::BadOption {
                name: "region",
                range: "finite corners",
            });
        }
        let p = order(options.tolerance);
        let (origin, side) = root_box(sources, options.region);
        // Coordinates spanning more than f64 can hold (about ±9e307) have no box.
        if !(side.is_finite() && origin.re.is_finite() && origin.im.is_finite()) {
            return Err(FmmError::TooLarge);
        }
        let levels = depth(sources, origin, side, options);
        let mut fmm = Self {
            p,
            levels,
            origin,
            side,
            pieces: Vec::new(),
            weights: weights.to_vec(),
            leaf_start: Vec::new(),
            multipoles: Vec::new(),
            counts: Vec::new(),
            locals: Vec::new(),
            sources: sources.len(),
        };
        fmm.cut(sources);
        fmm.upward();
        fmm.downward();
        Ok(fmm)
    }

    /// The expansion order `p`.
    pub fn order(&self) -> usize {
        self.p
    }

    /// The leaf level `L` (`4^L` leaves).
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// The width of a leaf box.
    pub fn leaf_width(&self) -> f64 {
        self.width(self.levels)
    }

    /// The number of sources.
    pub fn len(&self) -> usize {
        self.sources
    }

    /// Whether there are no sources.
    pub fn is_empty(&self) -> bool {
        self.sources == 0
    }

    /// `Re F_c(z)` and `F'_c(z)` for each channel, the far field from the expansions; `near` is
    /// called once for each piece the expansions leave out, and the caller adds its exact kernel
    /// for it (the pieces of the 3 × 3 leaves about `z`, or of the leaves a walk outside the
    /// root box reaches). `F''` is left at zero; see [`Self::eval2`].
    pub fn eval(&self, z: C64, near: impl FnMut(&Piece)) -> [Values; C] {
        self.eval_with::<false>(z, near)
    }

    /// [`Self::eval`] with `F''_c(z)` too.
    pub fn eval2(&self, z: C64, near: impl FnMut(&Piece)) -> [Values; C] {
        self.eval_with::<true>(z, near)
    }

    /// Adds a point source with its weights, numbered `self.len()` (before the call), without a
    /// rebuild: its P2L into every leaf outside its 3 × 3 neighbourhood, with the fewest terms
    /// per ring of leaves that keep the tree's truncation bound (docs/maths.md §15, eq.
    /// push-order), and its P2M into its ancestors. Errors: [`FmmError::NotFinite`], [`FmmError::OutsideRoot`] (the tree is then
    /// unchanged).
    pub fn push_point(&mut self, z: C64, w: [f64; C]) -> Result<usize, FmmError> {
        if !(z.re.is_finite() && z.im.is_finite() && w.iter().all(|x| x.is_finite())) {
            return Err(FmmError::NotFinite {
                source: self.sources,
            });
        }
        let leaf = self.leaf_of(z).ok_or(FmmError::OutsideRoot)?;
        let index = self.sources;
        let n = 1usize << self.levels;
        let at = self.leaf_start[leaf + 1];
        self.pieces.insert(
            at,
            Piece {
                source: index,
                shape: Source::Point(z),
            },
        );
        for s in &mut self.leaf_start[leaf + 1..] {
            *s += 1;
        }
        self.weights.push(w);
        self.sources += 1;
        let terms = self.p + 1;
        // P2M into the leaf and its ancestors (every term: a multipole serves every M2L).
        let (mut ix, mut iy) = (leaf % n, leaf / n);
        for l in (0..=self.levels).rev() {
            let nl = 1usize << l;
            let b = iy * nl + ix;
            let (c, width) = (self.centre(l, ix, iy), self.width(l));
            for (ch, q) in w.iter().enumerate() {
                let start = (b * C + ch) * terms;
                p2m_point(
                    &mut self.multipoles[l as usize][start..start + terms],
                    *q,
                    z,
                    c,
                    width,
                );
            }
            self.counts[l as usize][b] += 1;
            ix /= 2;
            iy /= 2;
        }
        // P2L into every far leaf, ring by ring about the point's leaf (eq. push-order: each
        // ring with its own order), `P2L_BATCH` leaves at a time (independent power chains).
        let (lx, ly) = (leaf % n, leaf / n);
        let width = self.width(self.levels);
        let mut ring = Vec::with_capacity(8 * n);
        for r in 2..n {
            ring_leaves(n, (lx, ly), r, &mut ring);
            if ring.is_empty() {
                continue;
            }
            let terms = push_terms(self.p, r);
            for (ch, q) in w.iter().enumerate() {
                for chunk in ring.chunks(P2L_BATCH) {
                    let mut starts = [0; P2L_BATCH];
                    let mut centres = [C64::new(0.0, 0.0); P2L_BATCH];
                    for (j, &b) in chunk.iter().enumerate() {
                        starts[j] = (b * C + ch) * (self.p + 1);
                        centres[j] = self.centre(self.levels, b % n, b / n);
                    }
                    let charge = (*q, z, width);
                    p2l_point_batch(
                        &mut self.locals,
                        &starts,
                        &centres,
                        chunk.len(),
                        terms,
                        charge,
                    );
                }
            }
        }
        Ok(index)
    }

    fn width(&self, level: u32) -> f64 {
        self.side / (1u64 << level) as f64
    }

    fn centre(&self, level: u32, ix: usize, iy: usize) -> C64 {
        let w = self.width(level);
        self.origin + C64::new((ix as f64 + 0.5) * w, (iy as f64 + 0.5) * w)
    }

    /// The leaf holding `z` (the closed root box; the top and right edges belong to the last
    /// leaves), or `None` outside it.
    fn leaf_of(&self, z: C64) -> Option<usize> {
        let n = 1usize << self.levels;
        let (u, v) = (
            (z.re - self.origin.re) / self.side,
            (z.im - self.origin.im) / self.side,
        );
        if !((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)) {
            return None;
        }
        let cell = |t: f64| ((t * n as f64) as usize).min(n - 1);
        Some(cell(v) * n + cell(u))
    }

    /// Cuts the sources into pieces at the leaf grid lines and groups them by leaf ([`cut`]).
    fn cut(&mut self, sources: &[Source]) {
        let grid = (self.origin, self.width(self.levels), 1usize << self.levels);
        let leaf = |z| self.leaf_of(z).expect("the root box holds every source");
        (self.leaf_start, self.pieces) = cut(sources, grid, leaf);
    }

    /// P2M at the leaves, M2M up to the root.
    fn upward(&mut self) {
        let terms = self.p + 1;
        let binom = pascal(2 * self.p);
        self.multipoles = (0..=self.levels)
            .map(|l| vec![C64::new(0.0, 0.0); (1usize << (2 * l)) * C * terms])
            .collect();
        self.counts = (0..=self.levels)
            .map(|l| vec![0; 1usize << (2 * l)])
            .collect();
        let n = 1usize << self.levels;
        let w = self.width(self.levels);
        let top = self.levels as usize;
        for leaf in 0..n * n {
            let c = self.centre(self.levels, leaf % n, leaf / n);
            for piece in &self.pieces[self.leaf_start[leaf]..self.leaf_start[leaf + 1]] {
                let q = self.weights[piece.source];
                for (ch, qc) in q.iter().enumerate() {
                    let start = (leaf * C + ch) * terms;
                    let a = &mut self.multipoles[top][start..start + terms];
                    match piece.shape {
                        Source::Point(z) => p2m_point(a, *qc, z, c, w),
                        Source::Segment(s0, s1) => p2m_segment(a, *qc, (s0, s1), c, w),
                    }
                }
                self.counts[top][leaf] += 1;
            }
        }
        let mut multipoles = std::mem::take(&mut self.multipoles);
        for l in (0..self.levels).rev() {
            let (nl, wl) = (1usize << l, self.width(l));
            let (upper, lower) = multipoles.split_at_mut(l as usize + 1);
            let (parent_level, child_level) = (&mut upper[l as usize], &lower[0]);
            for iy in 0..nl {
                for ix in 0..nl {
                    let parent = iy * nl + ix;
                    let c = self.centre(l, ix, iy);
                    for (cx, cy) in children(ix, iy) {
                        let child = cy * 2 * nl + cx;
                        let count = self.counts[l as usize + 1][child];
                        if count == 0 {
                            continue;
                        }
                        self.counts[l as usize][parent] += count;
                        let d = (self.centre(l + 1, cx, cy) - c) / wl;
                        for ch in 0..C {
                            let ps = (parent * C + ch) * terms;
                            let cs = (child * C + ch) * terms;
                            m2m(
                                &mut parent_level[ps..ps + terms],
                                &child_level[cs..cs + terms],
                                d,
                                &binom,
                            );
                        }
                    }
                }
            }
        }
        self.multipoles = multipoles;
    }

    /// M2L over each box's interaction list and L2L down to the leaves.
    fn downward(&mut self) {
        let terms = self.p + 1;
        let binom = pascal(2 * self.p);
        let table = m2l_table(self.p);
        let mut parent_locals = vec![C64::new(0.0, 0.0); C * terms];
        for l in 1..=self.levels {
            let nl = 1usize << l;
            let mut locals = vec![C64::new(0.0, 0.0); nl * nl * C * terms];
            let row = nl * C * terms;
            let fill = |rows: std::ops::Range<usize>, out: &mut [C64]| {
                for (k, iy) in rows.enumerate() {
                    for ix in 0..nl {
                        let start = k * row + ix * C * terms;
                        self.local_of_box(
                            (l, ix, iy),
                            &mut out[start..start + C * terms],
                            &parent_locals,
                            (&binom, &table),
                        );
                    }
                }
            };
            if l >= PARALLEL_LEVEL {
                // Each box's expansion is computed alone, so the two halves of the rows on two
                // threads give the one-thread expansions bit for bit.
                let (low, high) = locals.split_at_mut(nl / 2 * row);
                std::thread::scope(|scope| {
                    let handle = scope.spawn(|| fill(nl / 2..nl, high));
                    fill(0..nl / 2, low);
                    handle
                        .join()
                        .unwrap_or_else(|e| std::panic::resume_unwind(e));
                });
            } else {
                fill(0..nl, &mut locals);
            }
            parent_locals = locals;
        }
        self.locals = parent_locals;
    }

    /// The local expansions (all channels) of box `(ix, iy)` of level `l ≥ 1` into `out`: L2L
    /// from its parent's (`parent_locals`, level `l − 1`) and M2L from its interaction list.
    fn local_of_box(
        &self,
        (l, ix, iy): (u32, usize, usize),
        out: &mut [C64],
        parent_locals: &[C64],
        (binom, table): (&[Vec<f64>], &[f64]),
    ) {
        let terms = self.p + 1;
        let (nl, wl) = (1usize << l, self.width(l));
        let c = self.centre(l, ix, iy);
        // L2L from the parent.
        let (px, py) = (ix / 2, iy / 2);
        let parent = py * (nl / 2) + px;
        let d = (c - self.centre(l - 1, px, py)) / self.width(l - 1);
        for ch in 0..C {
            let ps = (parent * C + ch) * terms;
            l2l(
                &mut out[ch * terms..(ch + 1) * terms],
                &parent_locals[ps..ps + terms],
                d,
                binom,
            );
        }
        // M2L: the children of the parent's neighbours that are not adjacent.
        for (sx, sy) in interaction_list(ix, iy, nl) {
            let s = sy * nl + sx;
            if self.counts[l as usize][s] == 0 {
                continue;
            }
            let z0 = self.centre(l, sx, sy) - c;
            for ch in 0..C {
                let ss = (s * C + ch) * terms;
                m2l(
                    &mut out[ch * terms..(ch + 1) * terms],
                    &self.multipoles[l as usize][ss..ss + terms],
                    z0,
                    wl,
                    table,
                );
            }
        }
    }

    fn eval_with<const SECOND: bool>(&self, z: C64, mut near: impl FnMut(&Piece)) -> [Values; C] {
        let terms = self.p + 1;
        let mut out = [Values::default(); C];
        match self.leaf_of(z) {
            Some(leaf) => {
                let n = 1usize << self.levels;
                let (ix, iy) = (leaf % n, leaf / n);
                let (c, w) = (self.centre(self.levels, ix, iy), self.width(self.levels));
                for (ch, o) in out.iter_mut().enumerate() {
                    let start = (leaf * C + ch) * terms;
                    *o = eval_local::<SECOND>(&self.locals[start..start + terms], z, c, w);
                }
                for jy in iy.saturating_sub(1)..=(iy + 1).min(n - 1) {
                    let row = jy * n;
                    let (from, to) = (ix.saturating_sub(1), (ix + 1).min(n - 1));
                    for piece in
                        &self.pieces[self.leaf_start[row + from]..self.leaf_start[row + to + 1]]
                    {
                        near(piece);
                    }
                }
            }
            None => self.walk::<SECOND>(z, &mut out, &mut near),
        }
        out
    }

    /// Barnes–Hut outside the root box: a box's multipole when `w/√2 ≤ ρ|z − c|`.
    fn walk<const SECOND: bool>(
        &self,
        z: C64,
        out: &mut [Values; C],
        near: &mut impl FnMut(&Piece),
    ) {
        let terms = self.p + 1;
        // A depth-first walk on the stack, no allocation (it runs per evaluation: the point
        // world's `h` leaves the root box near the outer boundary, which `Phi` sends far away).
        // Each expanded box replaces itself by its 4 children, so at most `1 + 3L` boxes wait
        // at once.
        let mut stack = [(0u32, 0usize, 0usize); 1 + 3 * MAX_LEVEL as usize];
        let mut len = 1;
        while len > 0 {
            len -= 1;
            let (l, ix, iy) = stack[len];
            let nl = 1usize << l;
            let b = iy * nl + ix;
            if self.counts[l as usize][b] == 0 {
                continue;
            }
            let (c, w) = (self.centre(l, ix, iy), self.width(l));
            if w * std::f64::consts::FRAC_1_SQRT_2 <= RHO_OUTSIDE * (z - c).norm() {
                for (ch, o) in out.iter_mut().enumerate() {
                    let start = (b * C + ch) * terms;
                    let v = eval_multipole::<SECOND>(
                        &self.multipoles[l as usize][start..start + terms],
                        z,
                        c,
                        w,
                    );
                    o.value += v.value;
                    o.d1 += v.d1;
                    o.d2 += v.d2;
                }
            } else if l == self.levels {
                for piece in &self.pieces[self.leaf_start[b]..self.leaf_start[b + 1]] {
                    near(piece);
                }
            } else {
                for child in children(ix, iy) {
                    stack[len] = (l + 1, child.0, child.1);
                    len += 1;
                }
            }
        }
    }
}

/// The worst separation ratio of the uniform method (M2L between boxes two widths apart):
/// `√2/(4 − √2) ≈ 0.55`.
const RHO_UNIFORM: f64 = 0.55;

/// `p = ⌈ln(tol)/ln 0.55⌉ + 2`, at most `MAX_TERMS − 1`.
pub(crate) fn order(tolerance: f64) -> usize {
    let p = (tolerance.ln() / RHO_UNIFORM.ln()).ceil() as usize + 2;
    p.clamp(4, MAX_TERMS - 1)
}

/// The number of terms `P + 1` of a pushed point's P2L into a leaf `r ≥ 2` leaves away from
/// the point's own (Chebyshev distance of the leaves; docs/maths.md §15, eq. push-order):
///
/// ```text
/// ρ_r = (√2/2)/(r − 1/2),    the smallest P with ρ_r^{P+1} ≤ ρ₀^{p+1}/(p + 1),  ρ₀ = 0.55,
/// ```
///
/// at most `p`. The point lies in its closed leaf box, so `|c − z₀| ≥ (r − 1/2)w` from the
/// target leaf's centre `c`, and a target `z` in that leaf has `|z − c| ≤ (√2/2)w`: the `m`-th
/// term of `F^{(k)}` is at most `|q| (m − 1)!/(m − k)! ρ_r^m` in units of `((√2/2)w)^{−k}`.
/// The rule makes each dropped term of every derivative `k ≥ 0` no larger than the matching
/// dropped term (`m + p − P`) of the uniform method at its worst ratio `ρ₀` and order `p`
/// (where it asks for more than `p + 1` terms, the cap keeps order `p` at `ρ_r ≤ 0.47 < ρ₀`;
/// at least 2 terms are kept), so
/// the push keeps the tree's stated truncation bound with fewer terms far away (49 terms at
/// `r = 2`, 20 at `r = 5`, 14 at `r = 10` for `p = 53`, against 54).
pub(crate) fn push_terms(p: usize, r: usize) -> usize {
    let rho = std::f64::consts::FRAC_1_SQRT_2 / (r as f64 - 0.5);
    let bound = (p + 1) as f64 * RHO_UNIFORM.ln() - ((p + 1) as f64).ln();
    // `(P + 1) ln ρ_r ≤ bound`, both sides negative.
    let terms = (bound / rho.ln()).ceil() as usize;
    terms.clamp(2, p + 1)
}

/// The leaves of an `n × n` grid at Chebyshev distance exactly `r ≥ 1` from `(lx, ly)`,
/// row-major, into `out` (cleared first).
fn ring_leaves(n: usize, (lx, ly): (usize, usize), r: usize, out: &mut Vec<usize>) {
    out.clear();
    let (x0, x1) = (lx.saturating_sub(r), (lx + r).min(n - 1));
    for jy in ly.saturating_sub(r)..=(ly + r).min(n - 1) {
        if jy.abs_diff(ly) == r {
            out.extend((x0..=x1).map(|jx| jy * n + jx));
        } else {
            out.extend(
                [lx.checked_sub(r), Some(lx + r).filter(|&x| x < n)]
                    .into_iter()
                    .flatten()
                    .map(|jx| jy * n + jx),
            );
        }
    }
}

/// The root square: the bounding box of the sources and the region, squared, with a relative
/// pad of `1e-9` (and an absolute floor for a single point) so every source lies strictly inside.
pub(crate) fn root_box(sources: &[Source], region: Option<(C64, C64)>) -> (C64, f64) {
    let (mut lo, mut hi) = (
        C64::new(f64::INFINITY, f64::INFINITY),
        C64::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    let mut grow = |z: C64| {
        lo = C64::new(lo.re.min(z.re), lo.im.min(z.im));
        hi = C64::new(hi.re.max(z.re), hi.im.max(z.im));
    };
    for s in sources {
        match *s {
            Source::Point(z) => grow(z),
            Source::Segment(a, b) => {
                grow(a);
                grow(b);
            }
        }
    }
    if let Some((a, b)) = region {
        grow(a);
        grow(b);
    }
    if !lo.re.is_finite() {
        return (C64::new(-1.0, -1.0), 2.0);
    }
    // Halves first: `lo + hi` and `hi − lo` overflow for coordinates near ±f64::MAX.
    let centre = lo * 0.5 + hi * 0.5;
    let extent = (hi.re * 0.5 - lo.re * 0.5).max(hi.im * 0.5 - lo.im * 0.5) * 2.0;
    let scale = centre.re.abs().max(centre.im.abs()).max(extent);
    let side = (extent * (1.0 + 1e-9))
        .max(scale * 1e-9)
        .max(f64::MIN_POSITIVE);
    (centre - C64::new(side * 0.5, side * 0.5), side)
}

/// The leaf level: from 2, deeper while the mean number of sources per occupied leaf (by each
/// source's centre) exceeds `leaf_size` and a level separates more of them than the one
/// before, up to `max_level`.
pub(crate) fn depth(sources: &[Source], origin: C64, side: f64, options: &Options) -> u32 {
    let centres: Vec<C64> = sources
        .iter()
        .map(|s| match *s {
            Source::Point(z) => z,
            Source::Segment(a, b) => (a + b) * 0.5,
        })
        .collect();
    let (mut level, mut occupied_before) = (2, 0);
    while level < options.max_level {
        let n = 1usize << level;
        let mut cells: Vec<usize> = centres
            .iter()
            .map(|z| {
                let cell = |t: f64| ((t * n as f64) as usize).min(n - 1);
                cell((z.im - origin.im) / side) * n + cell((z.re - origin.re) / side)
            })
            .collect();
        cells.sort_unstable();
        cells.dedup();
        // Deep enough, or refining no longer separates the sources (coincident ones would
        // otherwise drive the tree to `max_level` and its `4^L` local expansions).
        if centres.len() <= options.leaf_size * cells.len().max(1)
            || (level > 2 && cells.len() == occupied_before)
        {
            break;
        }
        occupied_before = cells.len();
        level += 1;
    }
    level
}

pub(crate) fn children(ix: usize, iy: usize) -> impl Iterator<Item = (usize, usize)> {
    [(0, 0), (1, 0), (0, 1), (1, 1)]
        .into_iter()
        .map(move |(dx, dy)| (2 * ix + dx, 2 * iy + dy))
}

/// The children of the parent's neighbours (the parent included) that are not adjacent to
/// `(ix, iy)`, on an `nl × nl` grid.
pub(crate) fn interaction_list(
    ix: usize,
    iy: usize,
    nl: usize,
) -> impl Iterator<Item = (usize, usize)> {
    let (px, py) = (ix / 2, iy / 2);
    let np = nl / 2;
    let xs = px.saturating_sub(1)..=(px + 1).min(np.saturating_sub(1));
    xs.flat_map(move |qx| {
        (py.saturating_sub(1)..=(py + 1).min(np.saturating_sub(1)))
            .flat_map(move |qy| children(qx, qy))
    })
    .filter(move |(sx, sy)| sx.abs_diff(ix) > 1 || sy.abs_diff(iy) > 1)
}

/// The parameters `t ∈ [0, 1]` at which the segment `a → b` crosses the lines of the grid of
/// spacing `w` from `origin` (both ends included, sorted, without repeats): the segment's
/// pieces between them each lie in one leaf.
/// The sources cut into pieces at the leaf grid lines of `(origin, w, n)` (an `n × n` grid of
/// boxes of width `w` from `origin`; [`grid_cuts`]) and grouped by leaf, `leaf(z)` the leaf of
/// a point: `(start, pieces)`, the pieces of leaf `i` being `pieces[start[i]..start[i + 1]]`, in
/// the order of their sources. A cut of zero length is dropped. Used by [`crate::Fmm`] and
/// [`crate::Operator`] alike.
pub(crate) fn cut(
    sources: &[Source],
    (origin, w, n): (C64, f64, usize),
    leaf: impl Fn(C64) -> usize,
) -> (Vec<usize>, Vec<Piece>) {
    let mut tagged: Vec<(usize, Piece)> = Vec::with_capacity(2 * sources.len());
    for (j, s) in sources.iter().enumerate() {
        match *s {
            Source::Point(z) => tagged.push((
                leaf(z),
                Piece {
                    source: j,
                    shape: *s,
                },
            )),
            Source::Segment(a, b) => {
                let ts = grid_cuts(a, b, origin, w);
                for pair in ts.windows(2) {
                    let (p0, p1) = (a + (b - a) * pair[0], a + (b - a) * pair[1]);
                    if p0 == p1 {
                        continue;
                    }
                    tagged.push((
                        leaf((p0 + p1) * 0.5),
                        Piece {
                            source: j,
                            shape: Source::Segment(p0, p1),
                        },
                    ));
                }
            }
        }
    }
    tagged.sort_by_key(|(leaf, _)| *leaf);
    let mut start = vec![0; n * n + 1];
    for (leaf, _) in &tagged {
        start[leaf + 1] += 1;
    }
    for i in 0..n * n {
        start[i + 1] += start[i];
    }
    (start, tagged.into_iter().map(|(_, p)| p).collect())
}

pub(crate) fn grid_cuts(a: C64, b: C64, origin: C64, w: f64) -> Vec<f64> {
    let mut ts = vec![0.0, 1.0];
    for (lo, hi, o) in [(a.re, b.re, origin.re), (a.im, b.im, origin.im)] {
        if lo == hi {
            continue;
        }
        let (x0, x1) = (lo.min(hi), lo.max(hi));
        let first = ((x0 - o) / w).floor() as i64 + 1;
        let last = ((x1 - o) / w).ceil() as i64 - 1;
        for i in first..=last {
            let t = (o + i as f64 * w - lo) / (hi - lo);
            if t > 0.0 && t < 1.0 {
                ts.push(t);
            }
        }
    }
    ts.sort_by(f64::total_cmp);
    ts.dedup();
    ts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expansion::p2l_point;

    /// `push_point` leaves the tree's local expansions bit for bit where the leaf-by-leaf P2L
    /// of the single form (`p2l_point` of `push_terms` terms into every leaf outside the 3 × 3
    /// about the point's leaf, channel by channel) leaves them: two channels, weights of either sign, pushes
    /// into corner, edge and interior leaves.
    #[test]
    fn the_batched_push_matches_the_single_p2l_to_the_bit() {
        let sources: Vec<Source> = (0..400)
            .map(|i| {
                let (x, y) = (
                    (i % 20) as f64 * 0.5,
                    (i / 20) as f64 * 0.5 + 0.01 * (i % 7) as f64,
                );
                Source::Point(C64::new(x, y))
            })
            .collect();
        let weights: Vec<[f64; 2]> = (0..400).map(|i| [1.0, 0.5 - (i % 3) as f64]).collect();
        let built = Fmm::new(&sources, &weights, &Options::default()).unwrap();
        assert!(built.levels >= 2, "a tree with far leaves");
        let mut batched = built.clone();
        let mut single = built;
        for (z, w) in [
            (C64::new(0.05, 0.02), [0.7, -1.3]),
            (C64::new(9.4, 4.1), [2.5, 1.0]),
            (C64::new(4.8, 5.2), [1.0, -0.2]),
        ] {
            batched.push_point(z, w).unwrap();
            // The reference: the push without its P2L, then the P2L one leaf at a time.
            let locals = single.locals.clone();
            single.push_point(z, w).unwrap();
            single.locals = locals;
            let n = 1usize << single.levels;
            let leaf = single.leaf_of(z).unwrap();
            let (lx, ly) = (leaf % n, leaf / n);
            let (stride, width) = (single.p + 1, single.width(single.levels));
            for b in 0..n * n {
                let (jx, jy) = (b % n, b / n);
                let r = jx.abs_diff(lx).max(jy.abs_diff(ly));
                if r <= 1 {
                    continue;
                }
                let c = single.centre(single.levels, jx, jy);
                let terms = push_terms(single.p, r);
                for (ch, q) in w.iter().enumerate() {
                    let start = (b * 2 + ch) * stride;
                    p2l_point(&mut single.locals[start..start + terms], *q, z, c, width);
                }
            }
            let bits = |f: &Fmm<2>| -> Vec<(u64, u64)> {
                f.locals
                    .iter()
                    .map(|c| (c.re.to_bits(), c.im.to_bits()))
                    .collect()
            };
            assert_eq!(bits(&batched), bits(&single), "push at {z}");
        }
    }

    /// Eq. push-order: the fewest terms whose first dropped term `ρ_r^{P+1}` is within the
    /// uniform method's `ρ₀^{p+1}/(p + 1)`, for every ring and the orders of the tolerances.
    #[test]
    fn the_push_order_is_the_fewest_terms_within_the_uniform_bound() {
        for tol in [1e-15, 1e-13, 1e-8, 1e-3] {
            let p = order(tol);
            let bound = RHO_UNIFORM.powi(p as i32 + 1) / (p + 1) as f64;
            let mut before = p + 1;
            for r in 2..=256 {
                let terms = push_terms(p, r);
                let rho = std::f64::consts::FRAC_1_SQRT_2 / (r as f64 - 0.5);
                // At the cap (low orders, near rings) the push keeps the uniform order at a
                // smaller ratio than `ρ₀`: within the bound too.
                assert!(
                    terms == p + 1 || rho.powi(terms as i32) <= bound * (1.0 + 1e-12),
                    "tol {tol}, r {r}"
                );
                assert!(
                    terms == 2 || rho.powi(terms as i32 - 1) > bound,
                    "minimal at r {r}"
                );
                assert!(terms <= before, "non-increasing in r");
                before = terms;
            }
        }
        // The figures of the docs, p = 53.
        let p = order(1e-13);
        assert_eq!(p, 53);
        let t: Vec<usize> = [2, 3, 5, 10].iter().map(|&r| push_terms(p, r)).collect();
        assert_eq!(t, [49, 29, 20, 14]);
    }

    /// The rings about a leaf partition the far leaves (every leaf outside the 3 × 3 once),
    /// at the corners, edges and inside of the grid.
    #[test]
    fn the_rings_partition_the_far_leaves() {
        for n in [4, 5, 16] {
            for (lx, ly) in [(0, 0), (n - 1, 0), (2, n - 1), (n / 2, n / 2), (1, 2)] {
                let mut seen = vec![0; n * n];
                let mut ring = Vec::new();
                for r in 2..n {
                    ring_leaves(n, (lx, ly), r, &mut ring);
                    for &b in &ring {
                        assert_eq!((b % n).abs_diff(lx).max((b / n).abs_diff(ly)), r);
                        seen[b] += 1;
                    }
                }
                for (b, &count) in seen.iter().enumerate() {
                    let far = (b % n).abs_diff(lx) > 1 || (b / n).abs_diff(ly) > 1;
                    assert_eq!(count, usize::from(far), "n {n}, leaf ({lx}, {ly}), b {b}");
                }
            }
        }
    }
}
