//! The `?-` examples written in the docs of `kb/*.pl` are run, and their
//! answers checked against the ones written under them.
//!
//! An example is a line `?- Query.` in a file's `/** ... */` doc or in a
//! `%` comment (the query may go on over several lines; what follows its
//! full stop on the line is a remark), then the answers as the toplevel
//! writes them, up to a full stop: `N = 3.`, `true.`, `false.`, or several
//! joined by `;` (`F = b4 ;  F = b5.`, on one line or several). A last
//! answer `...` says that only the answers before it are checked. Spaces
//! do not count. The examples run in `freemesh repl` with the L-shaped
//! domain `tests/inputs/l-shape.json` loaded (the live-front predicates
//! of `kb/front.pl` are shown on it).
//!
//! Every predicate documented with a `%% name(...)` mode line has at least
//! one example in its comment (STYLE.md).

use std::io::Write;
use std::process::{Command, Stdio};

/// Where the examples' front comes from.
const DOMAIN: &str = "tests/inputs/l-shape.json";

/// The query the session is sent after each example, to tell their
/// outputs apart.
const END: &str = "Fm_end = end_of_example.";

#[derive(Debug)]
struct Example {
    file: String,
    line: usize,
    query: String,
    answers: Vec<String>,
    /// Only the first answers are written (`...`).
    more: bool,
}

/// The text of a file's comments, line by line: the lines of `/** */`
/// docs as they are, `%` comment lines without the `%`s, other lines
/// empty (so an example cannot run on into code).
fn comment_lines(text: &str) -> Vec<String> {
    let mut in_doc = false;
    text.lines()
        .map(|l| {
            let t = l.trim_start();
            if in_doc {
                if t.starts_with("*/") {
                    in_doc = false;
                    return String::new();
                }
                return l.to_string();
            }
            if t.starts_with("/**") {
                in_doc = !t.contains("*/");
                return String::new();
            }
            match t.strip_prefix('%') {
                Some(rest) => rest.trim_start_matches('%').to_string(),
                None => String::new(),
            }
        })
        .collect()
}

/// The byte index just past the full stop that ends a clause in `s` (a `.`
/// outside brackets and quotes followed by a space or the end), if any.
fn clause_end(s: &str) -> Option<usize> {
    let b = s.as_bytes();
    let mut depth = 0i32;
    let mut quote: Option<u8> = None;
    for i in 0..b.len() {
        let c = b[i];
        if let Some(q) = quote {
            if c == q {
                quote = None;
            }
            continue;
        }
        match c {
            b'\'' | b'"' => quote = Some(c),
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth -= 1,
            b'.' if depth == 0 && b.get(i + 1).is_none_or(|n| n.is_ascii_whitespace()) => {
                return Some(i + 1)
            }
            _ => {}
        }
    }
    None
}

/// Splits answers at the `;` outside brackets and quotes.
fn split_answers(s: &str) -> Vec<String> {
    let mut out = Vec::new();
    let (mut depth, mut quote, mut start) = (0i32, None, 0);
    for (i, c) in s.char_indices() {
        if let Some(q) = quote {
            if c == q {
                quote = None;
            }
            continue;
        }
        match c {
            '\'' | '"' => quote = Some(c),
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            ';' if depth == 0 => {
                out.push(s[start..i].to_string());
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(s[start..].to_string());
    out.into_iter().map(|a| a.trim().to_string()).collect()
}

/// An answer with the spaces outside quotes taken out.
fn normal(s: &str) -> String {
    let mut out = String::new();
    let mut quote = None;
    for c in s.chars() {
        match quote {
            Some(q) => {
                if c == q {
                    quote = None;
                }
                out.push(c);
            }
            None if c.is_whitespace() => {}
            None => {
                if c == '\'' || c == '"' {
                    quote = Some(c);
                }
                out.push(c);
            }
        }
    }
    out
}

fn examples_of(file: &str) -> Vec<Example> {
    let text = std::fs::read_to_string(file).expect("a readable KB file");
    let lines = comment_lines(&text);
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let Some(start) = lines[i].trim_start().strip_prefix("?-") else {
            i += 1;
            continue;
        };
        let line = i + 1;
        // the query, up to its full stop
        let mut query = start.to_string();
        while clause_end(&query).is_none() && i + 1 < lines.len() && !lines[i + 1].is_empty() {
            i += 1;
            query.push(' ');
            query.push_str(lines[i].trim());
        }
        let end = clause_end(&query)
            .unwrap_or_else(|| panic!("{file}:{line}: the example's query has no full stop"));
        query.truncate(end);
        // the answers, up to theirs
        let mut answers = String::new();
        while clause_end(&answers).is_none() && i + 1 < lines.len() {
            i += 1;
            let l = lines[i].trim();
            assert!(
                !l.is_empty() && !l.starts_with("?-"),
                "{file}:{line}: the example has no answers written under it (end them with a full stop)"
            );
            answers.push(' ');
            answers.push_str(l);
        }
        let end = clause_end(&answers)
            .unwrap_or_else(|| panic!("{file}:{line}: the answers have no full stop"));
        let mut answers = split_answers(answers[..end - 1].trim());
        // `...` ends with the full stop taken off as `..`
        let more = answers.last().is_some_and(|a| a == ".." || a == "...");
        if more {
            answers.pop();
        }
        out.push(Example {
            file: file.to_string(),
            line,
            query: query.trim().to_string(),
            answers: answers.iter().map(|a| normal(a)).collect(),
            more,
        });
        i += 1;
    }
    out
}

/// Runs the examples in one session; the answers of each, as written.
fn run(examples: &[Example]) -> Vec<Vec<String>> {
    let mut script = format!(":load {DOMAIN}\n");
    for e in examples {
        script.push_str(&e.query);
        script.push('\n');
        script.push_str(END);
        script.push('\n');
    }
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let mut each = Vec::new();
    let mut current = String::new();
    for l in stdout.lines() {
        if l.trim() == "Fm_end = end_of_example." {
            each.push(std::mem::take(&mut current));
        } else if !l.trim_start().starts_with('%') {
            current.push_str(l);
            current.push(' ');
        }
    }
    assert_eq!(
        each.len(),
        examples.len(),
        "one output an example: {stdout}"
    );
    each.iter()
        .map(|text| {
            let text = text.trim();
            let text = text.strip_suffix('.').unwrap_or(text);
            // the toplevel joins answers with ; at the start of a line
            split_answers(&text.replace('\n', " "))
                .iter()
                .map(|a| normal(a))
                .collect()
        })
        .collect()
}

fn kb_files() -> Vec<String> {
    let mut files: Vec<String> = std::fs::read_dir("kb")
        .expect("the kb folder")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "pl"))
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    files.sort();
    files
}

#[test]
fn every_example_in_the_kb_docs_answers_as_written() {
    let mut failures = Vec::new();
    let mut count = 0;
    for file in kb_files() {
        let examples = examples_of(&file);
        count += examples.len();
        let answers = run(&examples);
        for (e, got) in examples.iter().zip(answers) {
            let ok = if e.more {
                got.len() > e.answers.len() && got[..e.answers.len()] == e.answers[..]
            } else {
                got == e.answers
            };
            if !ok {
                failures.push(format!(
                    "{}:{}: ?- {}\n   written: {}{}\n   answered: {}",
                    e.file,
                    e.line,
                    e.query,
                    e.answers.join(" ; "),
                    if e.more { " ; ..." } else { "" },
                    got.join(" ; ")
                ));
            }
        }
    }
    assert!(count >= 20, "only {count} examples found");
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

#[test]
fn every_documented_predicate_has_an_example() {
    let mut missing = Vec::new();
    for file in kb_files() {
        let text = std::fs::read_to_string(&file).expect("a readable KB file");
        let lines: Vec<&str> = text.lines().collect();
        for (i, l) in lines.iter().enumerate() {
            let Some(mode) = l.strip_prefix("%% ") else {
                continue;
            };
            // the comment lines that follow the mode line
            let has_example = lines[i + 1..]
                .iter()
                .take_while(|c| c.starts_with('%') && !c.starts_with("%% "))
                .any(|c| c.trim_start_matches('%').trim_start().starts_with("?-"));
            if !has_example {
                missing.push(format!("{file}:{}: {mode}", i + 1));
            }
        }
    }
    assert!(missing.is_empty(), "no ?- example:\n{}", missing.join("\n"));
}

#[test]
fn an_example_is_read_with_its_answers() {
    let dir = std::env::temp_dir().join(format!("freemesh-kb-examples-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("e.pl");
    std::fs::write(
        &file,
        "/** Doc.\n```\n?- member(X, [a, b]).   (a remark)\n   X = a\n;  X = b.\n```\n*/\n\
         %% p(-X)\n% ?- p(\n%      X).\n%    X = 'a b' ;  ...\np('a b').\n",
    )
    .unwrap();
    let es = examples_of(&file.to_string_lossy());
    assert_eq!(es.len(), 2);
    assert_eq!(es[0].query, "member(X, [a, b]).");
    assert_eq!(es[0].answers, ["X=a", "X=b"]);
    assert!(!es[0].more);
    assert_eq!(es[1].query, "p( X).");
    assert_eq!(es[1].answers, ["X='a b'"]);
    assert!(es[1].more);
}
