//! Display names of the configuration enums, for reports, logs and error messages: the short
//! lower-case names `texsim` takes on its command line (`nearest`, `csat`, `l2`, `smooth`,
//! `gradient`, `every16`, `fd32`, `multipass-16.8-xor`, ...), so that user-facing text never
//! shows Rust's `Debug` form.
//!
//! Guarantee: every name is a fixed string per variant (configuration data only: no allocation,
//! no panic).

use core::fmt;

use crate::filter::{Antialias, GradientNorm, WidthSource};
use crate::noise::{BasisKind, Fade};
use crate::raster::Perspective;
use crate::span::EvalMode;
use crate::table::TableLookup;

macro_rules! display_names {
    ($($ty:ty { $($(#[$m:meta])* $v:ident => $name:literal),+ $(,)? })+) => {$(
        impl fmt::Display for $ty {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(match self {
                    $($(#[$m])* <$ty>::$v => $name,)+
                })
            }
        }
    )+};
}

display_names! {
    TableLookup { Nearest => "nearest", Linear => "linear" }
    Antialias {
        None => "none",
        Mip => "mip",
        Csat => "csat",
        Csat3 => "csat3",
        #[cfg(feature = "ramp")]
        Ramp => "ramp",
    }
    GradientNorm { L1 => "l1", L2 => "l2", Max => "max" }
    WidthSource { Gradients => "gradients", Differences => "differences" }
    Fade {
        Linear => "linear",
        #[cfg(feature = "smooth-fade")]
        Smooth => "smooth",
        #[cfg(feature = "smooth-fade")]
        Quintic => "quintic",
    }
    BasisKind {
        Value => "value",
        #[cfg(feature = "gradient-noise")]
        Gradient => "gradient",
        #[cfg(feature = "mnoise")]
        Modified => "mnoise",
    }
    Perspective { Exact => "exact", Every8 => "every8", Every16 => "every16", Affine => "affine" }
}

/// `direct`, `fd`, `auto`, `fd32`, `reanchored`, `fused`, or `multipass-PRECISION` with `-HASH` unless
/// texcore's own hash.
impl fmt::Display for EvalMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EvalMode::Direct => f.write_str("direct"),
            EvalMode::Fd => f.write_str("fd"),
            EvalMode::Auto => f.write_str("auto"),
            EvalMode::Fd32 => f.write_str("fd32"),
            EvalMode::Reanchored => f.write_str("reanchored"),
            EvalMode::Fused => f.write_str("fused"),
            #[cfg(feature = "multipass")]
            EvalMode::Multipass(c) => {
                write!(f, "multipass-{}", c.precision.name())?;
                if c.hash != crate::multipass::PassHash::Texcore {
                    write!(f, "-{}", c.hash.name())?;
                }
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::format;
    use std::string::ToString;

    /// The names are the lower-cased variant names (what reports printed before), except where
    /// a variant's name is not the command line's.
    #[test]
    fn names_are_the_command_line_names() {
        let all = |v: &[&dyn fmt::Display]| {
            v.iter()
                .map(|x| x.to_string())
                .collect::<std::vec::Vec<_>>()
        };
        assert_eq!(
            all(&[&TableLookup::Nearest, &TableLookup::Linear]),
            ["nearest", "linear"]
        );
        assert_eq!(
            all(&[
                &Antialias::None,
                &Antialias::Mip,
                &Antialias::Csat,
                &Antialias::Csat3
            ]),
            ["none", "mip", "csat", "csat3"]
        );
        assert_eq!(
            all(&[&GradientNorm::L1, &GradientNorm::L2, &GradientNorm::Max]),
            ["l1", "l2", "max"]
        );
        assert_eq!(
            all(&[&WidthSource::Gradients, &WidthSource::Differences]),
            ["gradients", "differences"]
        );
        for p in [
            Perspective::Exact,
            Perspective::Every8,
            Perspective::Every16,
            Perspective::Affine,
        ] {
            assert_eq!(p.to_string(), format!("{p:?}").to_lowercase());
        }
        for m in [
            EvalMode::Direct,
            EvalMode::Fd,
            EvalMode::Auto,
            EvalMode::Fd32,
            EvalMode::Reanchored,
            EvalMode::Fused,
        ] {
            assert_eq!(m.to_string(), format!("{m:?}").to_lowercase());
        }
        assert_eq!(Fade::Linear.to_string(), "linear");
        assert_eq!(BasisKind::Value.to_string(), "value");
    }
}
