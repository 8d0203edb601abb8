//! `freemesh repl`: a Prolog toplevel over the live knowledge base and the
//! front of the remaining domain. Queries are answered the way a Prolog
//! toplevel does (`N = 7`, `true`, `false`); commands (`:load`, `:step`,
//! `:consult`, ...) drive the mesher one element at a time, so the user
//! can watch the features the KB sees change as the front advances.
//!
//! The session is driven line by line through [`Repl::handle`], whatever
//! the input is (a terminal, a pipe, a test), and never panics or stops on
//! what the user types: every fault is one `error:` line.
//!
//! A query or a run can be stopped from outside (Ctrl-C): the caller sets
//! the flag of [`Repl::interrupt_flag`], and the session stops at the next
//! answer or the next element, keeping what it had.

use std::io::{self, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use crate::input::domain::Domain;
use crate::io::output::{render, to_svg, write_all, Format};
use crate::kb::{KnowledgeBase, More, UserAnswer};
use crate::pipeline::{discretise_for_run, prepare_run, MeshResult, Options, Run};

/// At most this many inferences for one answer of a user's query: a
/// query that loops is an error, not a hung session.
pub const INFERENCE_LIMIT: u64 = 20_000_000;

/// With piped input every answer is printed, up to this many.
pub const MAX_ANSWERS: usize = 200;

/// Why a query stopped before its answers ran out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stop {
    /// Interrupted from outside (Ctrl-C).
    Interrupted,
    /// Piped input: `MAX_ANSWERS` were printed.
    Enough,
    /// The person at the terminal asked for no more.
    Asked,
}

/// What the session does after a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Read the next line.
    Continue,
    /// End the session.
    Quit,
}

/// The help text of `:help`.
pub const HELP: &str = "\
Queries: any Prolog goal, with or without a leading ?- and a final full stop.
  Answers show as N = 7, true or false; an answer that may have another
  after it waits: ; then Enter asks for the next, Enter alone stops.
  Each answer may take at most 20,000,000 inferences; Ctrl-C stops a query
  at its next answer (or at that limit) and a :run at its next element
  (if it has not after a second, Ctrl-C again ends the session).
  Loaded: lists, between, format, dif, error, si, lambda, iso_ext, charsio,
  dcgs, pairs, ordsets, assoc, freeze, reif, time.

The live front (the boundary of the remaining domain, kb/front.pl):
  node_xy(N, X, Y)      front node N at (X, Y)
  front_edge(A, B)      a front edge A-B, the remaining domain on its left
  node_angle(N, Deg)    interior angle of the remaining domain at N
  concave_point(N)      N is a concave point (angle above 180)
  parallel(E1, E2)      front edges E = A-B on parallel lines
  near_segment(N, E)    node N approaches front edge E (Fig. 10)
  edge_feature(E, at(F, N))
                        front edge E = A-B, read from its end N (A along
                        the front, B mirrored), shows feature F (b1..b5)
  edge_action(E, at(Act, N))
                        the design action the KB takes on E read from N
  edge_context(E, N, Ctx)
                        the context term the mesher asks about E read from N
The knowledge base (kb/*.pl, kb/README.md):
  strategy(S), bound(Name, Value), feature(F, Ctx), feature_action(F, Ctx, A),
  context_feature(Ctx, F), context_design(Ctx, F, A), violation(R, V),
  redesign_rule(Rule, Ctx, A, V, NewA), redesign(Ctx, A, Rels, Rule, NewA),
  final_pattern(Angles, K, P), loop_patterns(Angles, Ps),
  segments_parallel(S1, S2), point_segment_distances(P, S, V, H),
  point_segment_near(V, H, Size), angle_concave(Deg), line_equation(P1, P2, A, B, C)

Commands:
  :load DOMAIN.json   mesh this domain (from its boundary)
  :consult FILE.pl    add the clauses of FILE to the KB now
  :step [N]           make N elements (default 1), print their trace lines
  :run                finish the mesh (smoothing included)
  :blocks             mesh the domain in structured blocks instead (as
                      mesh --blocks): the layout chosen, each block's
                      element counts map(N, M), then :write or :svg it
  :front              the loops of the front: node(angle) in order
  :svg FILE.svg       draw the elements made so far and the front
  :write FILE         write the mesh (.msh, .vtk, .svg, .json: by extension);
                      before the mesh is complete, the elements made so far
  :trace on|off       print trace lines on :step and :run (default on)
  :help               this text
  :quit               end the session (also halt, or end of input)";

enum State<'k> {
    /// No domain loaded.
    Idle(&'k mut KnowledgeBase),
    /// A run over a domain, at some step.
    Meshing(Box<Run<'k>>),
}

/// A REPL session: the KB, and the run over the loaded domain if any.
pub struct Repl<'k> {
    state: Option<State<'k>>,
    size: Option<f64>,
    trace: bool,
    /// The domain's name, for pictures and messages.
    name: String,
    /// The domain loaded, for `:blocks`.
    domain: Option<Domain>,
    /// The finished mesh, once `:run` or `:step` completed it.
    finished: Option<MeshResult>,
    /// Set from outside (Ctrl-C) to stop the query or run under way.
    interrupt: Arc<AtomicBool>,
}

impl<'k> Repl<'k> {
    /// A session over `kb`; domains are discretised with boundary size
    /// `size` (their own when None).
    pub fn new(kb: &'k mut KnowledgeBase, size: Option<f64>) -> Repl<'k> {
        Repl {
            state: Some(State::Idle(kb)),
            size,
            trace: true,
            name: String::new(),
            domain: None,
            finished: None,
            interrupt: Arc::new(AtomicBool::new(false)),
        }
    }

    /// The flag that stops the query or run under way at its next answer
    /// or element (a Ctrl-C handler sets it). Set while nothing runs, it
    /// stops the next query or run that starts; the session clears it
    /// when it acts on it.
    pub fn interrupt_flag(&self) -> Arc<AtomicBool> {
        Arc::clone(&self.interrupt)
    }

    fn kb(&mut self) -> &mut KnowledgeBase {
        match self.state.as_mut() {
            Some(State::Idle(kb)) => kb,
            Some(State::Meshing(run)) => run.mesher().kb(),
            None => unreachable!("the state is only taken inside load"),
        }
    }

    /// Loads a domain and starts a run over it; the previous run ends.
    /// On an error the session keeps what it had.
    pub fn load(&mut self, path: &str) -> Result<String, crate::pipeline::Error> {
        let domain = Domain::from_file(path)?;
        let opts = Options::default().with_size(self.size);
        let boundary = discretise_for_run(&domain, opts.size)?;
        let prepared = prepare_run(&domain, boundary, self.kb(), &opts)?;
        let kb = match self.state.take() {
            Some(State::Idle(kb)) => kb,
            Some(State::Meshing(run)) => run.into_kb(),
            None => unreachable!("the state is only taken here"),
        };
        let mut run = Box::new(Run::start(kb, prepared));
        let published = run.mesher().publish_front();
        let loops = run.mesher_ref().front_node_loops();
        self.state = Some(State::Meshing(run));
        self.finished = None;
        self.name = domain.name.clone();
        let summary = format!(
            "% loaded {}: {} front segments in {} loop(s)",
            domain.name,
            loops.iter().map(Vec::len).sum::<usize>(),
            loops.len()
        );
        self.domain = Some(domain);
        published?;
        Ok(summary)
    }

    /// `:blocks`: the loaded domain meshed in blocks; the block steps of
    /// its trace (with the trace on) and a summary line.
    fn blocks(&mut self, out: &mut dyn Write) -> io::Result<()> {
        let Some(domain) = self.domain.clone() else {
            return writeln!(out, "error: no domain loaded (:load DOMAIN.json)");
        };
        let opts = Options::default().with_size(self.size);
        let r = match crate::blocks::mesh_in_blocks(&domain, self.kb(), &opts, &mut |_| {}) {
            Ok(r) => r,
            Err(e) => return writeln!(out, "error: {}", one_line(&e.to_string())),
        };
        if self.trace {
            for t in r
                .trace
                .iter()
                .filter(|t| t.by == crate::report::trace::By::Block)
            {
                writeln!(out, "{}", t.to_text())?;
            }
        }
        writeln!(
            out,
            "% the mesh in blocks: {} quads, {} irregular interior nodes, angles {:.1}..{:.1} deg; made {}",
            r.quality.quads,
            crate::blocks::irregular_nodes(&r.mesh),
            r.quality.min_angle,
            r.quality.max_angle,
            r.stats.made_by_text()
        )?;
        self.finished = Some(r);
        Ok(())
    }

    /// Handles one line of input: a command or a query. `more` is asked
    /// after each answer of a query whether to look for the next (None:
    /// every answer, as for piped input). Only writing `out` can fail.
    pub fn handle(
        &mut self,
        line: &str,
        out: &mut dyn Write,
        more: Option<&mut dyn FnMut(&str) -> bool>,
    ) -> io::Result<Flow> {
        let line = line.trim();
        if line.is_empty() || line.starts_with('%') {
            return Ok(Flow::Continue);
        }
        if matches!(line, "halt" | "halt." | "?- halt.") {
            return Ok(Flow::Quit);
        }
        let Some(command) = line.strip_prefix(':') else {
            self.query(line, out, more)?;
            return Ok(Flow::Continue);
        };
        let mut words = command.split_whitespace();
        let name = words.next().unwrap_or("");
        let arg = words.next();
        if words.next().is_some() {
            writeln!(out, "error: :{name} takes at most one argument")?;
            return Ok(Flow::Continue);
        }
        match (name, arg) {
            ("quit" | "q" | "exit", None) => return Ok(Flow::Quit),
            ("help" | "h", None) => writeln!(out, "{HELP}")?,
            ("load", Some(path)) => match self.load(path) {
                Ok(msg) => writeln!(out, "{msg}")?,
                Err(e) => writeln!(out, "error: {}", one_line(&e.to_string()))?,
            },
            ("consult", Some(path)) => self.consult(path, out)?,
            ("step", arg) => match arg.map(str::parse::<usize>) {
                None => self.advance(Some(1), out)?,
                Some(Ok(n)) if n > 0 => self.advance(Some(n), out)?,
                Some(_) => writeln!(out, "error: :step takes a positive whole number")?,
            },
            ("run", None) => self.advance(None, out)?,
            ("blocks", None) => self.blocks(out)?,
            ("front", None) => self.print_front(out)?,
            ("svg", Some(path)) => self.svg(path, out)?,
            ("write", Some(path)) => self.write(path, out)?,
            ("trace", Some("on")) => self.trace = true,
            ("trace", Some("off")) => self.trace = false,
            ("trace", _) => writeln!(out, "error: :trace takes on or off")?,
            _ => writeln!(
                out,
                "error: unknown command :{command} (:help lists the commands)"
            )?,
        }
        Ok(Flow::Continue)
    }

    fn query(
        &mut self,
        text: &str,
        out: &mut dyn Write,
        mut more: Option<&mut dyn FnMut(&str) -> bool>,
    ) -> io::Result<()> {
        let interactive = more.is_some();
        // the answers not yet shown (on a terminal, those that end the
        // query), and whether each may have another after it
        let mut answers: Vec<(String, More)> = Vec::new();
        let mut shown = 0usize;
        let mut error: Option<String> = None;
        // why the query stopped before the engine said there is no more
        let mut stop: Option<Stop> = None;
        let interrupt = Arc::clone(&self.interrupt);
        let kb = self.kb();
        // The engine is a library we do not control: should it panic on
        // some goal (halt(300) does), the session reports it in one line
        // and goes on; the default hook's report is kept from the user.
        let hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            kb.user_query(text, INFERENCE_LIMIT, &mut |answer| match answer {
                UserAnswer::Error(e) => {
                    error = Some(e);
                    false
                }
                UserAnswer::Bindings(b, m) => {
                    let text = if b.is_empty() {
                        "true".to_string()
                    } else {
                        b.iter()
                            .map(|(k, v)| format!("{k} = {v}"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    };
                    if interrupt.swap(false, Ordering::SeqCst) {
                        answers.push((text, More::Maybe));
                        stop = Some(Stop::Interrupted);
                        return false;
                    }
                    if m == More::No {
                        // the last answer: shown with its full stop below
                        answers.push((text, m));
                        return false;
                    }
                    if let Some(ask) = more.as_mut() {
                        shown += 1;
                        if !ask(&text) {
                            stop = Some(Stop::Asked);
                            return false;
                        }
                        return true;
                    }
                    answers.push((text, m));
                    if answers.len() >= MAX_ANSWERS {
                        stop = Some(Stop::Enough);
                        return false;
                    }
                    true
                }
            });
        }));
        std::panic::set_hook(hook);
        // the query may have asserted or retracted rules: answers kept
        // from before must be asked again
        self.kb().forget_answers();
        if let Some(State::Meshing(run)) = self.state.as_mut() {
            run.mesher().forget_answers();
        }
        if outcome.is_err() {
            error = Some("the Prolog engine failed on this query (its state may be damaged: :quit and start again if answers look wrong)".into());
        }
        // As a Prolog toplevel: answers joined by ;, the last with a full
        // stop when it is known to be the last, else followed by false.
        let n = answers.len();
        let ends = error.is_none() && stop.is_none();
        for (i, (a, m)) in answers.iter().enumerate() {
            let prefix = if shown + i == 0 || interactive {
                "   "
            } else {
                ";  "
            };
            let end = if i + 1 == n && ends && *m == More::No {
                "."
            } else {
                ""
            };
            writeln!(out, "{prefix}{a}{end}")?;
        }
        let det = answers.last().is_some_and(|(_, m)| *m == More::No);
        match (error, stop) {
            (Some(e), _) => writeln!(out, "error: {}", one_line(&e)),
            (None, Some(Stop::Interrupted)) => writeln!(out, "% interrupted"),
            (None, Some(Stop::Enough)) => {
                writeln!(out, "   % stopped after {MAX_ANSWERS} answers")
            }
            (None, Some(Stop::Asked)) => Ok(()),
            (None, None) if det => Ok(()),
            (None, None) if n + shown == 0 || interactive => writeln!(out, "   false."),
            (None, None) => writeln!(out, ";  false."),
        }
    }

    fn consult(&mut self, path: &str, out: &mut dyn Write) -> io::Result<()> {
        match self.kb().consult_file(path) {
            Ok(n) => {
                writeln!(out, "% consulted {path}: {n} clauses")?;
                if let Some(State::Meshing(run)) = self.state.as_mut() {
                    if let Err(e) = run.mesher().kb_changed() {
                        writeln!(out, "error: {}", one_line(&e.to_string()))?;
                    }
                }
            }
            Err(e) => writeln!(out, "error: {}", one_line(&e.to_string()))?,
        }
        Ok(())
    }

    /// Makes `n` more elements (None: to the end, and the mesh finished
    /// as `mesh` finishes it) and prints their trace.
    fn advance(&mut self, n: Option<usize>, out: &mut dyn Write) -> io::Result<()> {
        let trace = self.trace;
        let interrupt = Arc::clone(&self.interrupt);
        let mut interrupted = false;
        let Some(State::Meshing(run)) = self.state.as_mut() else {
            return writeln!(out, "error: no domain loaded (:load DOMAIN.json)");
        };
        if self.finished.is_some() {
            return writeln!(out, "% the mesh is complete");
        }
        let quads = |run: &Run| run.mesher_ref().mesh().quads.len();
        let (quads0, trace0) = (quads(run), run.mesher_ref().trace().len());
        let mut failure = None;
        loop {
            if n.is_some_and(|n| quads(run) >= quads0 + n) {
                break;
            }
            if interrupt.swap(false, Ordering::SeqCst) {
                interrupted = true;
                break;
            }
            match run.step() {
                Ok(true) => {}
                Ok(false) => break,
                Err(e) => {
                    failure = Some(e.to_string());
                    break;
                }
            }
        }
        if trace {
            for t in &run.mesher_ref().trace()[trace0..] {
                writeln!(out, "{}", t.to_text())?;
            }
        }
        let made = quads(run) - quads0;
        if let Err(e) = run.mesher().publish_front() {
            failure.get_or_insert(e.to_string());
        }
        if let Some(e) = failure {
            return writeln!(out, "error: {}", one_line(&e));
        }
        if interrupted {
            writeln!(out, "% interrupted")?;
        }
        // stepping stops where the rules are stuck; :run goes on to the
        // last resort, as `mesh` does
        if let (Some(reason), Some(_)) = (run.stopped(), n) {
            return writeln!(out, "error: {}", one_line(reason));
        }
        if !run.mesher_ref().is_done() && run.stopped().is_none() {
            let loops = run.mesher_ref().front_node_loops();
            return writeln!(
                out,
                "% {made} element(s) made, {} in all; the front: {} segments in {} loop(s)",
                quads(run),
                loops.iter().map(Vec::len).sum::<usize>(),
                loops.len()
            );
        }
        match run.finish() {
            Ok(r) => {
                writeln!(
                    out,
                    "% the mesh is complete: {} quads, {} nodes, angles {:.1}..{:.1} deg, {:.1}% in [{}, {}], {} fallback splits{}",
                    r.quality.quads,
                    r.mesh.nodes.len(),
                    r.quality.min_angle,
                    r.quality.max_angle,
                    r.quality.pct_45_135,
                    r.quality.corner_window[0],
                    r.quality.corner_window[1],
                    r.stats.fallback_splits,
                    r.stats.stopped_text()
                )?;
                self.finished = Some(r);
            }
            Err(e) => writeln!(out, "error: {}", one_line(&e.to_string()))?,
        }
        Ok(())
    }

    fn print_front(&mut self, out: &mut dyn Write) -> io::Result<()> {
        let Some(State::Meshing(run)) = self.state.as_mut() else {
            return writeln!(out, "error: no domain loaded (:load DOMAIN.json)");
        };
        let loops = run.mesher_ref().front_loop_angles();
        if loops.is_empty() {
            return writeln!(out, "% the front is empty: the domain is meshed");
        }
        for (i, l) in loops.iter().enumerate() {
            let nodes: Vec<String> = l.iter().map(|(n, a)| format!("{n}({a})")).collect();
            writeln!(
                out,
                "loop {} ({} segments): {}",
                i + 1,
                l.len(),
                nodes.join(" ")
            )?;
        }
        Ok(())
    }

    fn svg(&mut self, path: &str, out: &mut dyn Write) -> io::Result<()> {
        let name = self.name.clone();
        let text = match (&self.finished, self.state.as_ref()) {
            (Some(r), _) => to_svg(&r.mesh, &[], &name),
            (None, Some(State::Meshing(run))) => {
                let m = run.mesher_ref();
                to_svg(m.mesh(), &m.front_node_loops(), &name)
            }
            _ => return writeln!(out, "error: no domain loaded (:load DOMAIN.json)"),
        };
        match write_all(&[(Path::new(path).to_path_buf(), text)]) {
            Ok(()) => writeln!(out, "% wrote {path}"),
            Err(e) => writeln!(out, "error: {}", one_line(&e.to_string())),
        }
    }

    /// `:write FILE`: the session's mesh in the format of the extension;
    /// before it is complete, the elements made so far.
    fn write(&mut self, path: &str, out: &mut dyn Write) -> io::Result<()> {
        let format = match Format::from_path(Path::new(path)) {
            Ok(f) => f,
            Err(e) => return writeln!(out, "error: {}", one_line(&e.to_string())),
        };
        if format == Format::Svg {
            return self.svg(path, out);
        }
        let (mesh, complete) = match (&self.finished, self.state.as_ref()) {
            (Some(r), _) => (&r.mesh, true),
            (None, Some(State::Meshing(run))) => (run.mesher_ref().mesh(), false),
            _ => return writeln!(out, "error: no domain loaded (:load DOMAIN.json)"),
        };
        let text = render(mesh, None, &self.name, format);
        let quads = mesh.quads.len();
        match write_all(&[(Path::new(path).to_path_buf(), text)]) {
            Ok(()) if complete => writeln!(out, "% wrote {path}: {quads} quads"),
            Ok(()) => writeln!(
                out,
                "% wrote {path}: the {quads} quads made so far (the mesh is not complete)"
            ),
            Err(e) => writeln!(out, "error: {}", one_line(&e.to_string())),
        }
    }
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
