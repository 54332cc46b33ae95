//! Policies chosen by name (`k = "auto"`, `damping = "paper"`, …): one macro,
//! [`named_policy!`](crate::named_policy), gives every policy enum of harmonav its names in
//! scenario files, the CLI and JSON, `Display`, `FromStr`, and a typed error for an unknown
//! name that lists the names. No maths here; it lives in the lowest crate that the field, the
//! control laws and the facade all depend on.

/// `"a"`, `"a" or "b"`, `"a", "b" or "c"`: the names, quoted, for an error message.
#[must_use]
pub fn expected(names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
    match quoted.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
    }
}

/// Names for a policy enum: `ALL`, `as_str`, `Display`, `FromStr` and the error type for an
/// unknown name (`Unknown…(pub String)`, whose message names the kind and lists the names).
///
/// ```
/// #[derive(Clone, Copy, Debug, PartialEq, Eq)]
/// pub enum Rule {
///     /// The paper's.
///     Paper,
///     /// Ours.
///     Auto,
/// }
/// harmonav_potential::named_policy!(Rule, UnknownRule, "rule", [Paper => "paper", Auto => "auto"]);
///
/// assert_eq!("auto".parse::<Rule>(), Ok(Rule::Auto));
/// assert_eq!(Rule::Paper.to_string(), "paper");
/// assert_eq!(
///     "pid".parse::<Rule>().unwrap_err().to_string(),
///     r#"unknown rule "pid": expected "paper" or "auto""#
/// );
/// ```
#[macro_export]
macro_rules! named_policy {
    ($policy:ident, $unknown:ident, $what:literal, [$($variant:ident => $name:literal),+ $(,)?]) => {
        impl $policy {
            /// Every policy, for reports and sweeps.
            pub const ALL: [$policy; [$($name),+].len()] = [$($policy::$variant),+];

            /// The name used in scenario files, the CLI and JSON.
            #[must_use]
            pub fn as_str(self) -> &'static str {
                match self {
                    $(Self::$variant => $name,)+
                }
            }
        }

        impl ::std::fmt::Display for $policy {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str(self.as_str())
            }
        }

        #[doc = concat!("A name that is not a [`", stringify!($policy), "`].")]
        #[derive(Clone, Debug, PartialEq, Eq)]
        pub struct $unknown(pub String);

        impl ::std::fmt::Display for $unknown {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                write!(
                    f,
                    concat!("unknown ", $what, " \"{}\": expected {}"),
                    self.0,
                    $crate::named::expected(&[$($name),+])
                )
            }
        }

        impl ::std::error::Error for $unknown {}

        impl ::std::str::FromStr for $policy {
            type Err = $unknown;

            fn from_str(s: &str) -> Result<Self, Self::Err> {
                Self::ALL
                    .into_iter()
                    .find(|p| p.as_str() == s)
                    .ok_or_else(|| $unknown(s.to_string()))
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::expected;

    #[test]
    fn the_names_are_listed_as_a_sentence() {
        assert_eq!(expected(&[]), "");
        assert_eq!(expected(&["auto"]), "\"auto\"");
        assert_eq!(expected(&["paper", "auto"]), "\"paper\" or \"auto\"");
        assert_eq!(
            expected(&["paper", "shaped", "auto"]),
            "\"paper\", \"shaped\" or \"auto\""
        );
    }
}
