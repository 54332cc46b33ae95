//! What the CLI's test files share: running the binary.

use std::path::PathBuf;
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

/// A scenario file of the repository (`rel` below `scenarios/`), as an argument.
pub fn scenario(rel: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(rel)
        .to_string_lossy()
        .into_owned()
}

/// A fresh folder for one test (`tag` unique within its test file; the process id keeps
/// the test files apart).
pub fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("harmonav-cli-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}
