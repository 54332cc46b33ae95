//! # harmonav-harmonic
//!
//! The harmonic map `H` of a polygonal free space with polygonal holes onto the punctured unit
//! disk, by boundary elements, with its exact Jacobian and a certificate of `det J_H > 0` away
//! from the boundary. It is the `H` of the floor-plan transformation `Phi = S ∘ H ∘ B`
//! (issue 25, docs/maths.md §11); harmonav-floorplan composes it (§13).
//!
//! **The theorem** (Radó–Kneser–Choquet; Duren & Hengartner for finitely connected domains):
//! if `u, v` are harmonic in `W_s`, the outer boundary goes monotonically onto the unit circle,
//! and each hole `P_i` goes to a single point `p_i` with zero net flux of `u` and `v` across
//! it, then `H = (u, v)` is a diffeomorphism of `W_s` onto the disk minus the points `p_i`.
//!
//! **The construction** ([`HarmonicMap::new`]): `N` straight elements, graded toward corners
//! ([`mesh`]); per component a piecewise-constant single layer plus a constant,
//!
//! ```text
//! u(x) = Σ_j k_j ∫_{E_j} ln|z − s|² ds + c,      z = (x − x̄)/D,
//! ```
//!
//! with the element integral and its gradient in closed form (`src/kernel.rs`):
//! `W = (xo+a)ln r₊² − (xo−a)ln r₋² − 4a + 2yo·θ`, `θ = atan2(2a·yo, (xo−a)(xo+a) + yo²)`,
//! `∇W = (ln(r₊²/r₋²), 2θ)` in the element's frame. Collocation at the midpoints gives
//! `u(c_j) = cos 2πs_j` on the outer ring (`s_j` normalised arc length), `u(c_j) = p_i` on
//! hole `i`; one zero-charge row per hole is exactly zero flux (`Δ ln|x|² = 4πδ`); a zero-total-
//! charge row pairs with `c`, which removes the 2-D single layer's degenerate scale. One LU
//! (faer) of the `(N + M + 1)²` matrix serves `u` and `v`; the punctures `p_i` are unknowns.
//!
//! **Evaluation** ([`HarmonicMap::eval`]): `H(x)` and `J_H(x)` exactly (no differences), in
//! f64. Directly ([`HarmonicMap::eval_direct`]) it is `O(N)`, two logarithms and one `atan2`
//! per element. From [`FAR_FIELD_MIN_ELEMENTS`] elements the far field takes over: a fast
//! multipole tree (harmonav-multipole) of the single layers `u = Re Σ_j 2k^u_j G_j + c_u`,
//! `G_j(z) = ∫_{E_j} log(z − s)|ds|`, `∇u = (Re F', −Im F')`, sums the elements beyond the
//! 3 × 3 leaves about `x` to [`FAR_FIELD_TOLERANCE`], and the closed form adds the near pieces
//! exactly; the two paths agree to about 1e-14 of the map's scale (tested ≤ 1e-12).
//!
//! **The guarantee, honestly** ([`certify`], [`sampled_check`]): the discrete map folds only
//! in a layer about half an element thick along the boundary (docs/maths.md §11 has the
//! measurements), so the claim is made on `W_δ = {dist(x, ∂W_s) ≥ δ}` with `δ ≥ h`.
//! [`certify`] covers `W_δ` with cells decided by a Lipschitz bound on `det J_H` and `|H|`;
//! [`sampled_check`] only samples.
//!
//! Catalogue:
//! - [`Domain`] (validated rings, typed [`DomainError`]), [`RingId`];
//! - [`MeshOptions`], [`mesh::mesh`], [`Element`] (graded elements, [`MAX_ELEMENTS`]);
//! - [`HarmonicMap`] (`new`, `eval`, `eval_direct`, `with_far_field`, `far_field_bound`,
//!   `setup_cost`, `punctures`, `hole_flux`, `residuals`), [`MapEval`], [`SetupCost`],
//!   [`FAR_FIELD_MIN_ELEMENTS`], [`FAR_FIELD_TOLERANCE`], typed [`SolveError`], [`EvalError`];
//! - [`certify`] → [`Certificate`] with a [`Verdict`]; [`sampled_check`] → [`Extremes`].
//!
//! ```
//! use harmonav_harmonic::{certify, CertifyOptions, Domain, HarmonicMap, MeshOptions, Verdict};
//! use nalgebra::Vector2;
//!
//! let v = Vector2::new;
//! // A 2 m square room (counter-clockwise) with a 0.4 m pillar (clockwise).
//! let room = vec![v(-1.0, -1.0), v(1.0, -1.0), v(1.0, 1.0), v(-1.0, 1.0)];
//! let pillar = vec![v(-0.2, -0.2), v(-0.2, 0.2), v(0.2, 0.2), v(0.2, -0.2)];
//! let domain = Domain::new(room, vec![pillar])?;
//! let map = HarmonicMap::new(&domain, &MeshOptions::graded(0.25))?;
//! // By symmetry the pillar collapses to the centre of the disk, with zero flux.
//! assert!(map.punctures()[0].norm() < 1e-10);
//! assert!(map.hole_flux(0).unwrap().norm() < 1e-10);
//! let e = map.eval(v(0.6, 0.1))?;
//! assert!(e.value.norm() < 1.0 && e.det() > 0.0);
//! let c = certify(&map, &CertifyOptions::new(0.3))?;
//! assert!(!matches!(c.verdict, Verdict::Fold { .. }) && c.extremes.min_det > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod certificate;
pub mod domain;
mod kernel;
pub mod map;
pub mod mesh;
mod solve;

pub use certificate::{
    Certificate, CertifyError, CertifyOptions, Extremes, Verdict, certify, sampled_check,
};
pub use domain::{Domain, DomainError, RingId};
pub use map::{
    DENSE_LIMIT, DENSE_MAX_ELEMENTS, Enclosure, EvalError, FAR_FIELD_MIN_ELEMENTS,
    FAR_FIELD_TOLERANCE, HarmonicMap, MapEval, Residuals, SetupCost, SolveError, Solver,
};
pub use mesh::{Element, MAX_ELEMENTS, MeshError, MeshOptions};
