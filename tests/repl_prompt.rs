//! `freemesh repl` as a person meets it: Ctrl-C during a query or a run
//! (sent as SIGINT, over a pipe and under a pseudo-terminal), the prompt
//! after a deterministic answer, `:write`, and the history kept between
//! sessions.
//!
//! The sessions are driven line by line, waiting for what the REPL prints
//! before typing on; a wait has a generous limit only so that a broken
//! build fails instead of hanging (nothing here measures time).

use std::fs::File;
use std::io::{Read, Write};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use nix::sys::signal::{kill, Signal};
use nix::unistd::Pid;

/// How long a wait may take before the test gives up (a hang guard).
const PATIENCE: Duration = Duration::from_secs(120);

/// A running session: its input, and what it has printed so far.
struct Session {
    child: Child,
    input: Box<dyn Write>,
    output: Arc<Mutex<String>>,
    /// How much of the output the waits have gone past.
    seen: usize,
}

/// The output with terminal control sequences taken out.
fn plain(s: &str) -> String {
    let mut out = String::new();
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\x1b' => {
                // ESC [ parameters final-byte
                if chars.peek() == Some(&'[') {
                    chars.next();
                    while let Some(&n) = chars.peek() {
                        chars.next();
                        if n.is_ascii_alphabetic() || n == '~' {
                            break;
                        }
                    }
                }
            }
            '\r' => {}
            _ => out.push(c),
        }
    }
    out
}

impl Session {
    /// A session whose output is read from `froms` (standard output, and
    /// standard error when it is apart) into one text.
    fn reading(child: Child, input: Box<dyn Write>, froms: Vec<Box<dyn Read + Send>>) -> Self {
        let output = Arc::new(Mutex::new(String::new()));
        for mut from in froms {
            let sink = Arc::clone(&output);
            std::thread::spawn(move || {
                let mut buf = [0u8; 4096];
                // a pseudo-terminal's reader ends with an error when the
                // session closes it: both are the end
                while let Ok(n) = from.read(&mut buf) {
                    if n == 0 {
                        break;
                    }
                    let text = String::from_utf8_lossy(&buf[..n]).into_owned();
                    sink.lock().unwrap().push_str(&text);
                }
            });
        }
        Session {
            child,
            input,
            output,
            seen: 0,
        }
    }

    /// `freemesh repl ARGS` with its input and output piped.
    fn piped(args: &[&str]) -> Session {
        let mut child = Command::new(env!("CARGO_BIN_EXE_freemesh"))
            .arg("repl")
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the binary runs");
        let input = Box::new(child.stdin.take().expect("stdin is piped"));
        let output: Box<dyn Read + Send> = Box::new(child.stdout.take().expect("stdout is piped"));
        let errors: Box<dyn Read + Send> = Box::new(child.stderr.take().expect("stderr is piped"));
        Session::reading(child, input, vec![output, errors])
    }

    /// `freemesh repl ARGS` on a pseudo-terminal, with `data` as the
    /// user's data folder (where the history goes).
    fn on_a_terminal(args: &[&str], data: &std::path::Path) -> Session {
        let pty = nix::pty::openpty(None, None).expect("a pseudo-terminal");
        let slave = File::from(pty.slave);
        let child = Command::new(env!("CARGO_BIN_EXE_freemesh"))
            .arg("repl")
            .args(args)
            .env("TERM", "xterm")
            .env("XDG_DATA_HOME", data)
            .stdin(Stdio::from(slave.try_clone().unwrap()))
            .stdout(Stdio::from(slave.try_clone().unwrap()))
            .stderr(Stdio::from(slave))
            .spawn()
            .expect("the binary runs");
        let master = File::from(pty.master);
        let input = Box::new(master.try_clone().unwrap());
        Session::reading(child, input, vec![Box::new(master)])
    }

    fn type_line(&mut self, line: &str, enter: &str) {
        self.input
            .write_all(format!("{line}{enter}").as_bytes())
            .unwrap();
        self.input.flush().unwrap();
    }

    /// Waits until the output past what was seen holds `text`; returns
    /// the output up to and including it.
    fn expect(&mut self, text: &str) -> String {
        let t0 = Instant::now();
        loop {
            let all = plain(&self.output.lock().unwrap());
            if let Some(at) = all[self.seen.min(all.len())..].find(text) {
                let end = self.seen + at + text.len();
                let got = all[self.seen..end].to_string();
                self.seen = end;
                return got;
            }
            assert!(
                t0.elapsed() < PATIENCE,
                "waited for {text:?}; the session printed:\n{all}"
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    fn ctrl_c(&self) {
        kill(Pid::from_raw(self.child.id() as i32), Signal::SIGINT).expect("SIGINT is sent");
    }

    /// Waits for the end of the session; its exit status was success.
    fn ends(self) -> String {
        self.ends_with(0)
    }

    /// Waits for the end of the session, which exits with `code`.
    fn ends_with(mut self, code: i32) -> String {
        drop(self.input);
        let t0 = Instant::now();
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                let all = plain(&self.output.lock().unwrap());
                assert_eq!(status.code(), Some(code), "{status}: {all}");
                return all;
            }
            assert!(t0.elapsed() < PATIENCE, "the session did not end");
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("freemesh-repl-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A query that prints `started` and then gives an answer every few
/// hundred thousand inferences, a thousand of them.
const LONG_QUERY: &str =
    "write(started), nl, between(1, 1000, X), \\+ \\+ (numlist(1, 20000, _L), sum_list(_L, _)).";

#[test]
fn ctrl_c_stops_a_long_query_and_the_session_goes_on() {
    let mut s = Session::piped(&["tests/inputs/square.json"]);
    s.type_line(":step 2", "\n");
    s.expect("2 in all");
    s.type_line("assertz(kept(yes)).", "\n");
    s.expect("   true.");
    s.type_line(LONG_QUERY, "\n");
    s.expect("started");
    s.ctrl_c();
    let answers = s.expect("% interrupted");
    assert!(answers.contains("X = 1"), "{answers}");
    assert!(!answers.contains("stopped after"), "{answers}");
    // the rules asserted and the elements made are still there
    s.type_line("kept(K).", "\n");
    s.expect("   K = yes.");
    s.type_line(":step 1", "\n");
    s.expect("1 element(s) made, 3 in all");
    s.ends();
}

#[test]
fn ctrl_c_before_a_run_stops_it_at_its_first_element_and_keeps_the_mesh() {
    let mut s = Session::piped(&["tests/inputs/square.json"]);
    s.type_line(":step 2", "\n");
    s.expect("2 in all");
    // pressed while nothing runs: the next run stops at once
    s.ctrl_c();
    s.type_line(":run", "\n");
    s.expect("% interrupted");
    s.expect("0 element(s) made, 2 in all");
    s.type_line(":run", "\n");
    s.expect("% the mesh is complete: 16 quads");
    s.ends();
}

#[test]
fn a_ctrl_c_not_acted_on_is_noted_and_one_more_ends_the_session() {
    let mut s = Session::piped(&[]);
    s.type_line("X = 1.", "\n");
    s.expect("   X = 1.");
    // pressed while nothing runs, it waits for the next query: the note
    // comes after a second
    s.ctrl_c();
    s.expect("Ctrl-C again ends the session");
    s.ctrl_c();
    s.ends_with(130);
}

#[test]
fn write_saves_the_sessions_mesh_in_the_format_of_its_extension() {
    let dir = temp_dir("write");
    let path = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let mut s = Session::piped(&[]);
    s.type_line(&format!(":write {}", path("none.msh")), "\n");
    s.expect("error: no domain loaded");
    s.type_line(":load tests/inputs/square.json", "\n");
    s.type_line(":step 2", "\n");
    s.type_line(&format!(":write {}", path("partial.json")), "\n");
    s.expect("the 2 quads made so far (the mesh is not complete)");
    s.type_line(":run", "\n");
    s.type_line(&format!(":write {}", path("square.msh")), "\n");
    s.expect("square.msh: 16 quads");
    s.type_line(&format!(":write {}", path("square.txt")), "\n");
    s.expect("unknown output format");
    s.type_line(
        &format!(":write {}", path("no/such/folder/square.vtk")),
        "\n",
    );
    s.expect("error: ");
    s.type_line("X = still_here.", "\n");
    s.expect("X = still_here.");
    s.ends();
    let partial: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path("partial.json")).unwrap()).unwrap();
    assert_eq!(partial["quads"].as_array().map(Vec::len), Some(2));
    let msh = std::fs::read_to_string(path("square.msh")).unwrap();
    assert!(msh.starts_with("$MeshFormat\n4.1 0 8"), "{msh}");
    assert!(!dir.join("none.msh").exists());
    assert!(!dir.join("square.txt").exists());
}

#[test]
fn at_a_terminal_the_prompt_comes_back_after_a_deterministic_answer() {
    let data = temp_dir("terminal");
    let mut s = Session::on_a_terminal(&["tests/inputs/square.json"], &data);
    s.expect("?- ");
    // an answer that may have another waits for ; or Enter
    s.type_line("between(1, 3, X).", "\r");
    s.expect("X = 1 ");
    s.type_line(";", "\r");
    s.expect("X = 2 ");
    s.type_line(";", "\r");
    // the last one ends with a full stop and the prompt is back
    s.expect("   X = 3.\n");
    s.expect("?- ");
    s.type_line("Y = 1.", "\r");
    s.expect("   Y = 1.\n");
    s.expect("?- ");
    // a query typed where the next answer is offered is not swallowed
    s.type_line("member(Z, [a, b]).", "\r");
    s.expect("Z = a ");
    s.type_line("W = 2.", "\r");
    s.expect("   W = 2.\n");
    s.expect("?- ");
    // Ctrl-C during a query: the prompt comes back
    s.type_line(LONG_QUERY, "\r");
    s.expect("started");
    s.ctrl_c();
    s.expect("% interrupted");
    s.expect("?- ");
    s.type_line(":quit", "\r");
    s.ends();

    let history = std::fs::read_to_string(data.join("freemesh").join("history"))
        .expect("the history is kept in the user's data folder");
    for line in ["between(1, 3, X).", "Y = 1.", "W = 2.", ":quit"] {
        assert!(history.lines().any(|l| l == line), "{line} in {history}");
    }
    assert!(!history.lines().any(|l| l == ";"), "{history}");

    // the next session has it: the line before is :quit
    let mut again = Session::on_a_terminal(&[], &data);
    again.expect("?- ");
    again.type_line("\x1b[A", "\r");
    again.ends();
}

#[test]
fn a_history_that_cannot_be_written_does_not_stop_the_session() {
    let data = temp_dir("no-history");
    // the data folder is a file: no history folder can be made in it
    let not_a_folder = data.join("file");
    std::fs::write(&not_a_folder, "").unwrap();
    let mut s = Session::on_a_terminal(&[], &not_a_folder);
    s.expect("?- ");
    s.type_line("X = 1.", "\r");
    s.expect("   X = 1.\n");
    s.type_line(":quit", "\r");
    s.ends();
}
