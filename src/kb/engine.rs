//! The engine: scryer-prolog embedded as a library, loaded with the
//! built-in rules of `kb/*.pl` and the user's `--kb` files; it runs the
//! questions `questions.rs` asks and the queries a user types.
//!
//! The engine has no API for Rust predicates, so the split is: the KB
//! answers with action terms whose parameters it computes itself, and the
//! host executes them (see `initial_design.rs`). Answers to the hot queries depend
//! only on the text of the query, so they are memoised by that text: the
//! mesh and the trace are the same as without the cache, and the engine's
//! per-query memory (it keeps ~2 bytes a query character) stays bounded.

use scryer_prolog::{LeafAnswer, Machine, MachineBuilder, OutputStreamConfig, StreamConfig, Term};

use crate::kb::answer_store;
use crate::kb::error::KbError;
use crate::kb::second_engine::{Answer, Answerer, Question, SecondEngine};
use crate::kb::terms::{
    self, atom_or_text, binding_pair, fault_to_error, term_number, term_text, user_query_question,
    Bindings,
};
use crate::kb::user_file::ConsultCopy;
use std::collections::HashMap;

/// The built-in knowledge base, in load order (file name, text).
pub const BUILTIN_KB: &[(&str, &str)] = &[
    ("kb/strategy.pl", include_str!("../../kb/strategy.pl")),
    ("kb/geometry.pl", include_str!("../../kb/geometry.pl")),
    ("kb/features.pl", include_str!("../../kb/features.pl")),
    ("kb/design.pl", include_str!("../../kb/design.pl")),
    ("kb/redesign.pl", include_str!("../../kb/redesign.pl")),
    ("kb/patterns.pl", include_str!("../../kb/patterns.pl")),
    ("kb/front.pl", include_str!("../../kb/front.pl")),
];

const LOADER: &str = include_str!("loader.pl");

/// What a user's rules need (a file read clause by clause, a REPL query):
/// consulted the first time one comes in, not by every run.
const USER_LOADER: &str = include_str!("user_loader.pl");

/// Predicates a `--kb` file replaces instead of extending: one of arity 1
/// (`strategy/1`) whole, one of arity 2 or more (`bound/2`) name by name,
/// by its first argument (`fm_consult/3` in `loader.pl`).
const SETTINGS: &[&str] = &["strategy/1", "bound/2", "graded_bound/2"];

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

/// The engine with its rules loaded; built at the first question the
/// answer store cannot answer (`answer_store.rs`).
pub struct KnowledgeBase {
    machine: Option<Machine>,
    /// Whether what queries write goes to standard output (the prompt's).
    to_stdout: bool,
    /// The rules' state for the answer store: the built-in rules and the
    /// bounds changed since; None once a user's rule may have come in (a
    /// file, a query typed, the front stated as facts).
    pub(super) state: Option<answer_store::RulesState>,
    /// The pushes of bounds in force, outermost first (a pop takes the
    /// last): made in turn on built-in rules, they give these bounds (an
    /// engine built late, a second engine, a twin are given them).
    pub(super) pushes: Vec<String>,
    /// The files loaded, in order, for messages and the REPL.
    pub(crate) files: Vec<String>,
    cache: HashMap<String, Option<Term>>,
    /// Queries sent to the engine (cache misses) and answered from the cache.
    pub(crate) stats: KbStats,
    pub(super) second: Option<SecondEngine>,
    /// Whether a second engine starts when this one is built.
    pub(super) second_when_built: bool,
    /// Whether `USER_LOADER` is consulted.
    user_loader: bool,
    /// The time the engine took to build and consult its files.
    load_time: std::time::Duration,
    /// The names of the bounds set in place (`with_bounds_in_place`),
    /// outermost first.
    pub(super) in_place: Vec<Vec<String>>,
}

/// Counters of the engine's use.
#[derive(Debug, Default, Clone, Copy)]
pub struct KbStats {
    /// Queries run by the engine.
    pub engine_queries: u64,
    /// Queries answered from the memo.
    pub cached_queries: u64,
    /// Queries answered from the answer store (kept by earlier runs).
    pub stored_answers: u64,
    /// The engine's build, when it happened in the run (at the first
    /// question the store could not answer).
    pub build_time: std::time::Duration,
    /// Time spent in the engine.
    pub engine_time: std::time::Duration,
    /// Of the engine queries, those a second engine answered in parallel.
    pub second_engine_queries: u64,
    /// The second engine's time on them.
    pub second_engine_time: std::time::Duration,
}

impl KbStats {
    /// The use counted since `before` (counters taken earlier).
    pub fn since(&self, before: &KbStats) -> KbStats {
        KbStats {
            engine_queries: self.engine_queries - before.engine_queries,
            cached_queries: self.cached_queries - before.cached_queries,
            stored_answers: self.stored_answers - before.stored_answers,
            build_time: self.build_time - before.build_time,
            engine_time: self.engine_time - before.engine_time,
            second_engine_queries: self.second_engine_queries - before.second_engine_queries,
            second_engine_time: self.second_engine_time - before.second_engine_time,
        }
    }
}

/// The answer store's state of the built-in rules (their texts hashed
/// once a process).
fn initial_state() -> answer_store::Key {
    static STATE: std::sync::OnceLock<answer_store::Key> = std::sync::OnceLock::new();
    *STATE.get_or_init(|| {
        // and what the build runs after consulting them
        let mut texts = vec![LOADER, terms::ONLY_BUILT_IN_RULES];
        for (name, text) in BUILTIN_KB {
            texts.extend([*name, *text]);
        }
        answer_store::initial_state(&texts)
    })
}

impl KnowledgeBase {
    /// The built-in KB; its engine is built (about 0.05-0.1 s) at the
    /// first question the answer store cannot answer: build one per run
    /// or per worker.
    pub fn builtin() -> Result<KnowledgeBase, KbError> {
        Ok(KnowledgeBase {
            machine: None,
            to_stdout: false,
            state: Some(answer_store::RulesState::new(initial_state())),
            pushes: Vec::new(),
            files: BUILTIN_KB.iter().map(|(n, _)| n.to_string()).collect(),
            cache: HashMap::new(),
            stats: KbStats::default(),
            second: None,
            second_when_built: false,
            user_loader: false,
            load_time: std::time::Duration::ZERO,
            in_place: Vec::new(),
        })
    }

    /// The built-in KB for a person typing queries (`freemesh repl`):
    /// what the queries write goes to standard output, and the libraries
    /// a Prolog prompt has are loaded.
    pub fn builtin_for_prompt() -> Result<KnowledgeBase, KbError> {
        let mut kb = Self::builtin()?;
        kb.to_stdout = true;
        kb.load_query_libraries()?;
        Ok(kb)
    }

    /// Builds the engine now if it is not built (a second engine is
    /// ready only once it can answer).
    pub(super) fn build_now(&mut self) -> Result<(), KbError> {
        self.engine().map(|_| ())
    }

    /// Whether the engine is built.
    pub(super) fn is_built(&self) -> bool {
        self.machine.is_some()
    }

    /// The engine, built first if it is not yet.
    fn engine(&mut self) -> Result<&mut Machine, KbError> {
        if self.machine.is_none() {
            self.build()?;
        }
        match self.machine.as_mut() {
            Some(m) => Ok(m),
            None => unreachable!("built above"),
        }
    }

    fn build(&mut self) -> Result<(), KbError> {
        let t0 = std::time::Instant::now();
        self.start_second_engine_at_build();
        let streams = if self.to_stdout {
            StreamConfig::in_memory().with_user_output(OutputStreamConfig::stdout())
        } else {
            StreamConfig::in_memory()
        };
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
        self.machine = Some(machine);
        // A built-in file that did not load leaves its predicates missing:
        // check one predicate of each file so a broken build says so.
        for probe in terms::BUILT_IN_PROBES {
            let ok = self.run_on_engine(&terms::probe_question(probe), usize::MAX)?;
            if ok.is_empty() {
                return Err(KbError::Clause {
                    path: "built-in knowledge base".into(),
                    line: 0,
                    reason: format!("{probe} does not hold: a kb/*.pl file did not load"),
                });
            }
        }
        self.run_on_engine(terms::ONLY_BUILT_IN_RULES, usize::MAX)?;
        // the bounds changed while the store answered
        for push in self.pushes.clone() {
            self.run_on_engine(&push, usize::MAX)?;
        }
        let took = t0.elapsed();
        self.load_time += took;
        self.stats.build_time += took;
        Ok(())
    }

    /// The files loaded, in order: the built-in `kb/*.pl`, then the
    /// user's.
    pub fn files(&self) -> &[String] {
        &self.files
    }

    /// The user's files, in the order they were consulted.
    pub fn user_files(&self) -> &[String] {
        &self.files[BUILTIN_KB.len().min(self.files.len())..]
    }

    /// The time the engine took to build, consult the built-in rules and
    /// the user's files (0 while the answer store answered every
    /// question).
    pub fn load_time(&self) -> std::time::Duration {
        self.load_time
    }

    /// The engine's use since it was built (a run's own share is in
    /// `MeshResult::kb_stats`).
    pub fn stats(&self) -> KbStats {
        self.stats
    }

    /// Runs a query the host wrote (well-formed by construction) and
    /// returns every answer's bindings. An exception is an error.
    pub(crate) fn run(&mut self, query: &str) -> Result<Vec<Bindings>, KbError> {
        self.run_limited(query, usize::MAX)
    }

    /// Like `run`, stopping after `limit` answers.
    fn run_limited(&mut self, query: &str, limit: usize) -> Result<Vec<Bindings>, KbError> {
        let key = self.store_key(limit, query);
        if let Some(answers) = key.and_then(answer_store::get) {
            self.stats.stored_answers += 1;
            return Ok(answers);
        }
        self.ask_engine(query, limit, key)
    }

    /// The store's key of `query` asked for at most `limit` answers; None
    /// with no store open (the text is then not hashed) or once a user's
    /// rule may have come in.
    pub(super) fn store_key(&self, limit: usize, query: &str) -> Option<answer_store::Key> {
        let state = self.state.as_ref()?;
        answer_store::is_open().then(|| state.key(limit, query))
    }

    /// Runs `query` on the engine (built first if need be), counted, and
    /// keeps the answers under `key`.
    fn ask_engine(
        &mut self,
        query: &str,
        limit: usize,
        key: Option<answer_store::Key>,
    ) -> Result<Vec<Bindings>, KbError> {
        self.build_now()?;
        let t0 = std::time::Instant::now();
        self.stats.engine_queries += 1;
        let out = self.run_on_engine(query, limit);
        self.stats.engine_time += t0.elapsed();
        if let (Some(key), Ok(answers)) = (key, &out) {
            answer_store::put(key, answers);
        }
        out
    }

    /// Runs `query` on the engine (built): up to `limit` answers.
    fn run_on_engine(&mut self, query: &str, limit: usize) -> Result<Vec<Bindings>, KbError> {
        let mut out = Vec::new();
        let machine = self.engine()?;
        for answer in machine.run_query(query.to_string()) {
            match answer {
                Ok(LeafAnswer::True) => out.push(Bindings::new()),
                Ok(LeafAnswer::False) => break,
                Ok(LeafAnswer::LeafAnswer { bindings, .. }) => out.push(bindings),
                Ok(LeafAnswer::Exception(e)) | Err(e) => {
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
        Ok(out)
    }

    /// From here on the answer store is not asked: a user's rule may
    /// come in, or facts be stated, that its answers do not know.
    pub(super) fn leave_answer_store(&mut self) {
        self.state = None;
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
        let q = user_query_question(&text, limit);
        let machine = match self.trust_rules_no_more().and_then(|()| self.engine()) {
            Ok(machine) => machine,
            Err(e) => {
                on_answer(UserAnswer::Error(e.to_string()));
                return;
            }
        };
        for answer in machine.run_query(q) {
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
    pub(super) fn ask_bounded(
        &mut self,
        query: &str,
        context: &str,
    ) -> Result<Option<Term>, KbError> {
        let ans = self.ask_cached(query, "R")?;
        fault_to_error(ans, context)
    }

    /// Like `ask_bounded`, for a caller that memoises the answers itself.
    pub(super) fn ask_bounded_fresh(
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
    fn trust_rules_no_more(&mut self) -> Result<(), KbError> {
        self.leave_answer_store();
        if !self.user_loader {
            self.engine()?
                .consult_module_string("fm_user_loader", USER_LOADER.to_string());
            self.user_loader = true;
        }
        // a query the loader defines: it cannot fail to run
        let _ = self.run(terms::NOT_ONLY_BUILT_IN_RULES);
        Ok(())
    }

    /// Loads the libraries a person typing queries expects at a Prolog
    /// prompt (`between/3`, `format/2`, `dif/2`, `must_be/2`, ...): the
    /// engine's own toplevel brings some of them, and the machines here
    /// are built without it.
    pub fn load_query_libraries(&mut self) -> Result<(), KbError> {
        self.leave_answer_store();
        self.run(terms::QUERY_LIBRARIES).map(|_| ())
    }

    /// Drops the memoised answers (the rules may have changed, so a
    /// second engine is stopped too).
    pub fn forget_answers(&mut self) {
        self.cache.clear();
        self.second = None;
    }

    /// Whether a `with_bounds_in_place` call is under way (an engine
    /// built from the user's files alone would answer otherwise).
    pub fn has_bounds_in_place(&self) -> bool {
        !self.in_place.is_empty()
    }

    /// The built-in rules, then `user_files` consulted in turn.
    pub fn with_user_files(user_files: &[String]) -> Result<KnowledgeBase, KbError> {
        let mut kb = KnowledgeBase::builtin()?;
        for f in user_files {
            kb.consult_file(f)?;
        }
        Ok(kb)
    }

    pub(super) fn apply_bounds(&mut self, change: &str) -> Result<(), KbError> {
        self.cache.clear();
        // a change answered from the store is made by the engine when it
        // is built (from `pushes`); a built engine makes it now
        let key = self.store_key(usize::MAX, change);
        let stored = match self.machine {
            None => key.and_then(answer_store::get),
            Some(_) => None,
        };
        let answers = match stored {
            Some(answers) => {
                self.stats.stored_answers += 1;
                answers
            }
            None => self.ask_engine(change, usize::MAX, key)?,
        };
        if answers.is_empty() {
            return Err(KbError::Query {
                query: change.split('(').next().unwrap_or(change).to_string(),
                error: "false (it did not hold)".into(),
            });
        }
        let pop = change == terms::POP_BOUNDS;
        if let Some(state) = &mut self.state {
            state.change(change, pop);
        }
        if pop {
            self.pushes.pop();
        } else {
            self.pushes.push(change.to_string());
        }
        Ok(())
    }

    /// The first answer's binding of `var`, memoised by query text.
    pub(super) fn ask_cached(&mut self, query: &str, var: &str) -> Result<Option<Term>, KbError> {
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
        let t0 = std::time::Instant::now();
        let consulted = self.consult_file_timed(path);
        self.load_time += t0.elapsed();
        consulted
    }

    fn consult_file_timed(&mut self, path: &str) -> Result<usize, KbError> {
        let meta = std::fs::metadata(path).map_err(|e| KbError::Read {
            path: path.into(),
            message: e.to_string(),
        })?;
        if meta.is_dir() {
            return Err(KbError::Read {
                path: path.into(),
                message: "a folder, not a file".into(),
            });
        }
        let abs = std::fs::canonicalize(path).map_err(|e| KbError::Read {
            path: path.into(),
            message: e.to_string(),
        })?;
        self.trust_rules_no_more()?;
        // the engine reads a file that ends in a comment as a syntax
        // error (scryer-prolog 0.10: `% last line` after the last clause
        // gives incomplete_reduction): it reads a copy that ends in
        // `end_of_file.` instead, the lines numbered as in the file
        let copy = ConsultCopy::of(&abs).map_err(|message| KbError::Read {
            path: path.into(),
            message,
        })?;
        let read_from = copy.as_ref().map_or(abs.as_path(), |c| c.path.as_path());
        let q = terms::consult_question(&read_from.to_string_lossy(), SETTINGS);
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
                // a clause left open at the end is the file's, not the
                // copy's line after it
                let line = term_number(&args[0]).unwrap_or(0.0) as u64;
                Err(KbError::Clause {
                    path: path.into(),
                    line: copy.as_ref().map_or(line, |c| line.min(c.lines.max(1))),
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
}

impl Answerer for KnowledgeBase {
    fn answer(&mut self, (query, context): &Question) -> Answer {
        self.ask_bounded_fresh(query, context)
    }

    fn as_any(&mut self) -> &mut dyn std::any::Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DESIGN_B1: &str = "fm_design(ctx(180, 180, 180, 180, 180, 1.0, 1.0, 1.0), R).";

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

    fn design_question(ctx: &str) -> Question {
        (format!("fm_design({ctx}, R)."), ctx.to_string())
    }

    #[test]
    fn a_shared_batch_gets_the_answers_one_engine_gives() {
        let questions: Vec<Question> = [90, 120, 150, 180, 200, 240, 270, 300]
            .iter()
            .flat_map(|t| {
                [
                    design_question(&format!("ctx(180, 180, {t}, 180, 180, 1.0, 1.0, 1)")),
                    design_question(&format!("ctx(90, 180, 90, {t}, 90, 0.8, 1.2, 1)")),
                ]
            })
            .collect();
        let mut alone = KnowledgeBase::builtin().unwrap();
        let expected: Vec<String> = questions
            .iter()
            .map(|(q, c)| format!("{:?}", alone.ask_bounded_fresh(q, c).unwrap()))
            .collect();
        let mut kb = KnowledgeBase::builtin().unwrap();
        kb.start_second_engine();
        let t0 = std::time::Instant::now();
        // share until the second engine has answered some (it may be slow
        // to start on a busy machine)
        while kb.stats.second_engine_queries == 0 {
            let got: Vec<String> = kb
                .ask_bounded_fresh_all(questions.clone())
                .into_iter()
                .map(|a| format!("{:?}", a.unwrap()))
                .collect();
            assert_eq!(got, expected);
            assert!(
                t0.elapsed() < std::time::Duration::from_secs(60),
                "the second engine never answered"
            );
        }
    }

    #[test]
    fn a_task_on_the_second_engine_sees_the_users_rules_and_is_counted() {
        let file = std::env::temp_dir().join(format!("fm-task-{}.pl", std::process::id()));
        std::fs::write(&file, "task_probe(42).\n").unwrap();
        let name = file.to_string_lossy().into_owned();
        let second = KnowledgeBase::second_engine_loading(vec![name.clone()]);
        let mut kb = KnowledgeBase::builtin().unwrap();
        kb.consult_file(&name).unwrap();
        kb.take_second_engine(second);
        assert!(kb.wait_for_second_engine(std::time::Duration::from_secs(60)));
        let before = kb.stats;
        let rx = kb
            .on_second_engine(|kb| kb.ask_cached("task_probe(X).", "X").unwrap())
            .expect("a ready second engine takes the task");
        let answer = kb
            .take_from_second_engine(rx)
            .expect("its result comes back");
        let _ = std::fs::remove_file(&file);
        assert_eq!(answer.map(|t| term_text(&t)), Some("42".to_string()));
        assert_eq!(kb.stats.engine_queries, before.engine_queries + 1);
        assert_eq!(
            kb.stats.second_engine_queries,
            before.second_engine_queries + 1
        );
    }

    #[test]
    fn bounds_in_place_are_what_both_engines_answer_and_go_back_after() {
        const BAND: &str = "bound(uniform_size_band, V).";
        let all_bounds = |kb: &mut KnowledgeBase| -> Vec<String> {
            kb.run("bound(N, V).")
                .unwrap()
                .iter()
                .map(|b| format!("{}={}", term_text(&b["N"]), term_text(&b["V"])))
                .collect()
        };
        let mut kb = KnowledgeBase::builtin().unwrap();
        kb.start_second_engine();
        assert!(kb.wait_for_second_engine(std::time::Duration::from_secs(60)));
        let before = all_bounds(&mut kb);
        // memoised here, so a memo kept past the change would show
        let band = kb.ask_cached(BAND, "V").unwrap().map(|t| term_text(&t));
        assert_ne!(band.as_deref(), Some("1.75"));
        let (here, there) = kb
            .with_bounds_in_place(&[("uniform_size_band".to_string(), 1.75)], |kb| {
                let here = kb.ask_cached(BAND, "V").unwrap().map(|t| term_text(&t));
                let rx = kb
                    .on_second_engine(|kb| kb.ask_cached(BAND, "V").unwrap().map(|t| term_text(&t)))
                    .expect("a ready second engine takes the task");
                (here, kb.take_from_second_engine(rx).flatten())
            })
            .unwrap();
        assert_eq!(here.as_deref(), Some("1.75"));
        assert_eq!(there.as_deref(), Some("1.75"));
        // every bound back, in its order, on both engines
        assert_eq!(all_bounds(&mut kb), before);
        assert_eq!(
            kb.ask_cached(BAND, "V").unwrap().map(|t| term_text(&t)),
            band
        );
        let rx = kb
            .on_second_engine(|kb| kb.ask_cached(BAND, "V").unwrap().map(|t| term_text(&t)))
            .unwrap();
        assert_eq!(kb.take_from_second_engine(rx).flatten(), band);
    }

    #[test]
    fn bounds_set_in_place_by_an_outer_call_win_over_an_inner_ones() {
        let mut kb = KnowledgeBase::builtin().unwrap();
        let bound = |kb: &mut KnowledgeBase, n: &str| {
            kb.run(&format!("bound({n}, V).")).unwrap()[0]["V"].clone()
        };
        let (before_rows, before_coarsen) = (
            bound(&mut kb, "row_growth"),
            bound(&mut kb, "coarsen_ratio"),
        );
        let graded = kb.graded_bounds().unwrap();
        assert_eq!(graded[0].0, "row_growth");
        let outer = [("row_growth".to_string(), 3.0)];
        let (inner, placed) = kb
            .with_bounds_in_place(&outer, |kb| {
                kb.with_bounds_not_in_place(&graded, |kb| {
                    (bound(kb, "row_growth"), bound(kb, "coarsen_ratio"))
                })
                .unwrap()
            })
            .unwrap();
        assert_eq!(term_text(&inner.0), "3.0");
        assert_eq!(term_text(&inner.1), "1.4");
        assert_eq!(
            placed,
            vec![
                ("coarsen_ratio".to_string(), 1.4),
                ("graded_collapse_below".to_string(), 0.5)
            ]
        );
        assert_eq!(bound(&mut kb, "row_growth"), before_rows);
        assert_eq!(bound(&mut kb, "coarsen_ratio"), before_coarsen);
    }

    #[test]
    fn a_rule_at_fault_is_named_whichever_engine_asks() {
        let mut kb = KnowledgeBase::builtin().unwrap();
        kb.consult_file("tests/kb/throws-on-a-reflex-corner.pl")
            .unwrap();
        kb.start_second_engine();
        let questions: Vec<Question> = (265..=275)
            .map(|t| design_question(&format!("ctx(180, 180, {t}, 180, 180, 1.0, 1.0, 1)")))
            .collect();
        let t0 = std::time::Instant::now();
        while kb.stats.second_engine_queries == 0 {
            for a in kb.ask_bounded_fresh_all(questions.clone()) {
                let e = a.unwrap_err().to_string();
                assert!(e.contains("the rule feature(b6) raised"), "{e}");
            }
            assert!(
                t0.elapsed() < std::time::Duration::from_secs(60),
                "the second engine never answered"
            );
        }
    }
}
