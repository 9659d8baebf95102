//! texcore on an ESP32-C3 (rv32imc at 160 MHz: no FPU): an animated fire panel on a 240 x 320
//! ST7789 display.
//!
//! Wiring (SPI2): SCK GPIO6, MOSI GPIO7, CS GPIO10, DC GPIO4, RST GPIO5; backlight on GPIO3.
//!
//! The texture is made in one call (`Material::preset(PresetName::Fire).texture::<256>(..)`) and
//! drawn as a textured embedded-graphics rectangle; each frame moves the fire's plane through the
//! solid (`PlaneMapping::with_phase`), all in fixed point. Build: `cargo build --release` in this
//! directory (target `riscv32imc-unknown-none-elf` from `.cargo/config.toml`); flash with
//! `espflash flash --monitor`.
#![no_std]
#![no_main]

use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use embedded_hal_bus::spi::ExclusiveDevice;
use esp_hal::clock::CpuClock;
use esp_hal::delay::Delay;
use esp_hal::gpio::{Level, Output, OutputConfig};
use esp_hal::spi::master::{Config, Spi};
use esp_hal::spi::Mode;
use esp_hal::time::Rate;
use mipidsi::interface::SpiInterface;
use mipidsi::models::ST7789;
use mipidsi::Builder;
use texcore::draw::{PlaneMapping, TextureStyle};
use texcore::filter::Antialias;
use texcore::ready::{Material, PresetName};

esp_bootloader_esp_idf::esp_app_desc!();

/// Display size in pixels (portrait ST7789).
const WIDTH: u32 = 240;
/// See [`WIDTH`].
const HEIGHT: u32 = 320;
/// How far the plane moves through the solid each frame (16.16: 1/32 of a texture unit).
const PHASE_STEP: i32 = 2048;

/// A panic stops the core (the example has no log output).
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}

#[esp_hal::main]
fn main() -> ! {
    let _ = run();
    // A failed display set-up: nothing more to show.
    loop {}
}

/// Brings up the clocks, SPI and the display, then draws frames forever.
fn run() -> Result<core::convert::Infallible, ()> {
    let peripherals = esp_hal::init(esp_hal::Config::default().with_cpu_clock(CpuClock::max()));
    let spi = Spi::new(
        peripherals.SPI2,
        Config::default()
            .with_frequency(Rate::from_mhz(40))
            .with_mode(Mode::_0),
    )
    .map_err(|_| ())?
    .with_sck(peripherals.GPIO6)
    .with_mosi(peripherals.GPIO7);
    let out = OutputConfig::default();
    let cs = Output::new(peripherals.GPIO10, Level::High, out);
    let dc = Output::new(peripherals.GPIO4, Level::Low, out);
    let rst = Output::new(peripherals.GPIO5, Level::Low, out);
    let _backlight = Output::new(peripherals.GPIO3, Level::High, out);

    let spi = ExclusiveDevice::new_no_delay(spi, cs).map_err(|_| ())?;
    let mut buffer = [0u8; 512];
    let di = SpiInterface::new(spi, dc, &mut buffer);
    let mut delay = Delay::new();
    let mut display = Builder::new(ST7789, di)
        .display_size(WIDTH as u16, HEIGHT as u16)
        .invert_colors(mipidsi::options::ColorInversion::Inverted)
        .reset_pin(rst)
        .init(&mut delay)
        .map_err(|_| ())?;

    // One call: the fire preset, a 256-entry colour table, the summed-area filter.
    let fire = Material::preset(PresetName::Fire)
        .texture::<256>(Antialias::Csat)
        .map_err(|_| ())?;
    let screen = Rectangle::new(Point::zero(), Size::new(WIDTH, HEIGHT));
    let mut phase = 0i32;
    loop {
        let mapping = PlaneMapping::scaled(48).with_phase(phase);
        screen
            .into_styled(TextureStyle::new(&fire, mapping))
            .draw(&mut display)
            .map_err(|_| ())?;
        phase = phase.wrapping_add(PHASE_STEP);
    }
}
