"""An independent NumPy implementation of Θ and ∇Θ for worlds of discs in a disc.

It follows docs/maths.md §5 from the formulas, not from the Rust code: the band widths
``ε_i = f·min(min_j d(O_i, O_j), d(O_i, ∂O_0), 2 d(x_d, O_i))``, ``ε_0``, the stretch gain
``A = max(ε_0, 2 r*)``, the obstacle and outer radial maps with the smooth step ``beta``,
``φ_k`` on the point world and ``Θ = σ(φ_k)``, ``∇Θ = σ'(φ_k) J_Φᵀ ∇φ_k``. Distances between
discs are exact here; the Rust side measures them on certified outlines (within 1e-4 of the size), so the band widths
(and Θ inside the bands) agree to the outline's chord error, and Θ agrees to rounding outside
the bands. Vectorised over the points; one NumPy pass per obstacle.

Used by the tests (as a reference) and by bench/bench_eval.py (as the NumPy baseline).
"""

import numpy as np

WIDTH_FACTOR = 0.45


def _logistic(w):
    """σ(w) = 1/(1 + e^{−w}) and σ'(w), from e^{−|w|} (no overflow)."""
    e = np.exp(-np.abs(w))
    d = 1.0 + e
    return np.where(w >= 0, 1.0 / d, e / d), e / (d * d)


def _beta(t):
    """The smooth step beta(t) = f(t)/(f(t) + f(1 − t)), f(t) = e^{−1/t}, and beta'(t)."""
    t = np.clip(t, 0.0, 1.0)
    inner = (t > 0) & (t < 1)
    ts = np.where(inner, t, 0.5)
    w = 1.0 / (1.0 - ts) - 1.0 / ts
    b, sp = _logistic(w)
    db = sp * (1.0 / ts**2 + 1.0 / (1.0 - ts) ** 2)
    return np.where(inner, b, np.where(t >= 1, 1.0, 0.0)), np.where(inner, db, 0.0)


class DiscWorld:
    """Θ for `M` discs (centres (M, 2), radii (M,)) in the disc (c0, R0), goal `goal`, with
    `k = factor·(M + 1)` (6 for the policy "auto", 1 for "paper")."""

    def __init__(self, c0, r0, centres, radii, goal, factor=6):
        self.c0 = np.asarray(c0, float)
        self.r0 = float(r0)
        self.p = np.asarray(centres, float).reshape(-1, 2)
        self.r = np.asarray(radii, float)
        self.goal = np.asarray(goal, float)
        m = len(self.r)
        self.k = factor * (m + 1.0)
        gap = np.linalg.norm(self.p[:, None] - self.p[None], axis=2) - self.r[:, None] - self.r[None]
        np.fill_diagonal(gap, np.inf)
        to_wall = self.r0 - np.linalg.norm(self.p - self.c0, axis=1) - self.r
        to_goal = np.linalg.norm(self.goal - self.p, axis=1) - self.r
        self.eps = WIDTH_FACTOR * np.minimum(np.minimum(gap.min(axis=1, initial=np.inf), to_wall), 2 * to_goal)
        goal_wall = self.r0 - np.linalg.norm(self.goal - self.c0)
        self.eps0 = WIDTH_FACTOR * min(to_wall.min(initial=np.inf), 2 * goal_wall)
        dipole = (self.goal - self.c0) - (self.p - self.c0).sum(axis=0) / self.k
        r_star = self.k / (self.k - m) * np.linalg.norm(dipole)
        self.gain = max(self.eps0, 2 * r_star)

    def eval(self, x):
        """(theta (N,), grad (N, 2)) at the rows of x; NaN outside the free space."""
        x = np.asarray(x, float)
        n = len(x)
        h = x.copy()
        jac = np.broadcast_to(np.eye(2), (n, 2, 2)).copy()
        free = np.all(np.isfinite(x), axis=1)
        mapped = np.zeros(n, bool)
        for c, r, eps in zip(self.p, self.r, self.eps):
            v = x - c
            rho = np.linalg.norm(v, axis=1)
            free &= ~(rho <= r)
            band = (rho > r) & (rho < r + eps)
            if not band.any():
                continue
            rb = rho[band]
            u = v[band] / rb[:, None]
            t = (rb - r) / eps
            b, db = _beta(t)
            nu = t * (r + eps) + r * b * (1 - t)
            nu_rho = ((r + eps) + r * (db * (1 - t) - b)) / eps
            h[band] = c + nu[:, None] * u
            jac[band] = _radial_jacobian(u, rb, nu, nu_rho)
            mapped |= band
        v = x - self.c0
        rho = np.linalg.norm(v, axis=1)
        free &= rho < self.r0
        s = (rho - self.r0 + self.eps0) / self.eps0
        band = free & ~mapped & (s > 0)
        if band.any():
            rb, sb = rho[band], s[band]
            u = v[band] / rb[:, None]
            b, db = _beta(sb)
            gap = 1 - sb
            nu = rb + self.gain * b * sb / gap
            nu_rho = 1 + (self.gain / self.eps0) * (db * sb / gap + b / gap**2)
            h[band] = self.c0 + nu[:, None] * u
            jac[band] = _radial_jacobian(u, rb, nu, nu_rho)
        dd = h - self.goal
        nd = np.einsum("ij,ij->i", dd, dd)
        phi = np.log(nd)
        grad_phi = 2 * dd / nd[:, None]
        for c in self.p:
            di = h - c
            ni = np.einsum("ij,ij->i", di, di)
            phi -= np.log(ni) / self.k
            grad_phi -= 2 * di / (self.k * ni[:, None])
        theta, slope = _logistic(phi)
        grad = slope[:, None] * np.einsum("nji,nj->ni", jac, grad_phi)
        theta = np.where(free, theta, np.nan)
        grad = np.where(free[:, None], grad, np.nan)
        return theta, grad


def _radial_jacobian(u, rho, nu, nu_rho):
    """J = ν_ρ u uᵀ + (ν/ρ) u⊥ u⊥ᵀ (a disc: R' = 0, so no ν_θ term)."""
    perp = np.stack([-u[:, 1], u[:, 0]], axis=1)
    return nu_rho[:, None, None] * u[:, :, None] * u[:, None, :] + (nu / rho)[:, None, None] * perp[:, :, None] * perp[:, None, :]


def from_scenario(path, factor=6):
    """The DiscWorld of a scenario file whose workspace and obstacles are all circles."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python < 3.11
        import tomli as tomllib
    with open(path, "rb") as f:
        sc = tomllib.load(f)
    ws = sc["workspace"]
    obs = sc["obstacles"]
    assert ws["type"] == "circle" and all(o["type"] == "circle" for o in obs), "discs only"
    return DiscWorld(
        ws["center"], ws["radius"], [o["center"] for o in obs], [o["radius"] for o in obs], sc["robot"]["goal"], factor
    )
