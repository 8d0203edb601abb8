//! Snapshots of scripted `freemesh repl` sessions: each script in
//! tests/repl/ is piped into the binary, and the snapshot keeps the script
//! beside what the session printed, so a change to a rule or to the REPL
//! shows as a readable diff. CI runs with INSTA_UPDATE=no.

use std::io::Write;
use std::process::{Command, Stdio};

fn session(script: &str) -> (String, String, bool) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .arg("repl")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    child
        .stdin
        .take()
        .expect("stdin is piped")
        .write_all(script.as_bytes())
        .expect("the script is written");
    let out = child.wait_with_output().expect("the session ends");
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        out.status.success(),
    )
}

#[test]
fn scripted_sessions() {
    insta::glob!("repl/*.txt", |path| {
        let script = std::fs::read_to_string(path).expect("a readable script");
        let (stdout, stderr, ok) = session(&script);
        assert!(ok, "the session failed: {stderr}");
        assert!(
            !stderr.contains("panicked"),
            "a panic reached the user: {stderr}"
        );
        insta::assert_snapshot!(format!("{script}---\n{stdout}"));
    });
}
