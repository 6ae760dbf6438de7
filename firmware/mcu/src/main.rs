//! `purcell-mcu`, the QEMU firmware (`src/firmware.rs`), built for `thumbv7em-none-eabihf` (M4F,
//! M7) or `thumbv7m-none-eabi` (M3); `purcell-mcu-check` checks what it prints.
//!
//! Cargo builds every workspace member for the host too (stable cargo has no per-package
//! target), so on the host this binary is a stub that says how to run the firmware.

#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
mod firmware;

/// The host build: how to run the firmware, and where the checker is; exits with 1.
#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    eprintln!(
        "purcell-mcu is firmware for QEMU's Cortex-M boards: run it with
`cargo run -p purcell-mcu --target thumbv7em-none-eabihf --release` (M4F), `cargo mcu-m7` or
`cargo mcu-m3`. The host-side checks are `cargo run -p purcell-mcu-check -- reference|check|disasm`
(see firmware/README.md)."
    );
    std::process::ExitCode::FAILURE
}
