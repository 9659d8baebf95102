//! texcore device firmware (built for the device targets; on the host it is an empty program).
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {}
