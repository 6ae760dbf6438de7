//! `purcell-mcu`: on the MCU (`target_os = "none"`) the firmware; on the host the tool that
//! checks it (see `firmware/README.md`).

#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
mod firmware;

#[cfg(not(target_os = "none"))]
mod cli;

#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    cli::main()
}
