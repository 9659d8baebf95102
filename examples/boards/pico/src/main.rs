//! texcore on a Raspberry Pi Pico (RP2040, Cortex-M0+ at 125 MHz: no FPU, no hardware divide):
//! fills a 240 x 320 ST7789 display with animated marble, one frame after another.
//!
//! Wiring (SPI0): SCK GP18, MOSI GP19, CS GP17, DC GP16, RST GP20; backlight on GP21.
//!
//! The texture is made in one call (`Material::preset(..).texture::<256>(Antialias::Csat)`) and
//! drawn as a textured embedded-graphics rectangle; each frame slides the plane through the solid
//! (`PlaneMapping::with_phase`), all in fixed point. Build: `cargo build --release` in this
//! directory (target `thumbv6m-none-eabi` from `.cargo/config.toml`); flash the ELF with
//! `elf2uf2-rs` or `probe-rs run`.
#![no_std]
#![no_main]

use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use embedded_hal::digital::OutputPin;
use embedded_hal_bus::spi::ExclusiveDevice;
use mipidsi::interface::SpiInterface;
use mipidsi::models::ST7789;
use mipidsi::Builder;
use panic_halt as _;
use rp_pico::entry;
use rp_pico::hal::{self, fugit::RateExtU32, gpio, pac, Clock};
use texcore::draw::{PlaneMapping, TextureStyle};
use texcore::filter::Antialias;
use texcore::ready::{Material, PresetName};

/// Display size in pixels (portrait ST7789).
const WIDTH: u32 = 240;
/// See [`WIDTH`].
const HEIGHT: u32 = 320;
/// How far the plane moves through the solid each frame (16.16: 1/64 of a texture unit).
const PHASE_STEP: i32 = 1024;

#[entry]
fn main() -> ! {
    match run() {
        Ok(never) => match never {},
        // A failed display set-up: nothing more to show. Stop here.
        Err(()) => loop {
            cortex_m::asm::wfi();
        },
    }
}

/// Brings up the clocks, SPI and the display, then draws frames forever.
fn run() -> Result<core::convert::Infallible, ()> {
    let mut pac = pac::Peripherals::take().ok_or(())?;
    let mut watchdog = hal::Watchdog::new(pac.WATCHDOG);
    let clocks = hal::clocks::init_clocks_and_plls(
        rp_pico::XOSC_CRYSTAL_FREQ,
        pac.XOSC,
        pac.CLOCKS,
        pac.PLL_SYS,
        pac.PLL_USB,
        &mut pac.RESETS,
        &mut watchdog,
    )
    .map_err(|_| ())?;
    let mut timer = hal::Timer::new(pac.TIMER, &mut pac.RESETS, &clocks);
    let sio = hal::Sio::new(pac.SIO);
    let pins = rp_pico::Pins::new(
        pac.IO_BANK0,
        pac.PADS_BANK0,
        sio.gpio_bank0,
        &mut pac.RESETS,
    );

    let sck = pins.gpio18.into_function::<gpio::FunctionSpi>();
    let mosi = pins.gpio19.into_function::<gpio::FunctionSpi>();
    let spi = hal::spi::Spi::<_, _, _, 8>::new(pac.SPI0, (mosi, sck)).init(
        &mut pac.RESETS,
        clocks.peripheral_clock.freq(),
        62_500_000u32.Hz(),
        embedded_hal::spi::MODE_0,
    );
    let cs = pins.gpio17.into_push_pull_output();
    let dc = pins.gpio16.into_push_pull_output();
    let rst = pins.gpio20.into_push_pull_output();
    let mut backlight = pins.gpio21.into_push_pull_output();

    let spi = ExclusiveDevice::new_no_delay(spi, cs).map_err(|_| ())?;
    let mut buffer = [0u8; 512];
    let di = SpiInterface::new(spi, dc, &mut buffer);
    let mut display = Builder::new(ST7789, di)
        .display_size(WIDTH as u16, HEIGHT as u16)
        .invert_colors(mipidsi::options::ColorInversion::Inverted)
        .reset_pin(rst)
        .init(&mut timer)
        .map_err(|_| ())?;
    backlight.set_high().map_err(|_| ())?;

    // One call: the marble preset, a 256-entry colour table, the summed-area filter.
    let marble = Material::preset(PresetName::Marble)
        .texture::<256>(Antialias::Csat)
        .map_err(|_| ())?;
    let screen = Rectangle::new(Point::zero(), Size::new(WIDTH, HEIGHT));
    let mut phase = 0i32;
    loop {
        let mapping = PlaneMapping::scaled(64).with_phase(phase);
        screen
            .into_styled(TextureStyle::new(&marble, mapping))
            .draw(&mut display)
            .map_err(|_| ())?;
        phase = phase.wrapping_add(PHASE_STEP);
    }
}
