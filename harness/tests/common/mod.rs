//! What the command-line tests share: running the built binary.

use std::process::{Command, Output};

/// Runs the built `harness` binary with `args` (no device-select layer noise) and waits.
pub fn harness(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(args)
        .env("NODEVICE_SELECT", "1")
        .output()
        .expect("run the harness binary")
}
