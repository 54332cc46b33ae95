//! The expansions and their translations (Greengard & Rokhlin 1987, *A fast algorithm for
//! particle simulations*, Lemmas 2.3–2.5), **scaled** by the box width `w` so that no power of a
//! coordinate over- or underflows whatever the world's size:
//!
//! ```text
//! multipole about c:  F(z) = Q log(z − c) + Σ_{m=1..p} ã_m (w/(z − c))^m       (eq. mp)
//! local about c:      F(z) = Σ_{m=0..p} b̃_m ((z − c)/w)^m                       (eq. loc)
//! ```
//!
//! `F(z) = Σ_j q_j G_j(z)` with `G_j(z) = log(z − z_j)` (a point) or `∫_{[A,B]} log(z − s)|ds|`
//! (a segment of uniform density). Only `Re F`, `F'` and `F''` are meaningful: the imaginary part
//! of `F` depends on the branch of each logarithm, and no caller uses it.
//!
//! Coefficient arrays have `p + 1` entries; entry 0 of a multipole is `Q` (the total charge).

use nalgebra::Complex;

/// A complex number in f64.
pub type C64 = Complex<f64>;

const ZERO: C64 = C64::new(0.0, 0.0);
const ONE: C64 = C64::new(1.0, 0.0);

/// Pascal's triangle up to row `n`, `binom[n][k] = C(n, k)` (exact in f64 up to `n = 56`,
/// correctly rounded above: the translations use rows up to `2p`).
pub(crate) fn pascal(n: usize) -> Vec<Vec<f64>> {
    let mut rows: Vec<Vec<f64>> = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let mut row = vec![1.0; i + 1];
        for k in 1..i {
            row[k] = rows[i - 1][k - 1] + rows[i - 1][k];
        }
        rows.push(row);
    }
    rows
}

/// P2M of a point charge `q` at `z0`, added to `a` (box centre `c`, width `w`):
/// `Q += q`, `ã_m −= q ((z0 − c)/w)^m / m` (eq. mp).
pub(crate) fn p2m_point(a: &mut [C64], q: f64, z0: C64, c: C64, w: f64) {
    a[0] += q;
    let t = (z0 - c) / w;
    let mut power = ONE;
    for (m, am) in a.iter_mut().enumerate().skip(1) {
        power *= t;
        *am -= power * (q / m as f64);
    }
}

/// P2M of a segment `[A, B]` of uniform density `q` (charge `q·L`):
/// `ã_m −= (q/m)·∫_{[A,B]} ((s − c)/w)^m |ds| = (q/m)·L·S_m/(m + 1)`, where
/// `S_m = Σ_{i=0..m} β^i α^{m−i}` (`α = (A − c)/w`, `β = (B − c)/w`) is `(β^{m+1} − α^{m+1})/(β − α)`
/// summed without the cancellation of that difference: `S_m = β S_{m−1} + α^m`.
pub(crate) fn p2m_segment(a: &mut [C64], q: f64, ends: (C64, C64), c: C64, w: f64) {
    let (alpha, beta) = ((ends.0 - c) / w, (ends.1 - c) / w);
    let length = (ends.1 - ends.0).norm();
    a[0] += q * length;
    let (mut s, mut alpha_m) = (ONE, ONE);
    for (m, am) in a.iter_mut().enumerate().skip(1) {
        alpha_m *= alpha;
        s = beta * s + alpha_m;
        *am -= s * (q * length / (m as f64 * (m as f64 + 1.0)));
    }
}

/// M2M (Lemma 2.3): the multipole `child` of a box of width `w/2` centred at `c + d` shifted to
/// its parent of width `w` centred at `c` and added to `parent`; `d̃ = d/w`:
/// `b̃_l = −Q d̃^l / l + Σ_{k=1..l} ã_k 2^{−k} d̃^{l−k} C(l−1, k−1)`.
pub(crate) fn m2m(parent: &mut [C64], child: &[C64], d: C64, binom: &[Vec<f64>]) {
    let p = child.len() - 1;
    let q = child[0];
    parent[0] += q;
    // Child coefficients in the parent's scale: ã_k 2^{−k}.
    let mut scaled = [ZERO; MAX_TERMS];
    let mut half = 1.0;
    for k in 1..=p {
        half *= 0.5;
        scaled[k] = child[k] * half;
    }
    let mut dpow = [ONE; MAX_TERMS];
    for l in 1..=p {
        dpow[l] = dpow[l - 1] * d;
    }
    for l in 1..=p {
        let mut acc = -q * dpow[l] / l as f64;
        for k in 1..=l {
            acc += scaled[k] * dpow[l - k] * binom[l - 1][k - 1];
        }
        parent[l] += acc;
    }
}

/// The binomials of M2L laid out flat, `m2l_table(p)[l·(p + 1) + k] = C(l + k − 1, k − 1)` for
/// `l, k ∈ 1..=p` (contiguous in `k`, so [`m2l`]'s inner sums vectorise).
pub(crate) fn m2l_table(p: usize) -> Vec<f64> {
    let binom = pascal(2 * p);
    let mut table = vec![0.0; (p + 1) * (p + 1)];
    for l in 1..=p {
        for k in 1..=p {
            table[l * (p + 1) + k] = binom[l + k - 1][k - 1];
        }
    }
    table
}

/// M2L (Lemma 2.4): the multipole `source` (width `w`, centre `c_s`) as a local expansion about
/// `c_t` (width `w`), added to `local`; `z̃0 = (c_s − c_t)/w`, `|z̃0| ≥ 2`:
/// `b̃_0 = Q log(−z0) + Σ_k ã_k (−1)^k / z̃0^k`,
/// `b̃_l = −Q/(l z̃0^l) + z̃0^{−l} Σ_k ã_k (−1)^k C(l+k−1, k−1) / z̃0^k`
/// (`table` from [`m2l_table`]).
pub(crate) fn m2l(local: &mut [C64], source: &[C64], z0: C64, w: f64, table: &[f64]) {
    let p = source.len() - 1;
    let q = source[0];
    let zt = z0 / w;
    let inv = ONE / zt;
    // s_k = ã_k (−1)^k / z̃0^k, split into real and imaginary parts for the inner sums.
    let (mut s_re, mut s_im) = ([0.0; MAX_TERMS], [0.0; MAX_TERMS]);
    let mut ipow = ONE;
    let mut b0 = q * (-z0).ln();
    for k in 1..=p {
        ipow *= -inv;
        let sk = source[k] * ipow;
        (s_re[k], s_im[k]) = (sk.re, sk.im);
        b0 += sk;
    }
    local[0] += b0;
    let mut lpow = ONE;
    for l in 1..=p {
        lpow *= inv;
        let row = &table[l * (p + 1) + 1..(l + 1) * (p + 1)];
        let (re, im) = dot2(row, &s_re[1..=p], &s_im[1..=p]);
        local[l] += lpow * (C64::new(re, im) - q / l as f64);
    }
}

/// `(Σ t_k a_k, Σ t_k b_k)` with four independent partial sums per result, so the additions
/// do not wait on each other (a single running sum is latency-bound: floating-point addition
/// cannot be reordered by the compiler) and the lanes vectorise.
#[inline(always)]
fn dot2(t: &[f64], a: &[f64], b: &[f64]) -> (f64, f64) {
    let (mut ra, mut rb) = ([0.0f64; 4], [0.0f64; 4]);
    let n = t.len() / 4 * 4;
    for ((t, a), b) in t[..n]
        .chunks_exact(4)
        .zip(a[..n].chunks_exact(4))
        .zip(b[..n].chunks_exact(4))
    {
        for i in 0..4 {
            ra[i] += t[i] * a[i];
            rb[i] += t[i] * b[i];
        }
    }
    let (mut sa, mut sb) = (
        (ra[0] + ra[1]) + (ra[2] + ra[3]),
        (rb[0] + rb[1]) + (rb[2] + rb[3]),
    );
    for i in n..t.len() {
        sa += t[i] * a[i];
        sb += t[i] * b[i];
    }
    (sa, sb)
}

/// L2L (Lemma 2.5): the local `parent` (width `w`, centre `c`) re-expanded about its child's
/// centre `c + d` (width `w/2`) and added to `child`; `d̃ = d/w`:
/// `b̃'_l = 2^{−l} Σ_{k≥l} b̃_k C(k, l) d̃^{k−l}`.
pub(crate) fn l2l(child: &mut [C64], parent: &[C64], d: C64, binom: &[Vec<f64>]) {
    let p = parent.len() - 1;
    let mut dpow = [ONE; MAX_TERMS];
    for l in 1..=p {
        dpow[l] = dpow[l - 1] * d;
    }
    let mut half = 1.0;
    for l in 0..=p {
        let mut acc = ZERO;
        for k in l..=p {
            acc += parent[k] * dpow[k - l] * binom[k][l];
        }
        child[l] += acc * half;
        half *= 0.5;
    }
}

/// The reference form of [`p2l_point_batch`] (one expansion; kept for its test).
///
/// P2L of a point charge `q` at `z0` into the local expansion about `c` (width `w`), for `z0`
/// outside the disc of the expansion: `log(z − z0) = log(c − z0) + log(1 + (z − c)/(c − z0))`,
/// so `b̃_0 += q ln|c − z0|` (the real part of `q log(c − z0)`: the imaginary part of `F` is
/// not used, and `ln|·|` needs no `atan2`) and `b̃_m += q (−1)^{m+1} (w/(c − z0))^m / m`.
#[cfg(test)]
pub(crate) fn p2l_point(local: &mut [C64], q: f64, z0: C64, c: C64, w: f64) {
    // `v/w` is a real division; `ln|v| = ln w + ½ ln|v/w|²` and `w/v = 1/(v/w)`: `|v|²` itself
    // overflows for coordinates beyond about 1e154, `|v/w|²` (a few leaf widths) does not.
    let v = (c - z0) / w;
    local[0].re += q * (w.ln() + 0.5 * v.norm_sqr().ln());
    let t = -v.inv();
    let mut power = -ONE;
    for (m, bm) in local.iter_mut().enumerate().skip(1) {
        power *= t;
        *bm += power * (q / m as f64);
    }
}

/// How many local expansions [`p2l_point_batch`] fills at once.
pub(crate) const P2L_BATCH: usize = 8;

/// [`p2l_point`] into up to [`P2L_BATCH`] local expansions at once, `locals[start_j..start_j +
/// terms]` about `centres[j]` for `j < count` (all of width `w`). The same operations in the same
/// order per expansion (bit-identical to [`p2l_point`]), but the `P2L_BATCH` chains
/// `power_j *= t_j` are independent, so the processor overlaps their multiplications instead of
/// waiting on one chain; the coefficients `q/m` are computed once for the batch.
pub(crate) fn p2l_point_batch(
    locals: &mut [C64],
    starts: &[usize; P2L_BATCH],
    centres: &[C64; P2L_BATCH],
    count: usize,
    terms: usize,
    (q, z0, w): (f64, C64, f64),
) {
    let count = count.min(P2L_BATCH);
    let mut t = [ZERO; P2L_BATCH];
    let ln_w = w.ln();
    for j in 0..count {
        // As in `p2l_point`: through `v/w`, no overflow through `|v|²`.
        let v = (centres[j] - z0) / w;
        locals[starts[j]].re += q * (ln_w + 0.5 * v.norm_sqr().ln());
        t[j] = -v.inv();
    }
    let mut power = [-ONE; P2L_BATCH];
    for m in 1..terms {
        let coef = q / m as f64;
        // Unused lanes multiply zeros: a fixed width keeps the loop unrolled.
        for j in 0..P2L_BATCH {
            power[j] *= t[j];
        }
        for j in 0..count {
            locals[starts[j] + m] += power[j] * coef;
        }
    }
}

/// The three values of an expansion at a point: `Re F`, `F'` and `F''`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Values {
    /// `Re F(z)`.
    pub value: f64,
    /// `F'(z)`.
    pub d1: C64,
    /// `F''(z)` (zero when not asked for).
    pub d2: C64,
}

/// Eq. loc at `z`: `ζ = (z − c)/w`, `F = Σ b̃_m ζ^m`, `F' = (1/w) Σ m b̃_m ζ^{m−1}` and
/// `F'' = (1/w²) Σ m(m−1) b̃_m ζ^{m−2}`, each summed as `E(ζ²) + ζ·O(ζ²)` (its even and odd
/// powers apart, Horner in `s = ζ²` for both). The chains of dependent complex multiplications
/// are then half as long and independent of each other: one Horner chain in `ζ` of `p + 1`
/// terms was the critical path of the whole evaluation. `|s| ≤ ½` inside the leaf, so both
/// halves are as well conditioned as the single chain (compared with it in the tests).
pub(crate) fn eval_local<const SECOND: bool>(b: &[C64], z: C64, c: C64, w: f64) -> Values {
    let zeta = (z - c) / w;
    let s = zeta * zeta;
    let n = b.len();
    let at = |i: usize| if i < n { b[i] } else { ZERO };
    // `[even, odd]` sums of `F`, `wF'` and `w²F''`; terms past the last coefficient are zero.
    let (mut f, mut d1, mut d2) = ([ZERO; 2], [ZERO; 2], [ZERO; 2]);
    for j in (0..n.div_ceil(2)).rev() {
        let k = 2 * j;
        let kf = k as f64;
        let (b0, b1, b2) = (at(k), at(k + 1), at(k + 2));
        f = [f[0] * s + b0, f[1] * s + b1];
        d1 = [d1[0] * s + b1 * (kf + 1.0), d1[1] * s + b2 * (kf + 2.0)];
        if SECOND {
            let b3 = at(k + 3);
            d2 = [
                d2[0] * s + b2 * ((kf + 1.0) * (kf + 2.0)),
                d2[1] * s + b3 * ((kf + 2.0) * (kf + 3.0)),
            ];
        }
    }
    let join = |[even, odd]: [C64; 2]| even + zeta * odd;
    Values {
        value: join(f).re,
        d1: join(d1) / w,
        d2: if SECOND { join(d2) / (w * w) } else { ZERO },
    }
}

/// Eq. mp at `z` (outside the box's disc): with `t = w/(z − c)`,
/// `F = Q log(z − c) + Σ ã_m t^m`, `F' = (Q − Σ m ã_m t^m)/(z − c)`,
/// `F'' = (−Q + Σ m(m+1) ã_m t^m)/(z − c)²`.
pub(crate) fn eval_multipole<const SECOND: bool>(a: &[C64], z: C64, c: C64, w: f64) -> Values {
    let v = z - c;
    // `w/v` as `1/(v/w)` (see `p2l_point`), and `1/v = t/w` below.
    let t = (v / w).inv();
    let q = a[0];
    // Odd and even powers apart (`t^{m+2} = t^m·t²`): two independent chains of half the
    // length, each with its own partial sums (as eq. loc's `E + ζO`).
    let t2 = t * t;
    let mut power = [t, t2];
    let (mut s0, mut s1, mut s2) = ([ZERO; 2], [ZERO; 2], [ZERO; 2]);
    for (i, am) in a.iter().enumerate().skip(1) {
        let (m, lane) = (i as f64, (i + 1) & 1);
        let term = am * power[lane];
        power[lane] *= t2;
        s0[lane] += term;
        s1[lane] += term * m;
        if SECOND {
            s2[lane] += term * (m * (m + 1.0));
        }
    }
    let (s0, s1, s2) = (s0[0] + s0[1], s1[0] + s1[1], s2[0] + s2[1]);
    let inv = t / w;
    Values {
        value: (q * v.ln() + s0).re,
        d1: (q - s1) * inv,
        d2: if SECOND { (s2 - q) * inv * inv } else { ZERO },
    }
}

/// The largest expansion order plus one that the fixed-size scratch arrays hold.
pub(crate) const MAX_TERMS: usize = 97;

#[cfg(test)]
mod tests {
    use super::*;

    /// The odd and even power chains of eq. mp against one chain `t^m = t^{m−1}·t` (the form
    /// before), for every order, at points from just outside the Barnes–Hut radius to far away.
    #[test]
    fn the_split_multipole_powers_match_one_chain() {
        let (c, w) = (C64::new(-1.0, 2.0), 0.5);
        for terms in 1..=MAX_TERMS {
            let a: Vec<C64> = (0..terms)
                .map(|m| C64::from_polar(0.9f64.powi(m as i32), 1.3 * m as f64))
                .collect();
            for &(r, angle) in &[(1.42, 0.3), (3.0, 2.0), (40.0, -1.0)] {
                let z = c + C64::from_polar(r * w, angle);
                let v = z - c;
                let t = (v / w).inv();
                let (mut s0, mut s1, mut s2, mut power) = (ZERO, ZERO, ZERO, ONE);
                for (m, am) in a.iter().enumerate().skip(1) {
                    power *= t;
                    let term = am * power;
                    s0 += term;
                    s1 += term * m as f64;
                    s2 += term * (m as f64 * (m as f64 + 1.0));
                }
                let (q, inv) = (a[0], t / w);
                let got = eval_multipole::<true>(&a, z, c, w);
                // Of order 1 (in units of 1/w, 1/w²); measured at most 1.1e-16, 5.0e-16, 9.0e-16.
                assert!(
                    (got.value - (q * v.ln() + s0).re).abs() <= 1e-14,
                    "{terms} {r}"
                );
                assert!(
                    (got.d1 - (q - s1) * inv).norm() * w <= 1e-14,
                    "{terms} {r} d1"
                );
                assert!(
                    (got.d2 - (s2 - q) * inv * inv).norm() * w * w <= 1e-13,
                    "{terms} {r} d2"
                );
            }
        }
    }

    /// The even/odd sums of eq. loc against one Horner chain in `ζ` (the form before), for
    /// every order from 1 to 97 terms, coefficients decaying as a local
    /// expansion's do (`|b̃_m| ~ 0.7^m`), at points over the whole leaf (`|ζ| ≤ √2/2`).
    #[test]
    fn the_split_sums_match_one_horner_chain() {
        let (c, w) = (C64::new(3.0, -2.0), 0.25);
        for terms in 1..=MAX_TERMS {
            let b: Vec<C64> = (0..terms)
                .map(|m| {
                    C64::from_polar(
                        0.7f64.powi(m as i32) * (1.0 + 0.1 * m as f64),
                        0.9 * m as f64,
                    )
                })
                .collect();
            for &(x, y) in &[
                (0.5, 0.5),
                (-0.5, 0.5),
                (0.0, 0.0),
                (0.31, -0.47),
                (-0.5, -0.5),
            ] {
                let z = c + C64::new(x, y) * w;
                let zeta = (z - c) / w;
                let (mut f, mut f1, mut f2) = (b[terms - 1], ZERO, ZERO);
                for m in (0..terms - 1).rev() {
                    f2 = f2 * zeta + f1 * 2.0;
                    f1 = f1 * zeta + f;
                    f = f * zeta + b[m];
                }
                // Measured at most 2.2e-16, 5.0e-16 and 1.8e-15 (the sums are of order 1).
                let got = eval_local::<true>(&b, z, c, w);
                assert!(
                    (got.value - f.re).abs() <= 2e-15,
                    "{terms}: {} {}",
                    got.value,
                    f.re
                );
                assert!((got.d1 - f1 / w).norm() * w <= 5e-15, "{terms} d1");
                assert!(
                    (got.d2 - f2 / (w * w)).norm() * w * w <= 2e-14,
                    "{terms} d2"
                );
                let first = eval_local::<false>(&b, z, c, w);
                assert_eq!((first.value, first.d1), (got.value, got.d1));
                assert_eq!(first.d2, ZERO);
            }
        }
    }

    /// The batched P2L gives the single one's coefficients to the bit, for every batch size,
    /// and leaves every slot outside its `count` expansions untouched.
    #[test]
    fn batched_p2l_is_bit_identical_to_the_single_one() {
        let terms = 52;
        let (q, z0, w) = (0.7, C64::new(0.31, -0.42), 0.25);
        let centres: [C64; P2L_BATCH] =
            std::array::from_fn(|j| C64::new(1.1 - 0.9 * j as f64, 0.9 + 1.7 * (j % 3) as f64));
        for count in 0..=P2L_BATCH {
            // Every other expansion of a shared array, with nonzero starting coefficients.
            let seed = |i: usize| C64::new(0.01 * i as f64, -0.003 * i as f64);
            let mut batch: Vec<C64> = (0..2 * P2L_BATCH * terms).map(seed).collect();
            let mut single = batch.clone();
            let starts: [usize; P2L_BATCH] = std::array::from_fn(|j| 2 * j * terms);
            p2l_point_batch(&mut batch, &starts, &centres, count, terms, (q, z0, w));
            for j in 0..count {
                let s = starts[j];
                p2l_point(&mut single[s..s + terms], q, z0, centres[j], w);
            }
            assert_eq!(batch, single, "count {count}");
            if count > 0 {
                assert_ne!(batch[starts[0] + 3], seed(starts[0] + 3), "nothing written");
            }
        }
    }
}

#[cfg(test)]
mod timing {
    use super::*;

    /// Side by side in one run (not a test of speed: `--ignored --nocapture`, release): the P2L
    /// of one point into 247 leaves of 54 terms (`p = 53`, the tree's at the default tolerance), one
    /// expansion at a time against batches.
    #[test]
    #[ignore = "a measurement"]
    fn p2l_single_against_batched() {
        let terms = 54;
        let n = 16;
        let centres: Vec<C64> = (0..n * n)
            .map(|b| C64::new((b % n) as f64 + 0.5, (b / n) as f64 + 0.5))
            .filter(|c| (c.re - 3.5).abs() > 1.5 || (c.im - 3.5).abs() > 1.5)
            .collect();
        let mut locals = vec![ZERO; centres.len() * terms];
        let z0 = C64::new(3.3, 3.6);
        let reps = 2_000;
        for round in 0..3 {
            let t = std::time::Instant::now();
            for _ in 0..reps {
                for (j, &c) in centres.iter().enumerate() {
                    p2l_point(&mut locals[j * terms..(j + 1) * terms], 1.0, z0, c, 1.0);
                }
            }
            let single = t.elapsed().as_secs_f64() / reps as f64 * 1e6;
            let t = std::time::Instant::now();
            for _ in 0..reps {
                for (k, chunk) in centres.chunks(P2L_BATCH).enumerate() {
                    let mut starts = [0; P2L_BATCH];
                    let mut cs = [ZERO; P2L_BATCH];
                    for (j, &c) in chunk.iter().enumerate() {
                        starts[j] = (k * P2L_BATCH + j) * terms;
                        cs[j] = c;
                    }
                    p2l_point_batch(
                        &mut locals,
                        &starts,
                        &cs,
                        chunk.len(),
                        terms,
                        (1.0, z0, 1.0),
                    );
                }
            }
            let batched = t.elapsed().as_secs_f64() / reps as f64 * 1e6;
            println!(
                "round {round}: {} leaves, single {single:.1} µs, batched {batched:.1} µs",
                centres.len()
            );
        }
        assert!(locals.iter().all(|c| c.re.is_finite()));
    }
}
