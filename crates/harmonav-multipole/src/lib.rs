//! # harmonav-multipole
//!
//! Fast sums of 2-D logarithmic potentials: for sources `j` with real weights `q_{j,c}` in `C`
//! channels,
//!
//! ```text
//! F_c(z) = Σ_j q_{j,c} G_j(z),    G_j(z) = log(z − z_j)                (a point z_j)
//!                                 G_j(z) = ∫_{[A_j,B_j]} log(z − s)|ds|  (a segment, uniform)
//! ```
//!
//! and `Re F_c = Σ_j q_{j,c} ln|z − ·|` (the potential), `F'_c` (its complex gradient:
//! `∇ Re F = (Re F', −Im F')`) and `F''_c` (its Hessian) at any `z`, in `O(p + near)` per point
//! instead of `O(N)`. harmonav uses it for the point-world sum of `phi_k` with many obstacles and
//! for the single layers of the harmonic map of a floor plan (docs/maths.md §15).
//!
//! **The method** ([`Fmm::new`]): the fast multipole method of Greengard & Rokhlin (1987) on a
//! uniform quadtree of `L` levels. Each segment is cut at the leaf grid lines (the integral is
//! additive), so every piece lies in its leaf box; multipoles are formed at the leaves (P2M, in
//! closed form for segments), shifted up (M2M), turned into local expansions over each box's
//! interaction list (M2L) and shifted down (L2L). All expansions are scaled by their box width,
//! so a 1 mm world and a 10 km world are the same computation (`expansion.rs`).
//!
//! **Evaluation** ([`Fmm::eval`]): inside the root box, the leaf's local expansion gives the far
//! field, and the caller adds the pieces of the 3 × 3 leaves about it with its own exact kernel
//! (a closure receives each near [`Piece`]): the near field stays exactly the caller's, the
//! guarded logarithms and closed forms included. Outside the root box a Barnes–Hut walk takes a
//! box's multipole when its disc is at most `ρ = 1/2` of the distance, and otherwise its children
//! (the caller again gets the leaves' pieces).
//!
//! **Accuracy** ([`Options::tolerance`]): truncation at order `p` leaves an error of order
//! `A·ρ^p` with `A = Σ_j |q_j|·(1 or L_j)` the absolute charge and `ρ ≈ 0.55` the worst ratio of
//! the uniform method; `p` is chosen from the tolerance as `⌈ln(tol)/ln 0.55⌉ + 2`
//! (`tol = 1e-13` gives `p = 53`). Tested against the direct sums (`tests/direct.rs`):
//! `|ΔRe F| ≤ tol·A` and `|ΔF'| ≤ tol·A/w_leaf` on random and adversarial (corner-packed)
//! sources, at scales from 1e-3 to 1e6.
//!
//! **Adding a point** ([`Fmm::push_point`]): its P2L into every far leaf (with fewer terms in
//! farther rings of leaves, within the same truncation bound) and P2M into its ancestors,
//! `O(4^L)` leaves, no rebuild; a point outside the root box is refused
//! ([`FmmError::OutsideRoot`]) and the caller rebuilds.
//!
//! **A matrix–vector product** ([`Operator`]): fixed sources and fixed target points, new
//! weights per product, on a sparse tree (only occupied boxes): the far part of `A q` with
//! `A_ij = Re G_j(t_i)`, the near pieces left to the caller. The iterative boundary-element
//! solve of harmonav-harmonic uses it (docs/maths/13-harmonic-scaling.md).

#![warn(missing_docs)]

mod expansion;
mod operator;
mod tree;

pub use expansion::{C64, Values};
pub use operator::Operator;
pub use tree::{Fmm, FmmError, Options, Piece, Shape, Source};
