//! The `freemesh` binary: parses arguments, runs, prints one line per error.

mod cli;
mod prompt;
mod run_outputs;

use anyhow::{Context, Result};
use clap::Parser;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use freemesh::{render, write_all, Domain, ElementKind, KnowledgeBase, Options, SecondOrder};

// The engine and the mesher make many small, short-lived allocations;
// mimalloc serves them faster than the system allocator.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    let cli = match cli::Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let done = run(cli);
    // an interrupted run ends as a shell reports an interrupted command,
    // whether it stopped before its outputs or after
    if freemesh::was_interrupted() {
        freemesh::interrupt_writes();
        return ExitCode::from(130);
    }
    match done {
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
        cli::Command::Convert(args) => convert(args),
        cli::Command::Features(args) => features(args),
        cli::Command::Repl(args) => prompt::run(args),
        cli::Command::Quality(args) => quality(args),
    }
}

/// Whether a domain path names a DXF drawing (by its extension).
fn is_dxf(path: &std::path::Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("dxf"))
}

/// A DXF drawing's domain file with boundary size `size` (required: a
/// drawing has none); the reader's warnings are printed.
fn dxf_domain_file(
    path: &std::path::Path,
    size: Option<f64>,
    max_size: Option<f64>,
) -> Result<(freemesh::DomainFile, freemesh::Outline)> {
    let Some(size) = size else {
        anyhow::bail!(
            "{}: a DXF drawing gives no element size: give one with --size H (the boundary segment length)",
            path.display()
        );
    };
    let outline = freemesh::read_dxf(path)?;
    for w in &outline.warnings {
        eprintln!("warning: {w}");
    }
    let name = path.file_stem().map_or_else(
        || "domain".to_string(),
        |s| s.to_string_lossy().into_owned(),
    );
    Ok((outline.domain_file(&name, size, max_size), outline))
}

/// Reads a domain: a JSON domain file, or a DXF drawing's outline with
/// the boundary size `size`.
fn read_domain(path: &std::path::Path, size: Option<f64>) -> Result<Domain> {
    if !is_dxf(path) {
        return Ok(Domain::from_file(&path.to_string_lossy())?);
    }
    let (file, _) = dxf_domain_file(path, size, None)?;
    let domain = Domain::from_json(&file.to_json_value())
        .with_context(|| format!("{}: the outline is not a valid domain", path.display()))?;
    Ok(domain)
}

fn convert(args: cli::ConvertArgs) -> Result<()> {
    if !is_dxf(&args.input) {
        anyhow::bail!(
            "{}: convert reads DXF drawings (.dxf)",
            args.input.display()
        );
    }
    let (file, outline) = dxf_domain_file(&args.input, args.size, args.max_size)?;
    // the file written must mesh: the same checks as a run
    Domain::from_json(&file.to_json_value()).with_context(|| {
        format!(
            "{}: the outline is not a valid domain",
            args.input.display()
        )
    })?;
    write_all(&[(args.output.clone(), file.to_pretty_json())])
        .context("writing the domain file")?;
    eprintln!(
        "{}: {} -> {}",
        args.input.display(),
        outline.summary(),
        args.output.display()
    );
    Ok(())
}

/// A library error in the command line's words: an option names its flag.
fn in_cli_words(e: freemesh::Error) -> anyhow::Error {
    use freemesh::{Error, OptionError, RunOption};
    match e {
        Error::Option(OptionError::NotPositive { option, value }) => {
            let flag = match option {
                RunOption::Size => "--size",
                RunOption::MaxSize => "--max-size",
            };
            anyhow::anyhow!("{flag} must be a positive number, got {value}")
        }
        e => e.into(),
    }
}

/// The run options of the environment, for a developer: FREEMESH_DEBUG_CHECK
/// set turns on the mesher's self-check.
fn debug_options(opts: Options) -> Options {
    Options {
        self_check: std::env::var_os("FREEMESH_DEBUG_CHECK").is_some(),
        ..opts
    }
}

/// For a developer: where FREEMESH_DEBUG_SVG names a file, the state a run
/// stopped short in is written there as a picture, and its trace beside
/// it (`.trace`).
fn write_debug_picture(stopped: &freemesh::StoppedShort) {
    if let Some(path) = std::env::var_os("FREEMESH_DEBUG_SVG") {
        let path = PathBuf::from(path);
        let mut trace = path.clone().into_os_string();
        trace.push(".trace");
        let lines: Vec<String> = stopped.trace.iter().map(|t| t.to_json_line()).collect();
        let files = [
            (path, stopped.picture.clone()),
            (PathBuf::from(trace), lines.join("\n")),
        ];
        if let Err(e) = write_all(&files) {
            eprintln!("warning: the debug picture: {e}");
        }
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

fn quality(args: cli::QualityArgs) -> Result<()> {
    use std::io::Write;
    let read = freemesh::read_mesh(&args.mesh.to_string_lossy())?;
    let q = freemesh::measure_quality(&read.mesh);
    let mut out = std::io::stdout().lock();
    if args.json {
        let v = serde_json::json!({
            "mesh": args.mesh,
            "quality": q,
            "other_faces": read.other_faces,
            "angle_bins_10deg": freemesh::angle_bins(&read.mesh),
        });
        writeln!(out, "{}", serde_json::to_string_pretty(&v)?)?;
        return Ok(());
    }
    writeln!(
        out,
        "{}: {} quads, {} other faces",
        args.mesh.display(),
        q.quads,
        read.other_faces
    )?;
    writeln!(
        out,
        "angles {} deg, {} of quads in [{}, {}]{}",
        angle_range_text(&q),
        share_text(&q),
        q.corner_window[0],
        q.corner_window[1],
        outside_text(&q)
    )?;
    writeln!(
        out,
        "scaled Jacobian: smallest {:.3}",
        q.min_scaled_jacobian
    )?;
    writeln!(
        out,
        "aspect ratio: largest {:.2}; taper: largest {:.2}; size jump between neighbours: largest {:.2}",
        q.max_aspect, q.max_taper, q.max_size_jump
    )?;
    writeln!(out, "corner angles (deg):")?;
    write!(out, "{}", freemesh::angle_histogram(&read.mesh))?;
    Ok(())
}

fn features(args: cli::FeaturesArgs) -> Result<()> {
    use std::io::Write;
    let domain = read_domain(&args.domain, args.size)?;
    let mut kb = load_kb(&args.kb)?;
    let f = freemesh::domain_features(&domain, &mut kb, args.size).map_err(in_cli_words)?;
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

/// Meshes the domains, the answers the engine found kept for later runs
/// (`answer_store.rs`; a store that cannot be written is left as it was).
fn mesh(args: cli::MeshArgs) -> Result<()> {
    freemesh::answer_store::open(freemesh::answer_store::default_folder());
    let stats = args.stats;
    let done = mesh_domains(args);
    match freemesh::answer_store::save() {
        Ok(n) if stats && n > 0 => eprintln!("answer store: {n} new answers kept"),
        Err(e) if stats => eprintln!("answer store: not written ({e})"),
        _ => {}
    }
    done
}

fn mesh_domains(args: cli::MeshArgs) -> Result<()> {
    if args.order == 1 && args.serendipity.is_some() {
        anyhow::bail!("--serendipity is for second-order elements: give --order 2 with it");
    }
    if let (Some(size), Some(max_size)) = (args.size, args.max_size) {
        if max_size < size {
            anyhow::bail!("--max-size {max_size} is below --size {size}");
        }
    }
    let domains = expand_globs(&args.domains)?;
    // the handler first: checking the outputs makes (and removes) their
    // temporaries, and a Ctrl-C then must remove them too
    run_outputs::remove_temporaries_on_interrupt()?;
    let planned = run_outputs::plan(&domains, &args.outputs, args.trace.as_deref())?;
    if domains.len() == 1 {
        // the domain is read and its boundary made ready while the user's
        // `--kb` files are consulted (the engine cannot move between
        // threads; these can); a domain of more than a few hundred
        // elements, on a machine with a core to spare, gets a second
        // engine too, built beside the first, to answer part of the KB's
        // questions (on a small one its build would only contend with the
        // first's)
        let (kb, early) = std::thread::scope(|scope| {
            let early = scope.spawn(|| read_and_discretise(&domains[0], &args));
            let kb = load_kb(&args.kb);
            let early = early
                .join()
                .unwrap_or_else(|e| std::panic::resume_unwind(e));
            (kb, early)
        });
        let early = early?;
        let mut kb = kb?;
        if worth_a_second_engine(&early.1) {
            // (with the first's build: neither if the answer store
            // answers every question)
            kb.start_second_engine_when_built();
        }
        let done = mesh_one(&domains[0], Some(early), &planned[0], &mut kb, &args, true);
        // The engine's heap is large after a big run and the process ends
        // here: tearing it down piece by piece would only cost time.
        std::mem::forget(kb);
        return done;
    }
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .clamp(1, domains.len());
    let next = std::sync::atomic::AtomicUsize::new(0);
    let failed = std::sync::atomic::AtomicUsize::new(0);
    let bar = progress_bar(domains.len() as u64, "domains");
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                // one engine per worker, built once
                let mut kb = match load_kb(&args.kb) {
                    Ok(kb) => kb,
                    Err(e) => {
                        eprintln!("error: {e:#}");
                        failed.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                        return;
                    }
                };
                loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                    let Some(d) = domains.get(i) else { break };
                    if let Err(e) = mesh_one(d, None, &planned[i], &mut kb, &args, false) {
                        bar.suspend(|| eprintln!("error: {}", naming_the_file(d, &e)));
                        failed.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                    }
                    bar.inc(1);
                }
            });
        }
    });
    bar.finish_and_clear();
    let failed = failed.into_inner();
    if failed > 0 {
        anyhow::bail!("{failed} of {} domains failed", domains.len());
    }
    Ok(())
}

/// A domain's error on one line, with the file's name once: many errors
/// name it already (`d.json: not valid JSON`), the others get it first.
fn naming_the_file(path: &std::path::Path, e: &anyhow::Error) -> String {
    let message = one_line(&format!("{e:#}"));
    let name = path.display().to_string();
    if message.contains(&name) {
        message
    } else {
        format!("{name}: {message}")
    }
}

/// The domain arguments with quoted globs expanded, in order.
fn expand_globs(args: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for a in args {
        let text = a.to_string_lossy();
        if !text.contains(['*', '?', '[']) {
            out.push(a.clone());
            continue;
        }
        let mut found: Vec<PathBuf> = glob::glob(&text)
            .with_context(|| format!("the pattern {text}"))?
            .filter_map(Result::ok)
            .collect();
        if found.is_empty() {
            anyhow::bail!("no file matches {text}");
        }
        found.sort();
        out.extend(found);
    }
    Ok(out)
}

/// A progress bar on standard error, drawn only on a terminal.
fn progress_bar(len: u64, what: &str) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {what} ({{eta}} left)"
        ))
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

/// The share of quads in [45, 135] to a tenth of a percent, rounded
/// down: three quads outside in 8000 read 99.9%, never 100.0%.
fn share_text(q: &freemesh::Quality) -> String {
    let inside = q.quads - q.outside_45_135;
    let tenths = (inside * 1000).checked_div(q.quads).unwrap_or(0);
    format!("{}.{}%", tenths / 10, tenths % 10)
}

/// ` (N outside)` after the share, when a quad is outside [45, 135].
fn outside_text(q: &freemesh::Quality) -> String {
    match q.outside_45_135 {
        0 => String::new(),
        n => format!(" ({n} outside)"),
    }
}

/// The smallest and largest corner angle to a tenth of a degree, rounded
/// outward: a corner of 44.96 degrees reads 44.9, not 45.0 (a millionth
/// of a tenth spared, so that a right angle computed as 89.99999999
/// still reads 90.0).
fn angle_range_text(q: &freemesh::Quality) -> String {
    let down = (q.min_angle * 10.0 + 1e-6).floor() / 10.0;
    let up = (q.max_angle * 10.0 - 1e-6).ceil() / 10.0;
    format!("{down:.1}..{up:.1}")
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Whether a run on `boundary` is long enough for a second engine to pay
/// for its build (about 30 ms of another core's time): on a machine with
/// a core to spare, a domain of more elements of its size than
/// `SECOND_ENGINE_FROM`.
fn worth_a_second_engine(boundary: &freemesh::RunBoundary) -> bool {
    std::thread::available_parallelism().is_ok_and(|n| n.get() > 1)
        && boundary.elements_of_the_size() > SECOND_ENGINE_FROM
}

/// See `worth_a_second_engine`.
const SECOND_ENGINE_FROM: f64 = 300.0;

/// A domain file read, and its boundary made ready for a run.
fn read_and_discretise(
    path: &std::path::Path,
    args: &cli::MeshArgs,
) -> Result<(Domain, freemesh::RunBoundary)> {
    let domain = read_domain(path, args.size)?;
    check_sizes(&domain, args)?;
    let boundary = freemesh::discretise_for_run(&domain, args.size).map_err(in_cli_words)?;
    Ok((domain, boundary))
}

/// The run's largest interior size is not below its boundary size (the
/// domain's or the one given: an error, not a bound silently ignored).
fn check_sizes(domain: &Domain, args: &cli::MeshArgs) -> Result<()> {
    let size = args.size.unwrap_or(domain.size());
    let Some(max_size) = args.max_size.or(domain.max_size()) else {
        return Ok(());
    };
    // a size that is no positive number is the library's to refuse
    if !(size > 0.0 && max_size > 0.0) {
        return Ok(());
    }
    if max_size < size {
        let name = |flag: Option<f64>, key: &str| match flag {
            Some(_) => format!("--{}", key.replace('_', "-")),
            None => format!("the domain's {key}"),
        };
        anyhow::bail!(
            "{} {max_size} is below {} {size}",
            name(args.max_size, "max_size"),
            name(args.size, "size")
        );
    }
    Ok(())
}

/// Meshes one domain into its outputs, with a summary line on stderr;
/// `early` is the domain read and its boundary made ready, if it was.
fn mesh_one(
    path: &std::path::Path,
    early: Option<(Domain, freemesh::RunBoundary)>,
    outputs: &run_outputs::DomainOutputs,
    kb: &mut KnowledgeBase,
    args: &cli::MeshArgs,
    show_progress: bool,
) -> Result<()> {
    let t0 = Instant::now();
    let (domain, early_boundary) = match early {
        Some((d, b)) => (d, Some(b)),
        None => {
            let domain = read_domain(path, args.size)?;
            check_sizes(&domain, args)?;
            (domain, None)
        }
    };
    let trace_path = outputs.trace.as_deref();
    let opts = debug_options(
        Options::default()
            .with_size(args.size)
            .with_max_size(args.max_size)
            .with_trace(trace_path.is_some()),
    );
    // A bar for runs longer than a second: made on the first report
    // after one second, sized by the element estimate.
    let size = args.size.unwrap_or(domain.size());
    let estimate = (domain.area() / (size * size)).max(1.0) as u64;
    let mut bar: Option<indicatif::ProgressBar> = None;
    let mut progress = |quads: usize| {
        if !show_progress {
            return;
        }
        if bar.is_none() && t0.elapsed().as_secs_f64() > 1.0 {
            bar = Some(progress_bar(estimate, "elements (estimate)"));
        }
        if let Some(b) = &bar {
            b.set_position(quads as u64);
        }
    };
    let result = if args.blocks {
        freemesh::mesh_in_blocks(&domain, kb, &opts, &mut progress)
    } else {
        freemesh::mesh_free_then_blocks(&domain, early_boundary, kb, &opts, &mut progress)
    };
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let result = result.map_err(in_cli_words)?;
    if let Some(stopped) = &result.stopped_short {
        write_debug_picture(stopped);
    }
    let kind = ElementKind::from_order(args.order, args.serendipity.unwrap_or(true))
        .context("--order is 1 or 2")?;
    let second =
        (kind != ElementKind::Quad4).then(|| SecondOrder::build(&result.mesh, &domain, kind));
    let mut files: Vec<(PathBuf, String)> = outputs
        .meshes
        .iter()
        .map(|(p, f)| {
            (
                p.clone(),
                render(&result.mesh, second.as_ref(), domain.name(), *f),
            )
        })
        .collect();
    if let Some(t) = trace_path {
        let text = freemesh::trace_json_lines(&result.trace, &result.vetoes);
        files.push((t.to_path_buf(), text));
    }
    write_all(&files).context("writing the outputs")?;
    let q = &result.quality;
    let elapsed = t0.elapsed().as_secs_f64();
    eprintln!(
        "{}: {} nodes, {} quads, angles {} deg, {} in [{}, {}]{}, {} fallback splits{}, {:.3} s; made {}",
        domain.name(),
        result.mesh.nodes().len(),
        q.quads,
        angle_range_text(q),
        share_text(q),
        q.corner_window[0],
        q.corner_window[1],
        outside_text(q),
        result.stats.fallback_splits,
        result.stats.stopped_text(),
        elapsed,
        result.stats.made_by_text()
    );
    if args.stats {
        let k = &result.kb_stats;
        let quads = q.quads.max(1) as f64;
        let engine = k.engine_time.as_secs_f64();
        eprintln!(
            "{}: engine {:.3} s in {} queries ({} more answered from the memo, {} from the answer store of earlier runs), {:.2} queries and {:.1} us of engine time per element; host {:.3} s",
            domain.name(),
            engine,
            k.engine_queries,
            k.cached_queries,
            k.stored_answers,
            (k.engine_queries + k.cached_queries + k.stored_answers) as f64 / quads,
            engine * 1e6 / quads,
            elapsed - engine - k.build_time.as_secs_f64()
        );
        if k.second_engine_queries > 0 {
            eprintln!(
                "{}: of those queries, {} answered by a second engine in parallel ({:.3} s of its time, not counted above)",
                domain.name(),
                k.second_engine_queries,
                k.second_engine_time.as_secs_f64()
            );
        }
        eprintln!(
            "{}: elements made {} (validity checks that refused a design)",
            domain.name(),
            result.stats.made_by_text()
        );
        eprintln!(
            "{}: clean-up {} edge flips, {} element collapses, {} hexagons split in three",
            domain.name(),
            result.stats.cleanup_flips,
            result.stats.cleanup_collapses,
            result.stats.cleanup_splits
        );
        if result.stats.coarsened > 0 {
            eprintln!(
                "{}: coarsened to the size field: {} elements under its size collapsed or merged (bound(graded_collapse_below, F))",
                domain.name(),
                result.stats.coarsened
            );
        }
        if result.stats.polished > 0 {
            eprintln!(
                "{}: polishing brought {} regions round elements past the bounds nearer them (bound(polish_rings, R))",
                domain.name(),
                result.stats.polished
            );
        }
        if result.stats.boundary_slides > 0 {
            eprintln!(
                "{}: easing slid boundary nodes along their input edges {} times (bound(boundary_slide, S))",
                domain.name(),
                result.stats.boundary_slides
            );
        }
        if result.stats.thin_wall_edges > 0 {
            eprintln!(
                "{}: boundary: {} edges facing each other across thin walls given one segment count each (bound(thin_wall, K))",
                domain.name(),
                result.stats.thin_wall_edges
            );
        }
        if result.stats.near_line_edges > 0 {
            eprintln!(
                "{}: boundary: {} inner-line edges nearer another part of the boundary than bound(line_gap, F) sizes given segments as long as the gap (not under bound(line_gap_floor, G) sizes)",
                domain.name(),
                result.stats.near_line_edges
            );
        }
        let ph = &result.phases;
        if ph.blocks > 0.0 {
            eprintln!(
                "{}: blocks {:.3} s (the layouts, their block meshes, and the meshes not kept)",
                domain.name(),
                ph.blocks
            );
        }
        if ph.retries > 0.0 {
            eprintln!(
                "{}: retries {:.3} s (meshed again with the bounds of retry_bound/3's variants, as many at once as there are cores; the kept mesh's own stages below)",
                domain.name(),
                ph.retries
            );
        }
        if ph.coarser > 0.0 {
            eprintln!(
                "{}: coarser pass {:.3} s (the meshes it made or replaced and did not keep, two at once where a core is spare, bound(coarser_when_over, K); the kept mesh's own stages above and below)",
                domain.name(),
                ph.coarser
            );
        }
        eprintln!(
            "{}: engine start {:.3} s (built, rules consulted; at the first question the answer store could not answer, and counted in the stage that asked it; 0 if none); prepare {:.3} s, recursion {:.3} s, smoothing {:.3} s, check {:.3} s, the rest (reading, writing) {:.3} s",
            domain.name(),
            kb.load_time().as_secs_f64(),
            ph.prepare,
            ph.recursion,
            ph.smoothing,
            ph.check,
            elapsed
                - ph.prepare
                - ph.recursion
                - ph.smoothing
                - ph.check
                - ph.blocks
                - ph.retries
                - ph.coarser
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quality(quads: usize, outside: usize, min_angle: f64, max_angle: f64) -> freemesh::Quality {
        freemesh::Quality {
            quads,
            min_angle,
            max_angle,
            pct_45_135: 100.0 * (quads - outside) as f64 / quads as f64,
            outside_45_135: outside,
            min_scaled_jacobian: 0.7,
            max_aspect: 1.0,
            max_taper: 1.0,
            max_size_jump: 1.0,
            corner_window: [45.0, 135.0],
        }
    }

    #[test]
    fn a_share_just_below_all_is_rounded_down_with_the_count_outside() {
        let q = quality(8000, 3, 44.0, 130.0);
        assert_eq!(
            (share_text(&q), outside_text(&q).as_str()),
            ("99.9%".into(), " (3 outside)")
        );
        let q = quality(8000, 0, 45.0, 130.0);
        assert_eq!(
            (share_text(&q), outside_text(&q).as_str()),
            ("100.0%".into(), "")
        );
        assert_eq!(share_text(&quality(3, 1, 44.0, 130.0)), "66.6%");
    }

    #[test]
    fn the_angle_range_is_rounded_outward() {
        assert_eq!(
            angle_range_text(&quality(1, 1, 44.96, 135.04)),
            "44.9..135.1"
        );
        assert_eq!(angle_range_text(&quality(1, 0, 45.0, 135.0)), "45.0..135.0");
        assert_eq!(
            angle_range_text(&quality(1, 0, 89.999_999_99, 90.000_000_01)),
            "90.0..90.0"
        );
    }
}
