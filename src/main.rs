//! The `freemesh` binary: parses arguments, runs, prints one line per error.

mod cli;

use anyhow::{Context, Result};
use clap::Parser;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use freemesh::output::{render, write_all, Format};
use freemesh::{mesh_domain, Domain, KnowledgeBase, Options};

fn main() -> ExitCode {
    let cli = match cli::Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let msg = format!("{e:#}");
            if msg.contains("Broken pipe") {
                return ExitCode::SUCCESS;
            }
            eprintln!("error: {}", msg.replace('\n', " "));
            ExitCode::from(1)
        }
    }
}

fn run(cli: cli::Cli) -> Result<()> {
    match cli.command {
        cli::Command::Mesh(args) => mesh(args),
        cli::Command::Features(args) => features(args),
        cli::Command::Repl(args) => repl(args),
    }
}

fn repl(args: cli::ReplArgs) -> Result<()> {
    use freemesh::repl::{Flow, Repl};
    use std::io::{BufRead, IsTerminal, Write};
    let mut kb = load_kb(&args.kb)?;
    let mut session = Repl::new(&mut kb, args.size);
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
    use rustyline::error::ReadlineError;
    let mut editor = rustyline::DefaultEditor::new().context("starting the line editor")?;
    writeln!(out, "freemesh repl: Prolog queries over the knowledge base and the live front; :help lists the commands")?;
    loop {
        let line = match editor.readline("?- ") {
            Ok(l) => l,
            Err(ReadlineError::Interrupted) => continue,
            Err(ReadlineError::Eof) => break,
            Err(e) => return Err(e).context("reading the terminal"),
        };
        let _ = editor.add_history_entry(line.as_str());
        // After each answer: ; asks for the next, Enter alone stops.
        let mut ask = |answer: &str| -> bool {
            let reply = editor.readline(&format!("   {answer} "));
            matches!(reply.as_deref().map(str::trim), Ok(";"))
        };
        if session.handle(&line, &mut out, Some(&mut ask))? == Flow::Quit {
            break;
        }
    }
    Ok(())
}

/// One warning line for the keys of a domain file the format does not know.
fn warn_unknown_keys(domain: &Domain, path: &std::path::Path) {
    if !domain.unknown_keys.is_empty() {
        eprintln!(
            "warning: {}: unknown keys ignored: {}",
            path.display(),
            domain.unknown_keys.join(", ")
        );
    }
}

/// The built-in knowledge base with the user's `--kb` files consulted.
fn load_kb(files: &[PathBuf]) -> Result<KnowledgeBase> {
    let mut kb = KnowledgeBase::builtin()?;
    for f in files {
        kb.consult_file(&f.to_string_lossy())?;
    }
    Ok(kb)
}

fn features(args: cli::FeaturesArgs) -> Result<()> {
    use std::io::Write;
    let domain = Domain::from_file(&args.domain.to_string_lossy())?;
    warn_unknown_keys(&domain, &args.domain);
    let mut kb = load_kb(&args.kb)?;
    let f = freemesh::domain_features(&domain, &mut kb, args.size)?;
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&f)?)?;
        return Ok(());
    }
    writeln!(out, "nodes: id x y angle concave")?;
    for n in &f.nodes {
        writeln!(
            out,
            "{:>5} {:>12.6} {:>12.6} {:>5} {}",
            n.node,
            n.x,
            n.y,
            n.angle,
            if n.concave { "concave" } else { "" }
        )?;
    }
    writeln!(out, "edges: N1 -> N2 feature action   (ctx)")?;
    for e in &f.edges {
        writeln!(
            out,
            "{:>5} -> {:<5} {:<6} {:<28} {}",
            e.n1,
            e.n2,
            e.feature.as_deref().unwrap_or("-"),
            e.action.as_deref().unwrap_or("-"),
            e.ctx
        )?;
    }
    Ok(())
}

fn mesh(args: cli::MeshArgs) -> Result<()> {
    let t0 = Instant::now();
    let formats: Vec<(PathBuf, Format)> = args
        .outputs
        .iter()
        .map(|p| Ok((p.clone(), Format::from_path(p)?)))
        .collect::<Result<_>>()?;
    let domain = Domain::from_file(&args.domain.to_string_lossy())?;
    warn_unknown_keys(&domain, &args.domain);
    let mut kb = load_kb(&args.kb)?;
    let opts = Options::default()
        .with_size(args.size)
        .with_max_size(args.max_size);
    let result = mesh_domain(&domain, &mut kb, &opts, &mut |_| {})?;
    let mut files: Vec<(PathBuf, String)> = formats
        .iter()
        .map(|(p, f)| (p.clone(), render(&result.mesh, &domain.name, *f)))
        .collect();
    if let Some(t) = &args.trace {
        let mut text = String::new();
        for step in &result.trace {
            text.push_str(&step.to_json_line());
            text.push('\n');
        }
        files.push((t.clone(), text));
    }
    write_all(&files).context("writing the outputs")?;
    let q = &result.quality;
    eprintln!(
        "{}: {} nodes, {} quads, angles {:.1}..{:.1} deg, {:.1}% in [45, 135], {} fallback splits{}, {:.3} s",
        domain.name,
        result.mesh.nodes.len(),
        q.quads,
        q.min_angle,
        q.max_angle,
        q.pct_45_135,
        result.stats.fallback_splits,
        if result.stats.triangle_fallbacks > 0 {
            " (the rules stopped: meshed whole by the triangle fallback)"
        } else {
            ""
        },
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}
