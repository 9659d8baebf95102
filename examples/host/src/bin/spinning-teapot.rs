//! The marble teapot turning on its pedestal (32 frames), saved as GIF.
//!
//! `cargo run --release -p texcore-examples --bin spinning-teapot -- [OUTPUT]` (default `spinning-teapot.gif`).

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::PathBuf::from(
        std::env::args_os()
            .nth(1)
            .unwrap_or_else(|| "spinning-teapot.gif".into()),
    );
    texcore_examples::spinning_teapot(&out, 32)?;
    println!("wrote {}", out.display());
    Ok(())
}
