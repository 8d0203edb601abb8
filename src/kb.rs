//! The knowledge base: scryer-prolog embedded as a library, loaded with the
//! built-in rules of `kb/*.pl` and the user's `--kb` files, and the queries
//! the mesher asks of it.
//!
//! The engine has no API for Rust predicates, so the split is: the KB
//! answers with action terms whose parameters it computes itself, and the
//! host executes them (see `design.rs`). Answers to the hot queries depend
//! only on the text of the query, so they are memoised by that text: the
//! mesh and the trace are the same as without the cache, and the engine's
//! per-query memory (it keeps ~2 bytes a query character) stays bounded.

use scryer_prolog::{LeafAnswer, Machine, MachineBuilder, OutputStreamConfig, StreamConfig, Term};

use crate::second_engine::{Answer, Question, SecondEngine};
use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;

/// The built-in knowledge base, in load order (file name, text).
pub const BUILTIN_KB: &[(&str, &str)] = &[
    ("kb/strategy.pl", include_str!("../kb/strategy.pl")),
    ("kb/geometry.pl", include_str!("../kb/geometry.pl")),
    ("kb/features.pl", include_str!("../kb/features.pl")),
    ("kb/design.pl", include_str!("../kb/design.pl")),
    ("kb/redesign.pl", include_str!("../kb/redesign.pl")),
    ("kb/patterns.pl", include_str!("../kb/patterns.pl")),
    ("kb/front.pl", include_str!("../kb/front.pl")),
];

const LOADER: &str = include_str!("kb_loader.pl");

/// The libraries loaded for queries typed at `freemesh repl` (the built-in
/// files load `lists`, `iso_ext` and `charsio` themselves).
pub const QUERY_LIBRARIES: &[&str] = &[
    "lists", "between", "format", "dif", "error", "si", "lambda", "iso_ext", "charsio", "dcgs",
    "pairs", "ordsets", "assoc", "freeze", "reif", "time",
];

/// Predicates a `--kb` file replaces instead of extending: one of arity 1
/// (`strategy/1`) whole, one of arity 2 or more (`bound/2`) name by name,
/// by its first argument (`fm_consult/3` in `kb_loader.pl`).
pub const SETTINGS: &[&str] = &["strategy/1", "bound/2"];

/// An error of the knowledge base: loading a file or answering a query.
#[derive(Debug, thiserror::Error)]
pub enum KbError {
    /// A KB file could not be read.
    #[error("{path}: cannot read: {message}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// A KB file has a clause the KB refuses (syntax error, unknown action...).
    #[error("{path}:{line}: {reason}")]
    Clause {
        /// The file.
        path: String,
        /// Its line (0 when unknown).
        line: u64,
        /// What is wrong, in Prolog's words.
        reason: String,
    },
    /// A query raised an exception in a rule.
    #[error("knowledge base: {query} raised {error}")]
    Query {
        /// The predicate asked.
        query: String,
        /// The exception term.
        error: String,
    },
    /// A rule threw or ran past the inference limit while meshing.
    #[error("knowledge base: the rule {rule} {why} on {context}")]
    Rule {
        /// The rule at fault (`feature(b6)`, `feature_action(b6)`, ...).
        rule: String,
        /// What it did.
        why: String,
        /// The question it was asked (the edge's context, ...).
        context: String,
    },
    /// A query answered with something the host cannot use.
    #[error("knowledge base: {query} answered {answer}, which is not {expected}")]
    Answer {
        /// The predicate asked.
        query: String,
        /// What it answered.
        answer: String,
        /// What was expected.
        expected: String,
    },
}

/// One answer's bindings.
pub type Bindings = BTreeMap<String, Term>;

/// Whether a query may have another answer after this one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum More {
    /// The goal left no choice point: this answer is its last.
    No,
    /// Choice points are left: asking again may give another answer, or
    /// `false`.
    Maybe,
}

/// One answer to a query the user typed.
#[derive(Debug, Clone, PartialEq)]
pub enum UserAnswer {
    /// A solution: each named variable with its value as Prolog text
    /// (empty: `true`), and whether another may follow.
    Bindings(Vec<(String, String)>, More),
    /// A syntax error, an exception or a runaway, in Prolog's words.
    Error(String),
}

fn atom_or_text(t: &Term) -> String {
    match t {
        Term::Atom(a) => a.clone(),
        other => term_text(other),
    }
}

fn binding_pair(t: &Term) -> Option<(String, String)> {
    match t {
        Term::Compound(f, args) if f == "=" && args.len() == 2 => {
            Some((atom_or_text(&args[0]), atom_or_text(&args[1])))
        }
        _ => None,
    }
}

/// The engine with its rules loaded.
pub struct KnowledgeBase {
    machine: Machine,
    /// The files loaded, in order, for messages and the REPL.
    pub files: Vec<String>,
    cache: HashMap<String, Option<Term>>,
    /// Queries sent to the engine (cache misses) and answered from the cache.
    pub stats: KbStats,
    second: Option<SecondEngine>,
}

/// Counters of the engine's use.
#[derive(Debug, Default, Clone, Copy)]
pub struct KbStats {
    /// Queries run by the engine.
    pub engine_queries: u64,
    /// Queries answered from the memo.
    pub cached_queries: u64,
    /// Time spent in the engine.
    pub engine_time: std::time::Duration,
    /// Of the engine queries, those a second engine answered in parallel.
    pub second_engine_queries: u64,
    /// The second engine's time on them.
    pub second_engine_time: std::time::Duration,
}

/// Batches of new questions smaller than this are answered by the first
/// engine alone: handing work over costs about a question's time.
const SPLIT_FROM: usize = 2;

/// Renders a term as Prolog text (atoms quoted when needed).
pub fn term_text(t: &Term) -> String {
    let mut s = String::new();
    write_term(&mut s, t);
    s
}

fn atom_needs_quotes(a: &str) -> bool {
    let mut ch = a.chars();
    match ch.next() {
        None => true,
        Some(c) if c.is_ascii_lowercase() => {
            !a.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        }
        _ => {
            !matches!(a, "[]" | "!" | ";" | "{}" | "," | "|")
                && !a.chars().all(|c| "+-*/\\^<>=~:.?@#&$".contains(c))
        }
    }
}

fn write_term(s: &mut String, t: &Term) {
    match t {
        Term::Integer(i) => {
            let _ = write!(s, "{i}");
        }
        Term::Rational(r) => {
            let _ = write!(s, "{r}");
        }
        Term::Float(f) => s.push_str(&fmt_float(*f)),
        Term::Atom(a) => {
            if atom_needs_quotes(a) {
                let _ = write!(s, "'{}'", a.replace('\\', "\\\\").replace('\'', "\\'"));
            } else {
                s.push_str(a);
            }
        }
        Term::String(st) => {
            let _ = write!(s, "{st:?}");
        }
        Term::List(l) => {
            s.push('[');
            for (i, x) in l.iter().enumerate() {
                if i > 0 {
                    s.push(',');
                }
                write_term(s, x);
            }
            s.push(']');
        }
        Term::Compound(f, args) => {
            if args.len() == 2 && matches!(f.as_str(), "/" | ":" | "-" | "=" | "+" | "*") {
                write_term(s, &args[0]);
                s.push_str(f);
                write_term(s, &args[1]);
                return;
            }
            write_term(s, &Term::Atom(f.clone()));
            s.push('(');
            for (i, x) in args.iter().enumerate() {
                if i > 0 {
                    s.push_str(", ");
                }
                write_term(s, x);
            }
            s.push(')');
        }
        Term::Var(v) => s.push_str(v),
        _ => s.push_str("_"),
    }
}

/// A float as Prolog text (always with a dot, exponents as `1.0e-5`).
pub fn fmt_float(f: f64) -> String {
    if !f.is_finite() {
        return "0.0".into();
    }
    if let Some(s) = fmt_thousandths(f) {
        return s;
    }
    let s = format!("{f:?}");
    if s.contains('e') && !s.contains('.') {
        s.replacen('e', ".0e", 1)
    } else {
        s
    }
}

/// `fmt_float` of a number that is a whole number of thousandths (the
/// mesher's angles and rounded ratios), written from the integer: the
/// same text as the shortest form Rust writes, for a fraction of its cost.
fn fmt_thousandths(f: f64) -> Option<String> {
    let k = (f * 1000.0).round();
    if k.abs() >= 1e12 || k / 1000.0 != f {
        return None;
    }
    let k = k as i64;
    let (whole, mut frac) = ((k / 1000).abs(), (k % 1000).abs());
    let sign = if f < 0.0 || (f == 0.0 && f.is_sign_negative()) {
        "-"
    } else {
        ""
    };
    let mut digits = 3;
    while digits > 1 && frac % 10 == 0 {
        frac /= 10;
        digits -= 1;
    }
    Some(format!("{sign}{whole}.{frac:0digits$}"))
}

/// The numeric value of a number term.
pub fn term_number(t: &Term) -> Option<f64> {
    match t {
        Term::Integer(i) => i.to_string().parse().ok(),
        Term::Float(f) => Some(*f),
        Term::Rational(r) => {
            let s = r.to_string();
            match s.split_once('/') {
                Some((a, b)) => Some(a.trim().parse::<f64>().ok()? / b.trim().parse::<f64>().ok()?),
                None => s.parse().ok(),
            }
        }
        _ => None,
    }
}

fn prolog_quoted(s: &str) -> String {
    format!("'{}'", s.replace('\\', "\\\\").replace('\'', "\\'"))
}

impl KnowledgeBase {
    /// A machine with the built-in KB loaded (about 0.1-0.2 s: build it
    /// once per run or per worker).
    pub fn builtin() -> Result<KnowledgeBase, KbError> {
        Self::with_streams(StreamConfig::in_memory())
    }

    /// The built-in KB for a person typing queries (`freemesh repl`):
    /// what the queries write goes to standard output, and the libraries
    /// a Prolog prompt has are loaded.
    pub fn builtin_for_prompt() -> Result<KnowledgeBase, KbError> {
        let streams = StreamConfig::in_memory().with_user_output(OutputStreamConfig::stdout());
        let mut kb = Self::with_streams(streams)?;
        kb.load_query_libraries()?;
        Ok(kb)
    }

    fn with_streams(streams: StreamConfig) -> Result<KnowledgeBase, KbError> {
        // the engine's own toplevel (its REPL, with a dozen libraries) is
        // not used here: a bare one halves the time a machine takes to
        // build; the loader and the KB load the libraries they use
        let mut machine = MachineBuilder::default()
            .with_streams(streams)
            .with_toplevel(":- module('$toplevel', []).")
            .build();
        machine.consult_module_string("fm_loader", LOADER.to_string());
        for (name, text) in BUILTIN_KB {
            machine.consult_module_string(name, text.to_string());
        }
        let mut kb = KnowledgeBase {
            machine,
            files: BUILTIN_KB.iter().map(|(n, _)| n.to_string()).collect(),
            cache: HashMap::new(),
            stats: KbStats::default(),
            second: None,
        };
        // A built-in file that did not load leaves its predicates missing:
        // check one predicate of each file so a broken build says so.
        for probe in [
            "strategy(_)",
            "point_segment_near(0, 0, 1)",
            "context_feature(ctx(180,180,180,180,180,1,1), _)",
            "context_design(ctx(180,180,180,180,180,1,1), _, _)",
            "violation(outer_corner(n1, 10), _)",
            "loop_patterns([90,90,180,90,90,180], _)",
            "fm_known_action_(a3)",
            "\\+ edge_feature(_, _)",
        ] {
            let ok = kb.run(&format!("{probe}."))?;
            if ok.is_empty() {
                return Err(KbError::Clause {
                    path: "built-in knowledge base".into(),
                    line: 0,
                    reason: format!("{probe} does not hold: a kb/*.pl file did not load"),
                });
            }
        }
        kb.run("assertz(fm_only_built_in_rules_).")?;
        Ok(kb)
    }

    /// Runs a query the host wrote (well-formed by construction) and
    /// returns every answer's bindings. An exception is an error.
    pub fn run(&mut self, query: &str) -> Result<Vec<Bindings>, KbError> {
        self.run_limited(query, usize::MAX)
    }

    /// Like `run`, stopping after `limit` answers.
    pub fn run_limited(&mut self, query: &str, limit: usize) -> Result<Vec<Bindings>, KbError> {
        let t0 = std::time::Instant::now();
        self.stats.engine_queries += 1;
        let mut out = Vec::new();
        for answer in self.machine.run_query(query.to_string()) {
            match answer {
                Ok(LeafAnswer::True) => out.push(Bindings::new()),
                Ok(LeafAnswer::False) => break,
                Ok(LeafAnswer::LeafAnswer { bindings, .. }) => out.push(bindings),
                Ok(LeafAnswer::Exception(e)) | Err(e) => {
                    self.stats.engine_time += t0.elapsed();
                    let name = query.split('(').next().unwrap_or(query).to_string();
                    return Err(KbError::Query {
                        query: name,
                        error: term_text(&e),
                    });
                }
            }
            if out.len() >= limit {
                break;
            }
        }
        self.stats.engine_time += t0.elapsed();
        Ok(out)
    }

    /// Runs a query the user typed (REPL): the text is handed to Prolog as
    /// character codes and read there inside `catch/3`, so a typo is an
    /// answer, never a crash. `on_answer` gets each answer in turn and
    /// says whether to ask for the next; at most `limit` inferences are
    /// spent on each answer.
    pub fn user_query(
        &mut self,
        text: &str,
        limit: u64,
        on_answer: &mut dyn FnMut(UserAnswer) -> bool,
    ) {
        let mut text = text.trim().trim_start_matches("?-").trim().to_string();
        if !text.ends_with('.') {
            text.push_str(" .");
        }
        self.trust_rules_no_more();
        let codes: Vec<String> = text.chars().map(|c| (c as u32).to_string()).collect();
        let q = format!("fm_repl_query([{}], {limit}, A).", codes.join(","));
        for answer in self.machine.run_query(q) {
            let answer = match answer {
                Ok(LeafAnswer::LeafAnswer { mut bindings, .. }) => match bindings.remove("A") {
                    Some(Term::Compound(f, args)) if f == "answer" && args.len() == 2 => {
                        let bindings = match &args[0] {
                            Term::List(items) => items.iter().filter_map(binding_pair).collect(),
                            _ => Vec::new(),
                        };
                        let more = match &args[1] {
                            Term::Atom(a) if a == "last" => More::No,
                            _ => More::Maybe,
                        };
                        UserAnswer::Bindings(bindings, more)
                    }
                    Some(Term::Compound(f, args)) if f == "error" && args.len() == 1 => {
                        UserAnswer::Error(atom_or_text(&args[0]))
                    }
                    // Only halt/0,1 ends a query without binding A.
                    None => UserAnswer::Error(
                        "halt stops the engine's query here; :quit ends the session".into(),
                    ),
                    Some(other) => {
                        UserAnswer::Error(format!("unexpected answer {}", term_text(&other)))
                    }
                },
                Ok(LeafAnswer::True) => UserAnswer::Bindings(Vec::new(), More::Maybe),
                Ok(LeafAnswer::False) => break,
                Ok(LeafAnswer::Exception(e)) | Err(e) => UserAnswer::Error(term_text(&e)),
            };
            let is_error = matches!(answer, UserAnswer::Error(_));
            if !on_answer(answer) || is_error {
                break;
            }
        }
    }

    /// Asks one of the mesher's bounded questions (`fm_design/2`,
    /// `fm_redesign/4`, `fm_patterns/2` of the loader), memoised by text:
    /// the first answer's `R`, or the rule at fault as an error.
    pub fn ask_bounded(&mut self, query: &str, context: &str) -> Result<Option<Term>, KbError> {
        let ans = self.ask_cached(query, "R")?;
        fault_to_error(ans, context)
    }

    /// Like `ask_bounded`, for a caller that memoises the answers itself.
    pub fn ask_bounded_fresh(
        &mut self,
        query: &str,
        context: &str,
    ) -> Result<Option<Term>, KbError> {
        let ans = self.run_limited(query, 1)?;
        fault_to_error(
            ans.into_iter().next().and_then(|mut b| b.remove("R")),
            context,
        )
    }

    /// From now on the mesher's questions are bounded by the inference
    /// limit: rules other than the built-in ones may come in (a user's
    /// file or query), and one of them may run away.
    fn trust_rules_no_more(&mut self) {
        // a query the loader defines: it cannot fail to run
        let _ = self.run("retractall(fm_only_built_in_rules_).");
    }

    /// Loads the libraries a person typing queries expects at a Prolog
    /// prompt (`between/3`, `format/2`, `dif/2`, `must_be/2`, ...): the
    /// engine's own toplevel brings some of them, and the machines here
    /// are built without it.
    pub fn load_query_libraries(&mut self) -> Result<(), KbError> {
        let uses: Vec<String> = QUERY_LIBRARIES
            .iter()
            .map(|l| format!("use_module(library({l}))"))
            .collect();
        self.run(&format!("{}.", uses.join(", "))).map(|_| ())
    }

    /// Drops the memoised answers (the rules may have changed, so a
    /// second engine is stopped too).
    pub fn forget_answers(&mut self) {
        self.cache.clear();
        self.second = None;
    }

    /// Starts a second engine on another thread with the same rules (the
    /// built-in ones and the files consulted so far), to answer part of
    /// each batch of `ask_bounded_fresh_all`. Worth it on a machine with
    /// a core to spare and a run of more than a fraction of a second.
    pub fn start_second_engine(&mut self) {
        let user_files = self.files[BUILTIN_KB.len()..].to_vec();
        self.second = Some(SecondEngine::start(user_files));
    }

    /// Waits until the second engine is loaded; false if there is none,
    /// it failed, or `timeout` passed first.
    pub fn wait_for_second_engine(&self, timeout: std::time::Duration) -> bool {
        let t0 = std::time::Instant::now();
        while t0.elapsed() < timeout {
            match self.second.as_ref().and_then(SecondEngine::is_ready) {
                Some(true) => return true,
                Some(false) => std::thread::sleep(std::time::Duration::from_millis(1)),
                None => return false,
            }
        }
        false
    }

    /// `ask_bounded_fresh` for each question, in order. A batch of
    /// `SPLIT_FROM` or more is shared with the second engine when there
    /// is one and it is ready: both take questions in turn.
    pub fn ask_bounded_fresh_all(&mut self, questions: Vec<Question>) -> Vec<Answer> {
        let ready = self.second.as_ref().and_then(SecondEngine::is_ready);
        match ready {
            Some(true) if questions.len() >= SPLIT_FROM => {
                let Some(second) = self.second.take() else {
                    unreachable!("ready implies a second engine")
                };
                let time_before = second.time();
                let (answers, theirs) = second.share(self, questions);
                self.stats.engine_queries += theirs;
                self.stats.second_engine_queries += theirs;
                // (its time on a question still running shows next time)
                self.stats.second_engine_time += second.time() - time_before;
                self.second = Some(second);
                answers
            }
            None if self.second.is_some() => {
                self.second = None; // it failed to load or is gone
                self.ask_each(&questions)
            }
            _ => self.ask_each(&questions),
        }
    }

    fn ask_each(&mut self, questions: &[Question]) -> Vec<Answer> {
        questions
            .iter()
            .map(|(q, ctx)| self.ask_bounded_fresh(q, ctx))
            .collect()
    }

    /// The first answer's binding of `var`, memoised by query text.
    pub fn ask_cached(&mut self, query: &str, var: &str) -> Result<Option<Term>, KbError> {
        if let Some(t) = self.cache.get(query) {
            self.stats.cached_queries += 1;
            return Ok(t.clone());
        }
        let ans = self.run_limited(query, 1)?;
        let t = ans.into_iter().next().and_then(|mut b| b.remove(var));
        self.cache.insert(query.to_string(), t.clone());
        Ok(t)
    }

    /// Consults a user's KB file: every clause is checked first; a file
    /// with any unsound clause is refused whole, naming file and line.
    /// Settings it defines replace the built-in ones (`strategy/1` whole,
    /// `bound/2` by name); its other clauses are added after the built-in
    /// rules.
    pub fn consult_file(&mut self, path: &str) -> Result<usize, KbError> {
        std::fs::metadata(path).map_err(|e| KbError::Read {
            path: path.into(),
            message: e.to_string(),
        })?;
        let abs = std::fs::canonicalize(path).map_err(|e| KbError::Read {
            path: path.into(),
            message: e.to_string(),
        })?;
        self.trust_rules_no_more();
        let settings = format!("[{}]", SETTINGS.join(", "));
        let q = format!(
            "fm_consult({}, {}, R).",
            prolog_quoted(&abs.to_string_lossy()),
            settings
        );
        let ans = self.run(&q).map_err(|e| KbError::Clause {
            path: path.into(),
            line: 0,
            reason: e.to_string(),
        })?;
        let r = ans.into_iter().next().and_then(|mut b| b.remove("R"));
        self.cache.clear();
        match r {
            Some(Term::Compound(f, args)) if f == "ok" => {
                Ok(args.first().and_then(term_number).unwrap_or(0.0) as usize)
            }
            Some(Term::Compound(f, args)) if f == "error" && args.len() == 2 => {
                Err(KbError::Clause {
                    path: path.into(),
                    line: term_number(&args[0]).unwrap_or(0.0) as u64,
                    reason: term_text(&args[1]),
                })
            }
            other => Err(KbError::Clause {
                path: path.into(),
                line: 0,
                reason: format!(
                    "could not be consulted ({})",
                    other
                        .map(|t| term_text(&t))
                        .unwrap_or_else(|| "no answer".into())
                ),
            }),
        }
        .inspect(|_| {
            self.files.push(path.to_string());
            // its rules are out of date now
            self.second = None;
        })
    }

    /// The recursion strategy: feature names in the order they are tried.
    pub fn strategy(&mut self) -> Result<Vec<String>, KbError> {
        let t = self
            .run("strategy(S).")?
            .into_iter()
            .next()
            .and_then(|mut b| b.remove("S"));
        match t {
            Some(Term::List(items)) => items
                .iter()
                .map(|x| match x {
                    Term::Atom(a) => Ok(a.clone()),
                    other => Err(KbError::Answer {
                        query: "strategy/1".into(),
                        answer: term_text(other),
                        expected: "a feature name".into(),
                    }),
                })
                .collect(),
            other => Err(KbError::Answer {
                query: "strategy/1".into(),
                answer: other
                    .map(|t| term_text(&t))
                    .unwrap_or_else(|| "nothing".into()),
                expected: "a list of feature names".into(),
            }),
        }
    }

    /// A numeric setting `bound(Name, Value)`.
    pub fn bound(&mut self, name: &str) -> Result<f64, KbError> {
        let t = self
            .run(&format!("bound({name}, V)."))?
            .into_iter()
            .next()
            .and_then(|mut b| b.remove("V"));
        t.as_ref()
            .and_then(term_number)
            .ok_or_else(|| KbError::Answer {
                query: format!("bound({name}, _)"),
                answer: t.map(|t| term_text(&t)).unwrap_or_else(|| "nothing".into()),
                expected: "a number".into(),
            })
    }
}

/// The answer of a bounded question, or the rule at fault as an error.
fn fault_to_error(ans: Option<Term>, context: &str) -> Result<Option<Term>, KbError> {
    match &ans {
        Some(Term::Compound(f, args)) if f == "fault" && args.len() == 2 => {
            let why = match &args[1] {
                Term::Compound(r, e) if r == "raised" && e.len() == 1 => {
                    format!("raised {}", term_text(&e[0]))
                }
                _ => "ran past the inference limit (2,000,000 inferences)".to_string(),
            };
            Err(KbError::Rule {
                rule: term_text(&args[0]),
                why,
                context: context.to_string(),
            })
        }
        _ => Ok(ans),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thousandths_are_written_as_rust_writes_them() {
        for k in -3_000_000i64..3_000_000 {
            let f = k as f64 / 1000.0;
            assert_eq!(fmt_thousandths(f), Some(format!("{f:?}")), "{k}");
        }
        assert_eq!(fmt_thousandths(-0.0).as_deref(), Some("-0.0"));
        assert_eq!(fmt_thousandths(0.1 + 0.2), None);
        assert_eq!(fmt_float(1e-5), "1.0e-5");
    }

    const DESIGN_B1: &str = "fm_design(ctx(180, 180, 180, 180, 180, 1.0, 1.0), R).";

    #[test]
    fn a_rule_a_users_query_adds_is_bounded_again() {
        let mut kb = KnowledgeBase::builtin().unwrap();
        // the built-in rules alone answer unbounded
        assert!(!kb.run("fm_only_built_in_rules_.").unwrap().is_empty());
        assert!(kb.ask_bounded_fresh(DESIGN_B1, "ctx").unwrap().is_some());
        let mut answered = false;
        kb.user_query(
            "asserta((feature(b1, _) :- repeat, fail))",
            1000,
            &mut |_| {
                answered = true;
                false
            },
        );
        assert!(answered);
        let e = kb
            .ask_bounded_fresh(DESIGN_B1, "ctx")
            .unwrap_err()
            .to_string();
        assert!(e.contains("ran past the inference limit"), "{e}");
    }

    #[test]
    fn a_users_file_makes_the_questions_bounded() {
        let mut kb = KnowledgeBase::builtin().unwrap();
        kb.consult_file("tests/kb/strategy-b2-first.pl").unwrap();
        assert!(kb.run("fm_only_built_in_rules_.").unwrap().is_empty());
    }
}
