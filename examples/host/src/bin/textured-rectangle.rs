//! A marble rectangle, a wood circle and a clouds triangle on a simulated RGB565 display, saved as PNG.
//!
//! `cargo run --release -p texcore-examples --bin textured-rectangle -- [OUTPUT]` (default `textured-rectangle.png`).

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::PathBuf::from(
        std::env::args_os()
            .nth(1)
            .unwrap_or_else(|| "textured-rectangle.png".into()),
    );
    texcore_examples::textured_rectangle(&out)?;
    println!("wrote {}", out.display());
    Ok(())
}
