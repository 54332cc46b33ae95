//! What the CLI's test files share: running the binary.

use std::process::Command;

/// Runs `harmonav args…`: its exit code, standard output and standard error.
pub fn harmonav(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_harmonav"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
