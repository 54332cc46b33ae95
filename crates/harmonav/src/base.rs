//! The robot's base ([`Base`]): holonomic, or a differential drive with its bounds
//! (issue 53; the law that steers it is `diff.rs`, docs/unicycle.md).

use crate::error::{NavError, in_range};
use crate::law::Law;

/// The robot's base: how it moves and which command it takes ([`crate::Options::base`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Base {
    /// The default: an omnidirectional robot commanded by [`Navigator::command`](crate::Navigator::command) (a velocity or
    /// a force), today's behaviour bit for bit.
    #[default]
    Holonomic,
    /// A differential-drive (unicycle) base with its axle at the disc's centre, commanded by
    /// [`Navigator::command_pose`](crate::Navigator::command_pose): forward speed `0 ≤ v ≤ v_max` (m/s) and turn rate
    /// `|ω| ≤ omega_max` (rad/s). Kinematic law only ([`Law::Kinematic`]); the dynamic law is
    /// refused at construction (`base`).
    Diff {
        /// The top forward speed, m/s, in [`crate::PARAMETER_RANGE`].
        v_max: f64,
        /// The top turn rate, rad/s, in [`crate::PARAMETER_RANGE`].
        omega_max: f64,
    },
}

impl Base {
    /// A differential-drive base with these bounds ([`Base::Diff`]); checked by
    /// [`crate::Options::validate`].
    #[must_use]
    pub fn diff(v_max: f64, omega_max: f64) -> Self {
        Self::Diff { v_max, omega_max }
    }

    /// The name used in logs and Python (`"holonomic"`, `"diff"`).
    #[must_use]
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Holonomic => "holonomic",
            Self::Diff { .. } => "diff",
        }
    }

    /// The bounds checked for `law`: `v_max` and `omega_max` finite and in
    /// [`crate::PARAMETER_RANGE`] (the error names the field); a differential-drive base with
    /// the dynamic law is [`NavError::InvalidOption`] naming `base` (not built in this
    /// release: the kinematic law only).
    pub(crate) fn validate(&self, law: &Law) -> Result<(), NavError> {
        if let Self::Diff { v_max, omega_max } = *self {
            in_range("v_max", v_max)?;
            in_range("omega_max", omega_max)?;
            if matches!(law, Law::Dynamic { .. }) {
                return Err(NavError::InvalidOption {
                    field: "base",
                    value: f64::NAN,
                });
            }
        }
        Ok(())
    }
}
