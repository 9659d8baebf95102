//! Host examples of texcore drawing through `embedded-graphics`, on
//! `embedded-graphics-simulator` displays without SDL, saved as PNG (one frame) or GIF (an
//! animation):
//!
//! | binary | function | output |
//! |---|---|---|
//! | `textured-rectangle` | [`textured_rectangle`] | marble rectangle, wood circle, clouds triangle (PNG) |
//! | `spinning-teapot` | [`spinning_teapot`] | the marble teapot on its pedestal, turning (GIF) |
//! | `fire-panel` | [`fire_panel`] | an animated fire panel (GIF) |
//!
//! `cargo run --release -p texcore-examples --bin fire-panel -- out/fire.gif`; the test
//! `tests/run.rs` runs all three (the README's `cargo test --workspace` and CI).
#![deny(missing_docs, unsafe_code)]

use std::error::Error;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{Circle, Rectangle, Triangle};
use embedded_graphics_simulator::{OutputSettings, SimulatorDisplay};
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};
use texcore::draw::{PlaneMapping, TextureStyle, TexturedScene};
use texcore::filter::Antialias;
use texcore::presets::set_fire_phase;
use texcore::ready::{Material, PresetName};
use texcore::scene::math::Angle;
use texcore::texture::{Shader, Texture};
use texcore::transform::Affine3;

/// The result of an example: what it wrote.
pub type Result<T> = std::result::Result<T, Box<dyn Error>>;

/// The textured-rectangle example: a 240 x 160 RGB565 display with a marble rectangle, a wood
/// circle and a clouds triangle, each filled with its preset (256-entry tables, summed-area
/// filter), saved as a PNG. Returns the display.
pub fn textured_rectangle(png: &Path) -> Result<SimulatorDisplay<Rgb565>> {
    let marble = Material::preset(PresetName::Marble).texture::<256>(Antialias::Csat)?;
    let wood = Material::preset(PresetName::Wood).texture::<256>(Antialias::Csat)?;
    let clouds = Material::preset(PresetName::Clouds).texture::<256>(Antialias::Csat)?;

    let mut display = SimulatorDisplay::<Rgb565>::new(Size::new(240, 160));
    display.clear(Rgb565::new(4, 8, 6))?;
    Rectangle::new(Point::new(8, 8), Size::new(136, 96))
        .into_styled(TextureStyle::new(&marble, PlaneMapping::scaled(96)))
        .draw(&mut display)?;
    // The wood's rings are centred on the plane's origin: attach it to the circle's centre.
    let circle = Circle::new(Point::new(152, 8), 80);
    let rings = PlaneMapping::scaled(16)
        .rotated(Angle::from_degrees(20))
        .at(circle.center());
    circle
        .into_styled(TextureStyle::new(&wood, rings))
        .draw(&mut display)?;
    Triangle::new(
        Point::new(8, 152),
        Point::new(120, 112),
        Point::new(232, 152),
    )
    .into_styled(TextureStyle::new(&clouds, PlaneMapping::scaled(64)))
    .draw(&mut display)?;
    display
        .to_rgb_output_image(&OutputSettings::default())
        .save_png(png)?;
    Ok(display)
}

/// The RGBA pixels of a simulator display.
fn rgba<C: PixelColor + Into<Rgb888>>(display: &SimulatorDisplay<C>) -> RgbaImage {
    let size = display.size();
    RgbaImage::from_fn(size.width, size.height, |x, y| {
        let c: Rgb888 = display.get_pixel(Point::new(x as i32, y as i32)).into();
        image::Rgba([c.r(), c.g(), c.b(), 255])
    })
}

/// Writes `frames` as a looping GIF, `ms` milliseconds a frame.
fn save_gif(path: &Path, frames: Vec<RgbaImage>, ms: u32) -> Result<()> {
    let mut enc = GifEncoder::new_with_speed(BufWriter::new(File::create(path)?), 10);
    enc.set_repeat(Repeat::Infinite)?;
    for f in frames {
        enc.encode_frame(Frame::from_parts(
            f,
            0,
            0,
            Delay::from_numer_denom_ms(ms, 1),
        ))?;
    }
    Ok(())
}

/// The textures of a scene's slots: each slot's preset with its own keys (if any), 256
/// entries, summed-area filter.
fn slot_textures(scene: &texcore::scene::Scene) -> Result<Vec<Texture<8, 256>>> {
    scene
        .slots
        .iter()
        .map(|slot| {
            let m = Material::by_name(slot.material, Default::default())
                .ok_or_else(|| format!("unknown material `{}`", slot.material))?;
            let keys = slot.keys.unwrap_or(m.keys());
            Ok(m.with_keys(keys).texture::<256>(Antialias::Csat)?)
        })
        .collect()
}

/// The spinning-teapot example: the built-in `marble` scene (a marble teapot on a marble
/// pedestal, 320 x 240, depth-buffered) with the teapot turned by `1/frames` of a turn a frame,
/// drawn as a `TexturedScene` on an RGB888 display, saved as a GIF. Returns the frame count.
pub fn spinning_teapot(gif: &Path, frames: u32) -> Result<u32> {
    let base = texcore::scene::by_name("marble").ok_or("no marble scene")?;
    let base = base.at_frame(base.still());
    let textures = slot_textures(&base)?;
    let (w, h) = base.size();
    let mut images = Vec::new();
    for k in 0..frames {
        let mut scene = base.clone();
        // Object 1 is the teapot, turned about the world's vertical axis; its texture is
        // attached to it, so it turns with it.
        if let Some(pot) = scene.objects.get_mut(1) {
            let turn = Affine3::rotate_y(Angle::from_turns(i64::from(k), frames.max(1)));
            pot.transform = pot.transform.then(&turn);
        }
        let mut display = SimulatorDisplay::<Rgb888>::new(Size::new(w.into(), h.into()));
        // Bands of 16 rows (two 320 x 16 buffers on the stack).
        TexturedScene::<_, Rgb888, 8, 256, { 320 * 16 }>::new(&scene, &textures)
            .draw(&mut display)??;
        images.push(rgba(&display));
    }
    save_gif(gif, images, 80)?;
    Ok(frames)
}

/// The fire-panel example: a 96 x 128 panel of the fire preset on an RGB565 display, its flames
/// rising with the preset's phase, `frames` frames saved as a GIF. Returns the last frame.
pub fn fire_panel(gif: &Path, frames: u32) -> Result<SimulatorDisplay<Rgb565>> {
    let material = Material::preset(PresetName::Fire);
    let mut fire = material.texture::<256>(Antialias::Csat)?;
    // The preset's 256-pixel check plane, stretched over the panel's 128 rows.
    let mapping = PlaneMapping::from_plane(material.plane())
        .with_zoom(2 << 16)
        .at(Point::new(0, 0));
    let panel = Rectangle::new(Point::zero(), Size::new(96, 128));
    let mut images = Vec::new();
    let mut display = SimulatorDisplay::<Rgb565>::new(panel.size);
    for k in 0..frames {
        // One noise cell every 16 frames.
        if let Shader::Model(m) = fire.shader_mut() {
            set_fire_phase(m, (k as i32) << 12);
        }
        panel
            .into_styled(TextureStyle::new(&fire, mapping))
            .draw(&mut display)?;
        images.push(rgba(&display));
    }
    save_gif(gif, images, 50)?;
    Ok(display)
}
