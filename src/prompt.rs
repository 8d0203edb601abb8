//! `freemesh repl` at a terminal or over a pipe: reads the lines, keeps
//! the history, and turns Ctrl-C into an interruption of the query or run
//! under way (the session itself is `freemesh::Repl`).

use anyhow::{Context, Result};
use std::io::{BufRead, IsTerminal, Write};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use freemesh::KnowledgeBase;
use freemesh::{Flow, Repl};

use crate::cli::ReplArgs;

/// The exit status when Ctrl-C ends the program (128 + SIGINT, as a shell
/// reports a program ended by it).
const EXIT_AFTER_THE_NOTE: i32 = 130;

/// How long a Ctrl-C may wait for the query to act on it before the note.
const NOTE_AFTER: Duration = Duration::from_secs(1);

/// How often the watcher of Ctrl-C looks.
const WATCH_EVERY: Duration = Duration::from_millis(50);

/// Runs a session: the built-in KB with the `--kb` files, the domain if
/// one is given, then one query or command a line until `:quit` or the end
/// of the input.
pub fn run(args: ReplArgs) -> Result<()> {
    let mut kb = KnowledgeBase::builtin_for_prompt()?;
    for f in &args.kb {
        kb.consult_file(&f.to_string_lossy())?;
    }
    let mut session = Repl::new(&mut kb, args.size);
    catch_ctrl_c(&session)?;
    let mut out = std::io::stdout();
    if let Some(d) = &args.domain {
        let msg = session.load(&d.to_string_lossy())?;
        writeln!(out, "{msg}")?;
    }
    if !std::io::stdin().is_terminal() {
        // Scripted: one line a query or command, no prompts.
        for line in std::io::stdin().lock().lines() {
            let line = line.context("reading standard input")?;
            if session.handle(&line, &mut out, None)? == Flow::Quit {
                break;
            }
        }
        return Ok(());
    }
    at_the_terminal(&mut session, &mut out)
}

/// Ctrl-C sets the session's interrupt flag: the query or run under way
/// stops at its next answer or element. If it has not after a second, a
/// note says so, and from then on another Ctrl-C ends the program, for a
/// query that cannot be stopped (`sleep(1000)`); a Ctrl-C pressed twice
/// in quick succession does not.
fn catch_ctrl_c(session: &Repl<'_>) -> Result<()> {
    use signal_hook::{consts::SIGINT, flag, iterator::Signals};
    let interrupt = session.interrupt_flag();
    let warned = Arc::new(AtomicBool::new(false));
    // the handlers run in this order: the exit sees `warned` as it was
    // before this Ctrl-C, and the flag is set before the call returns
    flag::register_conditional_shutdown(SIGINT, EXIT_AFTER_THE_NOTE, Arc::clone(&warned))
        .context("catching Ctrl-C")?;
    flag::register(SIGINT, Arc::clone(&interrupt)).context("catching Ctrl-C")?;
    let mut presses = Signals::new([SIGINT]).context("catching Ctrl-C")?;
    std::thread::spawn(move || {
        let mut pressed: Option<Instant> = None;
        loop {
            if presses.pending().count() > 0 {
                pressed.get_or_insert_with(Instant::now);
            }
            if !interrupt.load(Ordering::SeqCst) {
                // acted on (or cleared for a new line)
                pressed = None;
                warned.store(false, Ordering::SeqCst);
            } else if pressed.is_some_and(|t| t.elapsed() >= NOTE_AFTER)
                && !warned.swap(true, Ordering::SeqCst)
            {
                eprintln!(
                    "% Ctrl-C: the query stops at its next answer or at its inference limit; Ctrl-C again ends the session"
                );
            }
            std::thread::sleep(WATCH_EVERY);
        }
    });
    Ok(())
}

/// Where the history of the sessions is kept: `freemesh/history` in the
/// user's data folder (`$XDG_DATA_HOME`, `~/.local/share` on Linux).
fn history_path() -> Option<PathBuf> {
    Some(dirs_next::data_dir()?.join("freemesh").join("history"))
}

fn at_the_terminal(session: &mut Repl<'_>, out: &mut std::io::Stdout) -> Result<()> {
    use rustyline::error::ReadlineError;
    let mut editor = rustyline::DefaultEditor::new().context("starting the line editor")?;
    // The history is a convenience: a file that cannot be read or written
    // never stops the session.
    let history = history_path();
    if let Some(h) = &history {
        let _ = editor.load_history(h);
    }
    let interrupt = session.interrupt_flag();
    writeln!(out, "freemesh repl: Prolog queries over the knowledge base and the live front; :help lists the commands")?;
    // a line typed where the next answer was offered: the next query
    let mut typed_ahead: Option<String> = None;
    loop {
        let line = match typed_ahead.take() {
            Some(l) => l,
            None => match editor.readline("?- ") {
                Ok(l) => l,
                Err(ReadlineError::Interrupted) => continue,
                Err(ReadlineError::Eof) => break,
                Err(e) => return Err(e).context("reading the terminal"),
            },
        };
        // a Ctrl-C from before this line was typed is not meant for it
        interrupt.store(false, Ordering::SeqCst);
        if !line.trim().is_empty() && editor.add_history_entry(line.as_str()).unwrap_or(false) {
            if let Some(h) = &history {
                save_history(&mut editor, h);
            }
        }
        // After an answer that may have another: ; (then Enter) asks for
        // it, Enter alone stops; anything else stops and is the next line.
        let mut ask = |answer: &str| -> bool {
            match editor.readline(&format!("   {answer} ")) {
                Ok(reply) if reply.trim() == ";" => true,
                Ok(reply) if !reply.trim().is_empty() => {
                    typed_ahead = Some(reply);
                    false
                }
                _ => false,
            }
        };
        if session.handle(&line, out, Some(&mut ask))? == Flow::Quit {
            break;
        }
    }
    Ok(())
}

/// Adds the new lines to the history file, making its folder if need be;
/// a failure is ignored (the session goes on without a saved history).
fn save_history(editor: &mut rustyline::DefaultEditor, path: &std::path::Path) {
    if let Some(dir) = path.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    let _ = editor.append_history(path);
}
