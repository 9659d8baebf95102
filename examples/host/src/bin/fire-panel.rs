//! An animated fire panel (48 frames), saved as GIF.
//!
//! `cargo run --release -p texcore-examples --bin fire-panel -- [OUTPUT]` (default `fire-panel.gif`).

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::PathBuf::from(
        std::env::args_os()
            .nth(1)
            .unwrap_or_else(|| "fire-panel.gif".into()),
    );
    texcore_examples::fire_panel(&out, 48)?;
    println!("wrote {}", out.display());
    Ok(())
}
