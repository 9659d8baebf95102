//! The names a program that draws textures needs, in one import:
//! `use texcore::prelude::*;` brings [`Material`], [`PresetName`], [`Antialias`] and (feature
//! `embedded-graphics`) `TextureStyle`, `PlaneMapping` and `TexturedScene` of `texcore::draw`.

#[cfg(feature = "embedded-graphics")]
pub use crate::draw::{PlaneMapping, TextureStyle, TexturedScene};
pub use crate::filter::Antialias;
pub use crate::ready::{Material, MaterialError, PresetName};
