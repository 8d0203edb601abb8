//! `freemesh repl`: a Prolog toplevel over the live knowledge base and the
//! front of the remaining domain. Queries are answered the way a Prolog
//! toplevel does (`N = 7`, `true`, `false`); commands (`:load`, `:step`,
//! `:consult`, ...) drive the mesher one element at a time, so the user
//! can watch the features the KB sees change as the front advances.
//!
//! The session is driven line by line through [`Repl::handle`], whatever
//! the input is (a terminal, a pipe, a test), and never panics or stops on
//! what the user types: every fault is one `error:` line.

use std::io::{self, Write};
use std::path::Path;

use crate::kb::{KbStats, KnowledgeBase, UserAnswer};
use crate::mesher::Mesher;
use crate::output::{to_svg, write_all};
use crate::{finish, prepare_run, Domain, MeshResult, Options};

/// At most this many inferences for one answer of a user's query: a
/// query that loops is an error, not a hung session.
pub const INFERENCE_LIMIT: u64 = 20_000_000;

/// With piped input every answer is printed, up to this many.
pub const MAX_ANSWERS: usize = 200;

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
  Answers show as N = 7, true or false; on a terminal, ; asks for the next.
  Each answer may take at most 20,000,000 inferences.

The live front (the boundary of the remaining domain, kb/front.pl):
  node_xy(N, X, Y)      front node N at (X, Y)
  front_edge(N1, N2)    a front edge, the remaining domain on its left
  node_angle(N, Deg)    interior angle of the remaining domain at N
  concave_point(N)      N is a concave point (angle above 180)
  parallel(E1, E2)      front edges E = N1-N2 on parallel lines
  near_segment(N, E)    node N approaches front edge E (Fig. 10)
  edge_feature(E, F)    the oriented edge E = N1-N2 shows feature F (b1..b5)
  edge_action(E, A)     the design action the KB takes on E
  edge_context(E, Ctx)  the context term the mesher asks about E
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
  :front              the loops of the front: node(angle) in order
  :svg FILE.svg       draw the elements made so far and the front
  :trace on|off       print trace lines on :step and :run (default on)
  :help               this text
  :quit               end the session (also halt, or end of input)";

enum State<'k> {
    /// No domain loaded.
    Idle(&'k mut KnowledgeBase),
    /// A run over a domain, at some step.
    Meshing(Box<Mesher<'k>>),
}

/// A REPL session: the KB, and the run over the loaded domain if any.
pub struct Repl<'k> {
    state: Option<State<'k>>,
    size: Option<f64>,
    trace: bool,
    /// The domain's name, for pictures and messages.
    name: String,
    /// The finished mesh, once `:run` or `:step` completed it.
    finished: Option<MeshResult>,
    kb_before: KbStats,
}

impl<'k> Repl<'k> {
    /// A session over `kb`; domains are discretised with boundary size
    /// `size` (their own when None).
    pub fn new(kb: &'k mut KnowledgeBase, size: Option<f64>) -> Repl<'k> {
        Repl {
            kb_before: kb.stats,
            state: Some(State::Idle(kb)),
            size,
            trace: true,
            name: String::new(),
            finished: None,
        }
    }

    fn kb(&mut self) -> &mut KnowledgeBase {
        match self.state.as_mut() {
            Some(State::Idle(kb)) => kb,
            Some(State::Meshing(m)) => m.kb(),
            None => unreachable!("the state is only taken inside load"),
        }
    }

    /// Loads a domain and starts a run over it; the previous run ends.
    /// On an error the session keeps what it had.
    pub fn load(&mut self, path: &str) -> Result<String, crate::Error> {
        let domain = Domain::from_file(path)?;
        let size = self.size;
        let prepared = prepare_run(&domain, self.kb(), size)?;
        let kb = match self.state.take() {
            Some(State::Idle(kb)) => kb,
            Some(State::Meshing(m)) => m.into_kb(),
            None => unreachable!("the state is only taken here"),
        };
        self.kb_before = kb.stats;
        let mut m = Box::new(Mesher::start_from(kb, prepared));
        let published = m.publish_front();
        let loops = m.front_node_loops();
        self.state = Some(State::Meshing(m));
        self.finished = None;
        self.name = domain.name.clone();
        published?;
        Ok(format!(
            "% loaded {}: {} front segments in {} loop(s)",
            domain.name,
            loops.iter().map(Vec::len).sum::<usize>(),
            loops.len()
        ))
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
            ("front", None) => self.print_front(out)?,
            ("svg", Some(path)) => self.svg(path, out)?,
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
        let mut answers: Vec<String> = Vec::new();
        let mut error: Option<String> = None;
        let mut stopped = false;
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
                UserAnswer::Bindings(b) => {
                    let text = if b.is_empty() {
                        "true".to_string()
                    } else {
                        b.iter()
                            .map(|(k, v)| format!("{k} = {v}"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    };
                    if let Some(ask) = more.as_mut() {
                        stopped = !ask(&text);
                        return !stopped;
                    }
                    answers.push(text);
                    stopped = answers.len() >= MAX_ANSWERS;
                    !stopped
                }
            });
        }));
        std::panic::set_hook(hook);
        // the query may have asserted or retracted rules: answers kept
        // from before must be asked again
        self.kb().forget_answers();
        if let Some(State::Meshing(m)) = self.state.as_mut() {
            m.forget_answers();
        }
        if outcome.is_err() {
            error = Some("the Prolog engine failed on this query (its state may be damaged: :quit and start again if answers look wrong)".into());
        }
        let n = answers.len();
        for (i, a) in answers.iter().enumerate() {
            let prefix = if i == 0 { "   " } else { ";  " };
            let end = if i + 1 == n && error.is_none() && !stopped {
                "."
            } else {
                ""
            };
            writeln!(out, "{prefix}{a}{end}")?;
        }
        if stopped && !interactive {
            writeln!(out, "   % stopped after {MAX_ANSWERS} answers")?;
        }
        match error {
            Some(e) => writeln!(out, "error: {}", one_line(&e)),
            None if !stopped && (n == 0 || interactive) => writeln!(out, "   false."),
            None => Ok(()),
        }
    }

    fn consult(&mut self, path: &str, out: &mut dyn Write) -> io::Result<()> {
        match self.kb().consult_file(path) {
            Ok(n) => {
                writeln!(out, "% consulted {path}: {n} clauses")?;
                if let Some(State::Meshing(m)) = self.state.as_mut() {
                    if let Err(e) = m.kb_changed() {
                        writeln!(out, "error: {}", one_line(&e.to_string()))?;
                    }
                }
            }
            Err(e) => writeln!(out, "error: {}", one_line(&e.to_string()))?,
        }
        Ok(())
    }

    /// Makes `n` more elements (None: to the end) and prints their trace.
    fn advance(&mut self, n: Option<usize>, out: &mut dyn Write) -> io::Result<()> {
        let trace = self.trace;
        let Some(State::Meshing(m)) = self.state.as_mut() else {
            return writeln!(out, "error: no domain loaded (:load DOMAIN.json)");
        };
        if self.finished.is_some() {
            return writeln!(out, "% the mesh is complete");
        }
        let (quads0, trace0) = (m.mesh.quads.len(), m.trace.len());
        let mut failure = None;
        loop {
            if n.is_some_and(|n| m.mesh.quads.len() >= quads0 + n) {
                break;
            }
            match m.step() {
                Ok(true) => {}
                Ok(false) => break,
                Err(e) => {
                    failure = Some(e.to_string());
                    break;
                }
            }
        }
        if trace {
            for t in &m.trace[trace0..] {
                writeln!(out, "{}", t.to_text())?;
            }
        }
        let made = m.mesh.quads.len() - quads0;
        if let Err(e) = m.publish_front() {
            failure.get_or_insert(e.to_string());
        }
        if let Some(e) = failure {
            return writeln!(out, "error: {}", one_line(&e));
        }
        if !m.is_done() {
            let loops = m.front_node_loops();
            return writeln!(
                out,
                "% {made} element(s) made, {} in all; the front: {} segments in {} loop(s)",
                m.mesh.quads.len(),
                loops.iter().map(Vec::len).sum::<usize>(),
                loops.len()
            );
        }
        match finish(m, &Options::default(), self.kb_before) {
            Ok(r) => {
                writeln!(
                    out,
                    "% the mesh is complete: {} quads, {} nodes, angles {:.1}..{:.1} deg, {:.1}% in [45, 135], {} fallback splits",
                    r.quality.quads,
                    r.mesh.nodes.len(),
                    r.quality.min_angle,
                    r.quality.max_angle,
                    r.quality.pct_45_135,
                    r.stats.fallback_splits
                )?;
                self.finished = Some(r);
            }
            Err(e) => writeln!(out, "error: {}", one_line(&e.to_string()))?,
        }
        Ok(())
    }

    fn print_front(&mut self, out: &mut dyn Write) -> io::Result<()> {
        let Some(State::Meshing(m)) = self.state.as_mut() else {
            return writeln!(out, "error: no domain loaded (:load DOMAIN.json)");
        };
        let loops = m.front_loop_angles();
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
            (None, Some(State::Meshing(m))) => to_svg(&m.mesh, &m.front_node_loops(), &name),
            _ => return writeln!(out, "error: no domain loaded (:load DOMAIN.json)"),
        };
        match write_all(&[(Path::new(path).to_path_buf(), text)]) {
            Ok(()) => writeln!(out, "% wrote {path}"),
            Err(e) => writeln!(out, "error: {}", one_line(&e.to_string())),
        }
    }
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
