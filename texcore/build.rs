//! Follows the optimisation goal of the build: at `opt-level = "s"` or `"z"` texcore compiles
//! its size-lean code shape (`cfg(texcore_lean)`, see the crate documentation, "Code size"), at
//! every other level its fast one. Both give bit-identical results.

fn main() {
    println!("cargo::rustc-check-cfg=cfg(texcore_lean)");
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-env-changed=OPT_LEVEL");
    if matches!(std::env::var("OPT_LEVEL").as_deref(), Ok("s" | "z")) {
        println!("cargo::rustc-cfg=texcore_lean");
    }
}
