//! A multipole matrix–vector product: fixed sources, fixed target points, new weights per product.
//!
//! [`Operator::apply`] computes, for every target `t_i`,
//!
//! ```text
//! out_i = Re Σ_j q_j G_j(t_i)   over the pieces of the sources outside the 3 × 3 leaves about t_i,
//! ```
//!
//! the far part of a dense product `A q` whose entries are `A_ij = Re G_j(t_i)`; the caller adds
//! the near part (the pieces [`Operator::near`] lists) with its own exact kernel, once, as a
//! sparse matrix. This is what an iterative solver of a boundary-element system needs: the tree,
//! the cut pieces and the lists are built once ([`Operator::new`]), and each product costs one
//! upward pass (P2M, M2M), one downward pass (M2L, L2L) and one local evaluation per target,
//! `O(N p + B p²)` for `B` occupied boxes.
//!
//! **Batched M2L.** The `B p²` term, M2L, is most of a product. In the uniform tree the offset
//! `z̃0 = (c_s − c_t)/w` of a source box from its target is one of 40 integer pairs, and the
//! scaled M2L (`crate::expansion::m2l`) is `b̃_l += z̃0^{−l}(Σ_k T_lk s_k − Q/l)` with the same
//! real matrix `T_lk = C(l + k − 1, k − 1)` for every pair, `s_k = ã_k (−1/z̃0)^k`: so the
//! pairs of one level and one offset are gathered as the columns of `S` (real and imaginary
//! parts) and `T S` is one matrix product (nalgebra's `gemm`, which takes matrixmultiply's
//! kernels). The arithmetic is [`crate::expansion::m2l`]'s but for the order of the sums'
//! rounding (its truncation bound is unchanged); until 2026-12-06 each pair was a separate
//! matrix–vector sum, about 45 % of an iterative solve's time.
//!
//! **Fixed geometry.** The pieces and targets do not change between products, so the P2M of
//! each piece for a unit weight and the powers `ζ^m` of each target about its leaf's centre are
//! computed once (`16(p + 1)` bytes each): a product's P2M is `ã += q·(unit P2M)` and its L2P
//! one dot product, instead of the recurrences of `crate::expansion` per piece and target.
//!
//! Unlike [`crate::Fmm`], the tree is **sparse**: only the boxes that hold a piece keep a
//! multipole and only those that hold a target keep a local expansion, so a boundary (a set of
//! curves, occupying a small part of the leaves) costs what it occupies, not `4^L` boxes. The
//! expansions, the order `p = ⌈ln(tol)/ln 0.55⌉ + 2` and the truncation bound
//! (`|Δ out_i| ≤ tol·A`, `A = Σ_j |q_j|·(1 or L_j)`) are [`crate::Fmm`]'s (`expansion.rs`).

use nalgebra::{DMatrix, DMatrixView, DMatrixViewMut};

use crate::expansion::{C64, l2l, m2l_table, m2m, p2m_point, p2m_segment, pascal};
use crate::tree::{FmmError, Options, Piece, Source, children, depth, interaction_list, order};

const NONE: u32 = u32::MAX;

/// Most (target, source) pairs of one offset per matrix product of the batched M2L: `S` and
/// `T S` take `2·8p·BATCH` bytes (about 200 kB each at `p = 49`), within the cache.
const BATCH: usize = 256;

/// The offsets `(dx, dy)` of an interaction list lie in `[−3, 3]²`: an index into 49 buckets.
const OFFSETS: usize = 49;

/// The far part of the product with fixed sources and targets (see the module docs).
#[derive(Clone, Debug)]
pub struct Operator {
    p: usize,
    levels: u32,
    origin: C64,
    side: f64,
    sources: usize,
    /// The pieces, grouped by leaf (row-major leaf order).
    pieces: Vec<Piece>,
    /// `leaf_start[i]..leaf_start[i + 1]` are leaf `i`'s pieces.
    leaf_start: Vec<u32>,
    /// Per level: the slot of each box's multipole, [`NONE`] for a box without pieces.
    mslot: Vec<Vec<u32>>,
    /// Per level: the boxes with pieces, in slot order.
    mboxes: Vec<Vec<u32>>,
    /// Per level: the slot of each box's local expansion, [`NONE`] for a box without targets.
    lslot: Vec<Vec<u32>>,
    /// Per level: the boxes with targets, in slot order.
    lboxes: Vec<Vec<u32>>,
    targets: Vec<C64>,
    /// The leaf of each target.
    target_leaf: Vec<u32>,
    /// Per piece (in `pieces`' order), its P2M for a unit weight about its leaf's centre: a
    /// product's P2M is then `ã += q·(this)` (the geometry is fixed, only the weights change).
    unit_p2m: Vec<C64>,
    /// Per target, `ζ^m` for `m ∈ 0..=p`, `ζ = (t − c)/w` about its leaf's centre: L2P is then
    /// `Re Σ b̃_m ζ^m` as one dot product.
    powers: Vec<C64>,
    binom: Vec<Vec<f64>>,
    /// `T_lk = C(l + k − 1, k − 1)` for `l, k ∈ 1..=p`, as a `p × p` matrix (module docs).
    table: DMatrix<f64>,
}

impl Operator {
    /// Builds the sparse tree over `sources` and `targets` with [`Options`]'s tolerance,
    /// leaf size and deepest level (its `region` is ignored: the targets are the region).
    ///
    /// Errors: [`FmmError::NotFinite`] for a source (or, numbered `sources.len() + i`, a
    /// target `i`) with a coordinate that is not finite; [`FmmError::BadOption`] as
    /// [`crate::Fmm::new`]; [`FmmError::TooLarge`] when no root box holds them.
    pub fn new(sources: &[Source], targets: &[C64], options: &Options) -> Result<Self, FmmError> {
        if !(1e-15..=1e-2).contains(&options.tolerance) {
            return Err(FmmError::BadOption {
                name: "tolerance",
                range: "[1e-15, 1e-2]",
            });
        }
        if !(2..=8).contains(&options.max_level) {
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
        for (j, s) in sources.iter().enumerate() {
            let ok = match *s {
                Source::Point(z) => finite(z),
                Source::Segment(a, b) => finite(a) && finite(b),
            };
            if !ok {
                return Err(FmmError::NotFinite { source: j });
            }
        }
        if let Some(i) = targets.iter().position(|&z| !finite(z)) {
            return Err(FmmError::NotFinite {
                source: sources.len() + i,
            });
        }
        // The root box holds the sources and every target (as their bounding box).
        let region = targets.iter().fold(None, |acc: Option<(C64, C64)>, &z| {
            Some(match acc {
                None => (z, z),
                Some((lo, hi)) => (
                    C64::new(lo.re.min(z.re), lo.im.min(z.im)),
                    C64::new(hi.re.max(z.re), hi.im.max(z.im)),
                ),
            })
        });
        let (origin, side) = crate::tree::root_box(sources, region);
        if !(side.is_finite() && origin.re.is_finite() && origin.im.is_finite()) {
            return Err(FmmError::TooLarge);
        }
        let levels = depth(sources, origin, side, options);
        let p = order(options.tolerance);
        let mut op = Self {
            p,
            levels,
            origin,
            side,
            sources: sources.len(),
            pieces: Vec::new(),
            leaf_start: Vec::new(),
            mslot: Vec::new(),
            mboxes: Vec::new(),
            lslot: Vec::new(),
            lboxes: Vec::new(),
            targets: targets.to_vec(),
            target_leaf: Vec::new(),
            unit_p2m: Vec::new(),
            powers: Vec::new(),
            binom: pascal(2 * p),
            table: {
                let flat = m2l_table(p);
                DMatrix::from_fn(p, p, |l, k| flat[(l + 1) * (p + 1) + k + 1])
            },
        };
        op.cut(sources);
        op.occupancy();
        op.precompute();
        Ok(op)
    }

    /// The unit P2M of every piece and the powers `ζ^m` of every target (the fields' docs):
    /// `16(p + 1)` bytes per piece and per target.
    fn precompute(&mut self) {
        let terms = self.p + 1;
        let n = 1usize << self.levels;
        let w = self.width(self.levels);
        let zero = C64::new(0.0, 0.0);
        let mut unit = vec![zero; self.pieces.len() * terms];
        for leaf in 0..n * n {
            let c = self.centre(self.levels, leaf % n, leaf / n);
            let range = self.leaf_start[leaf] as usize..self.leaf_start[leaf + 1] as usize;
            for k in range {
                let a = &mut unit[k * terms..(k + 1) * terms];
                match self.pieces[k].shape {
                    Source::Point(z) => p2m_point(a, 1.0, z, c, w),
                    Source::Segment(s0, s1) => p2m_segment(a, 1.0, (s0, s1), c, w),
                }
            }
        }
        self.unit_p2m = unit;
        let mut powers = Vec::with_capacity(self.targets.len() * terms);
        for (&z, &leaf) in self.targets.iter().zip(&self.target_leaf) {
            let leaf = leaf as usize;
            let zeta = (z - self.centre(self.levels, leaf % n, leaf / n)) / w;
            let mut power = C64::new(1.0, 0.0);
            for _ in 0..terms {
                powers.push(power);
                power *= zeta;
            }
        }
        self.powers = powers;
    }

    /// The expansion order `p`.
    pub fn order(&self) -> usize {
        self.p
    }

    /// The leaf level `L`.
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// The number of sources.
    pub fn len(&self) -> usize {
        self.sources
    }

    /// Whether there are no sources.
    pub fn is_empty(&self) -> bool {
        self.sources == 0
    }

    /// The number of targets.
    pub fn targets(&self) -> usize {
        self.targets.len()
    }

    /// The occupied boxes over all levels: with pieces (multipoles) and with targets (locals).
    pub fn boxes(&self) -> (usize, usize) {
        (
            self.mboxes.iter().map(Vec::len).sum(),
            self.lboxes.iter().map(Vec::len).sum(),
        )
    }

    /// Calls `f` once for each piece that [`Operator::apply`] leaves out at target `i` (the
    /// pieces of the 3 × 3 leaves about its leaf): the caller's near field. Nothing for a
    /// target index out of range.
    pub fn near(&self, i: usize, mut f: impl FnMut(&Piece)) {
        let Some(&leaf) = self.target_leaf.get(i) else {
            return;
        };
        let n = 1usize << self.levels;
        let (ix, iy) = (leaf as usize % n, leaf as usize / n);
        for jy in iy.saturating_sub(1)..=(iy + 1).min(n - 1) {
            let row = jy * n;
            let (from, to) = (ix.saturating_sub(1), (ix + 1).min(n - 1));
            let (a, b) = (
                self.leaf_start[row + from] as usize,
                self.leaf_start[row + to + 1] as usize,
            );
            for piece in &self.pieces[a..b] {
                f(piece);
            }
        }
    }

    /// The far part of the product (module docs) with one weight per source, into `out` (one
    /// value per target, overwritten), at the tree's order `p`.
    ///
    /// # Panics
    /// When `weights` or `out` has the wrong length.
    pub fn apply(&self, weights: &[f64], out: &mut [f64]) {
        self.apply_order(weights, out, self.p);
    }

    /// The order of a product within `tolerance`: `min(p, q)` with `q` the order
    /// [`Options::tolerance`] would give (`⌈ln(tol)/ln 0.55⌉ + 2`, at least 4), so that
    /// [`Operator::apply_order`] with it is within `tol·A`, or within the tree's own tolerance
    /// if that is finer. A tolerance that is not in `(0, 1)` gives `p`.
    pub fn order_for(&self, tolerance: f64) -> usize {
        if tolerance > 0.0 && tolerance < 1.0 {
            order(tolerance).min(self.p)
        } else {
            self.p
        }
    }

    /// [`Operator::apply`] with every expansion truncated at order `q ≤ p` (a larger `q` is
    /// `p`): the product of the same tree built at the tolerance of order `q`, so within that
    /// tolerance's `tol·A` ([`Operator::order_for`]). M2L, M2M and L2L cost `q²` per box and
    /// P2M and L2P `q` per piece, so a product at `q = p/2` costs about a quarter of the
    /// multipole part: what an inexact Krylov solver asks for once its residual has fallen
    /// (harmonav-harmonic's GMRES, docs/maths/13-harmonic-scaling.md). With `q = p` it is
    /// [`Operator::apply`] bit for bit.
    ///
    /// # Panics
    /// When `weights` or `out` has the wrong length.
    pub fn apply_order(&self, weights: &[f64], out: &mut [f64], q: usize) {
        assert_eq!(weights.len(), self.sources, "one weight per source");
        assert_eq!(out.len(), self.targets.len(), "one output per target");
        // The expansions keep their stride `p + 1`; only the first `q + 1` terms are used.
        let terms = self.p + 1;
        let used = q.clamp(1, self.p) + 1;
        let zero = C64::new(0.0, 0.0);
        let top = self.levels as usize;
        // Upward: P2M at the leaves, M2M to the root.
        let mut multipoles: Vec<Vec<C64>> = self
            .mboxes
            .iter()
            .map(|b| vec![zero; b.len() * terms])
            .collect();
        for (slot, &leaf) in self.mboxes[top].iter().enumerate() {
            let leaf = leaf as usize;
            let a = &mut multipoles[top][slot * terms..(slot + 1) * terms];
            for k in self.leaf_start[leaf] as usize..self.leaf_start[leaf + 1] as usize {
                let q = weights[self.pieces[k].source];
                for (am, um) in a[..used]
                    .iter_mut()
                    .zip(&self.unit_p2m[k * terms..(k + 1) * terms])
                {
                    *am += um * q;
                }
            }
        }
        for l in (0..self.levels).rev() {
            let (upper, lower) = multipoles.split_at_mut(l as usize + 1);
            let (parents, childs) = (&mut upper[l as usize], &lower[0]);
            let nc = 1usize << (l + 1);
            let wl = self.width(l);
            for (slot, &child) in self.mboxes[l as usize + 1].iter().enumerate() {
                let (cx, cy) = (child as usize % nc, child as usize / nc);
                let (px, py) = (cx / 2, cy / 2);
                let parent = py * (nc / 2) + px;
                let ps = self.mslot[l as usize][parent] as usize;
                let d = (self.centre(l + 1, cx, cy) - self.centre(l, px, py)) / wl;
                m2m(
                    &mut parents[ps * terms..ps * terms + used],
                    &childs[slot * terms..slot * terms + used],
                    d,
                    &self.binom,
                );
            }
        }
        // Downward: L2L to each target box from its parent, then M2L over its interaction
        // list, batched by offset (module docs).
        let mut parent_locals: Vec<C64> = Vec::new();
        let mut buckets: Vec<Vec<(u32, u32)>> = vec![Vec::new(); OFFSETS];
        let mut scratch = (Vec::new(), Vec::new());
        for l in 1..=self.levels {
            let nl = 1usize << l;
            let wl = self.width(l);
            let boxes = &self.lboxes[l as usize];
            let mut locals = vec![zero; boxes.len() * terms];
            for bucket in &mut buckets {
                bucket.clear();
            }
            for (slot, &b) in boxes.iter().enumerate() {
                let (ix, iy) = (b as usize % nl, b as usize / nl);
                let c = self.centre(l, ix, iy);
                let out = &mut locals[slot * terms..slot * terms + used];
                if l >= 2 {
                    let (px, py) = (ix / 2, iy / 2);
                    let ps = self.lslot[l as usize - 1][py * (nl / 2) + px];
                    if ps != NONE && !parent_locals.is_empty() {
                        let ps = ps as usize;
                        let d = (c - self.centre(l - 1, px, py)) / self.width(l - 1);
                        l2l(
                            out,
                            &parent_locals[ps * terms..ps * terms + used],
                            d,
                            &self.binom,
                        );
                    }
                }
                for (sx, sy) in interaction_list(ix, iy, nl) {
                    let s = self.mslot[l as usize][sy * nl + sx];
                    if s == NONE {
                        continue;
                    }
                    // |sx − ix|, |sy − iy| ≤ 3 in an interaction list.
                    let k = (sx + 3 - ix) * 7 + (sy + 3 - iy);
                    buckets[k].push((slot as u32, s));
                }
            }
            for (k, bucket) in buckets.iter().enumerate() {
                let offset = C64::new((k / 7) as f64 - 3.0, (k % 7) as f64 - 3.0);
                for pairs in bucket.chunks(BATCH) {
                    self.m2l_batch(
                        &mut locals,
                        &multipoles[l as usize],
                        pairs,
                        (offset, wl),
                        used - 1,
                        &mut scratch,
                    );
                }
            }
            parent_locals = locals;
        }
        // L2P: the value of each target's leaf expansion, Re Σ b̃_m ζ^m.
        for (i, &leaf) in self.target_leaf.iter().enumerate() {
            let slot = self.lslot[top][leaf as usize] as usize;
            let b = &parent_locals[slot * terms..slot * terms + used];
            let zeta = &self.powers[i * terms..i * terms + used];
            out[i] = b
                .iter()
                .zip(zeta)
                .map(|(b, z)| b.re * z.re - b.im * z.im)
                .sum();
        }
    }

    /// M2L of every `(target slot, source slot)` pair in `pairs`, all at the scaled offset
    /// `z̃0 = offset` (box width `w`), into `locals`: [`crate::expansion::m2l`]'s formula with
    /// the inner sums of all pairs as one matrix product `T S` (module docs), at order `p`
    /// (at most the tree's; `T`'s leading `p × p` block).
    fn m2l_batch(
        &self,
        locals: &mut [C64],
        multipoles: &[C64],
        pairs: &[(u32, u32)],
        (offset, w): (C64, f64),
        p: usize,
        (s_buf, r_buf): &mut (Vec<f64>, Vec<f64>),
    ) {
        let terms = self.p + 1;
        let m = pairs.len();
        let inv = C64::new(1.0, 0.0) / offset;
        let log = (-(offset * w)).ln();
        // (−1/z̃0)^k, z̃0^{−l} and z̃0^{−l}/l, k, l ∈ 1..=p.
        let mut ipow = Vec::with_capacity(p);
        let mut lpow = Vec::with_capacity(p);
        let mut lpow_l = Vec::with_capacity(p);
        let (mut a, mut b) = (C64::new(1.0, 0.0), C64::new(1.0, 0.0));
        for l in 1..=p {
            a *= -inv;
            b *= inv;
            ipow.push(a);
            lpow.push(b);
            lpow_l.push(b / l as f64);
        }
        // S: column j the real parts of s_k of pair j, column m + j the imaginary parts.
        s_buf.clear();
        s_buf.resize(2 * m * p, 0.0);
        for (j, &(t, s)) in pairs.iter().enumerate() {
            let source = &multipoles[s as usize * terms..(s as usize + 1) * terms];
            let q = source[0];
            let mut b0 = q * log;
            for k in 1..=p {
                let sk = source[k] * ipow[k - 1];
                s_buf[j * p + k - 1] = sk.re;
                s_buf[(m + j) * p + k - 1] = sk.im;
                b0 += sk;
            }
            locals[t as usize * terms] += b0;
        }
        r_buf.clear();
        r_buf.resize(2 * m * p, 0.0);
        let mut r = DMatrixViewMut::from_slice(r_buf, p, 2 * m);
        r.gemm(
            1.0,
            &self.table.view((0, 0), (p, p)),
            &DMatrixView::from_slice(s_buf, p, 2 * m),
            0.0,
        );
        for (j, &(t, s)) in pairs.iter().enumerate() {
            let q = multipoles[s as usize * terms];
            let out = &mut locals[t as usize * terms..(t as usize + 1) * terms];
            for l in 1..=p {
                let sum = C64::new(r_buf[j * p + l - 1], r_buf[(m + j) * p + l - 1]);
                out[l] += lpow[l - 1] * sum - q * lpow_l[l - 1];
            }
        }
    }

    fn width(&self, level: u32) -> f64 {
        self.side / (1u64 << level) as f64
    }

    fn centre(&self, level: u32, ix: usize, iy: usize) -> C64 {
        let w = self.width(level);
        self.origin + C64::new((ix as f64 + 0.5) * w, (iy as f64 + 0.5) * w)
    }

    fn leaf_of(&self, z: C64) -> usize {
        let n = 1usize << self.levels;
        let cell = |t: f64| ((t * n as f64).max(0.0) as usize).min(n - 1);
        cell((z.im - self.origin.im) / self.side) * n + cell((z.re - self.origin.re) / self.side)
    }

    /// Cuts the sources at the leaf grid lines (as [`crate::Fmm`]) and groups them by leaf
    /// ([`crate::tree::cut`]).
    fn cut(&mut self, sources: &[Source]) {
        let grid = (self.origin, self.width(self.levels), 1usize << self.levels);
        let (start, pieces) = crate::tree::cut(sources, grid, |z| self.leaf_of(z));
        // Offsets as `u32`, as every other index of the operator.
        self.leaf_start = start.into_iter().map(|s| s as u32).collect();
        self.pieces = pieces;
    }

    /// The occupied boxes of every level: with pieces, with targets.
    fn occupancy(&mut self) {
        let n = 1usize << self.levels;
        let top = self.levels as usize;
        let mut with_pieces = vec![false; n * n];
        for (leaf, flag) in with_pieces.iter_mut().enumerate() {
            *flag = self.leaf_start[leaf + 1] > self.leaf_start[leaf];
        }
        self.target_leaf = self
            .targets
            .iter()
            .map(|&z| self.leaf_of(z) as u32)
            .collect();
        let mut with_targets = vec![false; n * n];
        for &leaf in &self.target_leaf {
            with_targets[leaf as usize] = true;
        }
        let slots = |flags: &[bool]| -> (Vec<u32>, Vec<u32>) {
            let mut slot = vec![NONE; flags.len()];
            let mut boxes = Vec::new();
            for (b, &f) in flags.iter().enumerate() {
                if f {
                    slot[b] = boxes.len() as u32;
                    boxes.push(b as u32);
                }
            }
            (slot, boxes)
        };
        let coarser = |flags: &[bool], l: u32| -> Vec<bool> {
            let nl = 1usize << l;
            let mut up = vec![false; nl * nl];
            for iy in 0..nl {
                for ix in 0..nl {
                    up[iy * nl + ix] = children(ix, iy).any(|(cx, cy)| flags[cy * 2 * nl + cx]);
                }
            }
            up
        };
        let mut mslot = vec![Vec::new(); top + 1];
        let mut mboxes = vec![Vec::new(); top + 1];
        let mut lslot = vec![Vec::new(); top + 1];
        let mut lboxes = vec![Vec::new(); top + 1];
        let (mut pf, mut tf) = (with_pieces, with_targets);
        for l in (0..=self.levels).rev() {
            (mslot[l as usize], mboxes[l as usize]) = slots(&pf);
            (lslot[l as usize], lboxes[l as usize]) = slots(&tf);
            if l > 0 {
                pf = coarser(&pf, l - 1);
                tf = coarser(&tf, l - 1);
            }
        }
        self.mslot = mslot;
        self.mboxes = mboxes;
        self.lslot = lslot;
        self.lboxes = lboxes;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Re ∫_{[A,B]} log(z − s)|ds|` in closed form: half of
    /// `W = (xo+a)ln r₊² − (xo−a)ln r₋² − 4a + 2yo·θ` in the segment's frame.
    fn segment_potential(z: C64, a: C64, b: C64) -> f64 {
        let len = (b - a).norm();
        let t = (b - a) / len;
        let d = (z - (a + b) * 0.5) * t.conj();
        let (xo, yo, h) = (d.re, d.im, len / 2.0);
        let rp = (xo + h) * (xo + h) + yo * yo;
        let rm = (xo - h) * (xo - h) + yo * yo;
        let theta = (2.0 * h * yo).atan2((xo - h) * (xo + h) + yo * yo);
        0.5 * ((xo + h) * rp.ln() - (xo - h) * rm.ln() - 4.0 * h + 2.0 * yo * theta)
    }

    /// The batched M2L is `crate::expansion::m2l` pair by pair, to rounding, at every offset
    /// of an interaction list (the two differ only in the order of the inner sums).
    #[test]
    fn the_batched_m2l_is_the_pairwise_m2l() {
        let sources = [Source::Segment(C64::new(0.0, 0.0), C64::new(1.0, 0.5))];
        let op = Operator::new(&sources, &[C64::new(0.2, 0.1)], &Options::default()).unwrap();
        let p = op.order();
        let terms = p + 1;
        // Three source multipoles with decaying pseudo-random coefficients, a charge first.
        let multipoles: Vec<C64> = (0..3 * terms)
            .map(|i| {
                let (j, k) = (i / terms, i % terms);
                let x = (
                    (i * 7919 % 101) as f64 / 50.0 - 1.0,
                    (i * 104729 % 97) as f64 / 48.0 - 1.0,
                );
                if k == 0 {
                    C64::new(0.5 + j as f64, 0.0)
                } else {
                    C64::new(x.0, x.1) * 0.5_f64.powi(k as i32)
                }
            })
            .collect();
        let w = 0.37;
        let table = m2l_table(p);
        let mut scratch = (Vec::new(), Vec::new());
        let mut worst = 0.0_f64;
        for dx in -3_i32..=3 {
            for dy in -3_i32..=3 {
                if dx.abs() <= 1 && dy.abs() <= 1 {
                    continue;
                }
                let offset = C64::new(f64::from(dx), f64::from(dy));
                let pairs = [(0u32, 2u32), (1, 0), (0, 1)];
                let mut batched = vec![C64::new(0.0, 0.0); 2 * terms];
                op.m2l_batch(
                    &mut batched,
                    &multipoles,
                    &pairs,
                    (offset, w),
                    p,
                    &mut scratch,
                );
                let mut pairwise = vec![C64::new(0.0, 0.0); 2 * terms];
                for &(t, s) in &pairs {
                    let (t, s) = (t as usize, s as usize);
                    crate::expansion::m2l(
                        &mut pairwise[t * terms..(t + 1) * terms],
                        &multipoles[s * terms..(s + 1) * terms],
                        offset * w,
                        w,
                        &table,
                    );
                }
                for (a, b) in batched.iter().zip(&pairwise) {
                    worst = worst.max((a - b).norm() / b.norm().max(1.0));
                }
            }
        }
        assert!(worst < 1e-13, "{worst:e}");
    }

    /// Sources, targets, weights and `A = Σ_j |q_j| L_j`.
    type Case = (Vec<Source>, Vec<C64>, Vec<f64>, f64);

    /// Segments along two nested squares' boundaries with targets beside their midpoints,
    /// their weights, and `A = Σ_j |q_j| L_j`.
    fn nested_squares() -> Case {
        let mut sources = Vec::new();
        for (half, count, c) in [
            (1.0, 200, C64::new(0.0, 0.0)),
            (0.2, 40, C64::new(0.3, -0.1)),
        ] {
            let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
            for side in 0..4 {
                let (x0, y0) = corners[side];
                let (x1, y1) = corners[(side + 1) % 4];
                for i in 0..count / 4 {
                    let t0 = i as f64 / (count / 4) as f64;
                    let t1 = (i + 1) as f64 / (count / 4) as f64;
                    let p = |t: f64| c + C64::new(x0 + (x1 - x0) * t, y0 + (y1 - y0) * t) * half;
                    sources.push(Source::Segment(p(t0), p(t1)));
                }
            }
        }
        let targets: Vec<C64> = sources
            .iter()
            .map(|s| match *s {
                Source::Segment(a, b) => (a + b) * 0.5 + C64::new(1e-3, 2e-3),
                Source::Point(z) => z,
            })
            .collect();
        let weights: Vec<f64> = (0..sources.len())
            .map(|j| ((j * 37 % 11) as f64 - 5.0) * 0.3)
            .collect();
        let total: f64 = sources
            .iter()
            .zip(&weights)
            .map(|(s, q)| match *s {
                Source::Segment(a, b) => q.abs() * (b - a).norm(),
                Source::Point(_) => q.abs(),
            })
            .sum();
        (sources, targets, weights, total)
    }

    /// [`nested_squares`] and its operator at tolerance 1e-12, four pieces a leaf.
    fn nested_squares_operator() -> (Operator, Case) {
        let case = nested_squares();
        let options = Options {
            tolerance: 1e-12,
            leaf_size: 4,
            ..Options::default()
        };
        (Operator::new(&case.0, &case.1, &options).unwrap(), case)
    }

    /// The largest error of the far part at order `q` plus the near pieces (closed form)
    /// against the direct sum over every target.
    fn worst_error(op: &Operator, case: &Case, q: usize) -> f64 {
        let (sources, targets, weights, _) = case;
        let mut out = vec![0.0; targets.len()];
        op.apply_order(weights, &mut out, q);
        let mut worst = 0.0_f64;
        for (i, &z) in targets.iter().enumerate() {
            let mut near = 0.0;
            op.near(i, |piece| {
                if let Source::Segment(a, b) = piece.shape {
                    near += weights[piece.source] * segment_potential(z, a, b);
                }
            });
            let direct: f64 = sources
                .iter()
                .zip(weights)
                .map(|(s, q)| match *s {
                    Source::Segment(a, b) => q * segment_potential(z, a, b),
                    Source::Point(p) => q * (z - p).norm().ln(),
                })
                .sum();
            worst = worst.max((out[i] + near - direct).abs());
        }
        worst
    }

    /// The far part plus the near pieces is the whole sum, to the tolerance, on segments along
    /// two nested squares' boundaries.
    #[test]
    fn far_plus_near_is_the_direct_sum() {
        let (op, case) = nested_squares_operator();
        assert!(op.levels() >= 3);
        let mut full = vec![0.0; case.1.len()];
        op.apply(&case.2, &mut full);
        let mut at_p = vec![0.0; case.1.len()];
        op.apply_order(&case.2, &mut at_p, op.order());
        assert_eq!(full, at_p, "apply is apply_order at p");
        let worst = worst_error(&op, &case, op.order());
        assert!(
            worst <= 1e-12 * case.3 + 1e-11,
            "{worst:e} (A = {})",
            case.3
        );
    }

    /// A product at a lower order is within that order's tolerance, and truncated (at 1e-4
    /// and 1e-6 its error is well above the full order's: the negative control that the order
    /// is used).
    #[test]
    fn a_lower_order_keeps_its_own_tolerance() {
        let (op, case) = nested_squares_operator();
        let full = worst_error(&op, &case, op.order());
        assert_eq!(op.order_for(1e-13), op.order());
        assert_eq!(op.order_for(2.0), op.order());
        for tol in [1e-4, 1e-6, 1e-9] {
            let q = op.order_for(tol);
            assert!(q < op.order(), "{tol:e}: {q}");
            let worst = worst_error(&op, &case, q);
            assert!(worst <= tol * case.3, "{tol:e}, q = {q}: {worst:e}");
            // (Far below its bound at 1e-9, the truncation sinks into the rounding.)
            if tol >= 1e-6 {
                assert!(
                    worst > 100.0 * full,
                    "{tol:e}, q = {q}: {worst:e} against {full:e}"
                );
            }
        }
    }
}
