//! How `k` of `phi_k` is chosen from the known world (`docs/maths.md` §8).

/// The rule that sets `k` of `phi_k` from the `n` known obstacles, at construction and at every
/// discovery. Every policy gives `k > n` (lemma `attactive`), the only condition theorem `isNF`
/// puts on `k`, so `Θ` is a navigation function under each of them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum KPolicy {
    /// `k = n + 1`, exactly the paper (its simulations and theorem `isNF`'s statement).
    Paper,
    /// `k = AUTO_FACTOR·(n + 1)` (the default): the obstacles' joint repulsion `n/k` stays below
    /// `1/AUTO_FACTOR` of the goal's attraction, whatever `n`, which removes the far-field valley
    /// that sends the paper's robot along the outer wall. Chosen by measurement on the
    /// motion-quality benchmark (`docs/maths.md` §8, `docs/benchmarks.md`).
    #[default]
    Auto,
}

/// The factor of [`KPolicy::Auto`]: `k = AUTO_FACTOR·(n + 1)`.
pub const AUTO_FACTOR: f64 = 6.0;

impl KPolicy {
    /// Every policy, for reports and sweeps.
    pub const ALL: [KPolicy; 2] = [KPolicy::Paper, KPolicy::Auto];

    /// `k` for `n` known obstacles; always `> n`.
    #[must_use]
    pub fn k(self, n: usize) -> f64 {
        let n1 = n as f64 + 1.0;
        match self {
            Self::Paper => n1,
            Self::Auto => AUTO_FACTOR * n1,
        }
    }

    /// The name used in scenario files, the CLI and JSON (`"paper"`, `"auto"`).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::Auto => "auto",
        }
    }
}

impl std::fmt::Display for KPolicy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A name that is not a [`KPolicy`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownKPolicy(pub String);

impl std::fmt::Display for UnknownKPolicy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "unknown k policy \"{}\": expected \"paper\" or \"auto\"",
            self.0
        )
    }
}

impl std::error::Error for UnknownKPolicy {}

impl std::str::FromStr for KPolicy {
    type Err = UnknownKPolicy;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|p| p.as_str() == s)
            .ok_or_else(|| UnknownKPolicy(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_policy_keeps_k_above_n_and_paper_is_n_plus_one() {
        for n in 0..200 {
            for p in KPolicy::ALL {
                assert!(p.k(n) > n as f64, "{p} at n = {n}");
            }
            assert_eq!(KPolicy::Paper.k(n), n as f64 + 1.0);
        }
    }

    #[test]
    fn names_round_trip_and_unknown_names_are_errors() {
        for p in KPolicy::ALL {
            assert_eq!(p.as_str().parse::<KPolicy>(), Ok(p));
        }
        let e = "n+1".parse::<KPolicy>().unwrap_err();
        assert!(e.to_string().contains("\"n+1\""), "{e}");
        assert_eq!(KPolicy::default(), KPolicy::Auto);
    }
}
