//! Follows the optimisation goal of the build: at `opt-level = "s"` or `"z"` texcore compiles
//! its size-lean code shape (`cfg(texcore_lean)`, see the crate documentation, "Code size"), at
//! every other level its fast one. Both give bit-identical results.
//!
//! Also names two feature combinations the span evaluator tests in many places:
//! `cfg(texcore_hermite)`, the Hermite segments of `EvalMode::Reanchored` (feature `reanchor`
//! with a basis that is not a cubic along a span: `smooth-fade`, `gradient-noise` or `mnoise`),
//! and `cfg(texcore_fd_state)`, a per-term 64-bit forward-difference state in the general loop
//! (`turbulence-fd` or the Hermite segments).

fn main() {
    println!("cargo::rustc-check-cfg=cfg(texcore_lean)");
    println!("cargo::rustc-check-cfg=cfg(texcore_hermite)");
    println!("cargo::rustc-check-cfg=cfg(texcore_fd_state)");
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-env-changed=OPT_LEVEL");
    if matches!(std::env::var("OPT_LEVEL").as_deref(), Ok("s" | "z")) {
        println!("cargo::rustc-cfg=texcore_lean");
    }
    let on = |f: &str| std::env::var_os(format!("CARGO_FEATURE_{f}")).is_some();
    let hermite = on("REANCHOR") && (on("SMOOTH_FADE") || on("GRADIENT_NOISE") || on("MNOISE"));
    if hermite {
        println!("cargo::rustc-cfg=texcore_hermite");
    }
    if hermite || on("TURBULENCE_FD") {
        println!("cargo::rustc-cfg=texcore_fd_state");
    }
}
