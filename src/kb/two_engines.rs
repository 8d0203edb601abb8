//! The knowledge base with a second engine beside it: started, handed
//! batches and whole tasks, and told of every change of bounds (the
//! engine itself is `second_engine.rs`; the first, `engine.rs`).

use crate::kb::engine::{KbStats, KnowledgeBase};
use crate::kb::error::KbError;
use crate::kb::second_engine::{Answer, Answerer, Question, SecondEngine};

/// Batches of new questions smaller than this are answered by the first
/// engine alone: handing work over costs about a question's time.
const SPLIT_FROM: usize = 2;

/// A second engine on its way (`KnowledgeBase::second_engine_loading`).
pub struct SecondEngineLoading(SecondEngine);

impl KnowledgeBase {
    /// Starts a second engine on another thread with the same rules (the
    /// built-in ones and the files consulted so far), to answer part of
    /// each batch of `ask_bounded_fresh_all`. Worth it on a machine with
    /// a core to spare and a run of more than a fraction of a second.
    pub fn start_second_engine(&mut self) {
        let user_files = self.user_files().to_vec();
        self.second = Some(Self::second_engine_loading(user_files).0);
    }

    /// `start_second_engine` now if this engine is built, else when it is
    /// (a run the answer store answers whole builds neither).
    pub fn start_second_engine_when_built(&mut self) {
        if self.is_built() {
            self.start_second_engine();
        } else {
            self.second_when_built = true;
        }
    }

    /// A second engine that starts loading now, on its own thread, with
    /// the built-in rules and `user_files` (as `consult_file` is given
    /// them): a caller with a core to spare builds it while the first
    /// engine loads, then hands it over with `take_second_engine`.
    pub fn second_engine_loading(user_files: Vec<String>) -> SecondEngineLoading {
        // the engine is built on the thread that uses it (it cannot move)
        SecondEngineLoading(SecondEngine::start(move || {
            let mut kb = KnowledgeBase::with_user_files(&user_files).ok()?;
            // ready only when it can answer what the store cannot
            kb.build_now().ok()?;
            Some(Box::new(kb) as Box<dyn Answerer>)
        }))
    }

    /// Whether this engine has a second one to share its work with
    /// (loaded or loading).
    pub fn has_second_engine(&self) -> bool {
        self.second.is_some()
    }

    /// Takes a second engine started by `second_engine_loading` (with the
    /// same user files as this one's) to answer part of each batch.
    pub fn take_second_engine(&mut self, second: SecondEngineLoading) {
        self.second = Some(second.0);
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

    /// Hands `task` to the second engine when one is loaded and waiting
    /// (None: there is none, or it is not ready yet; the caller does the
    /// work itself). The task's questions are counted with the second
    /// engine's when its result is taken by `take_from_second_engine`.
    pub(crate) fn on_second_engine<R: Send + 'static>(
        &mut self,
        task: impl FnOnce(&mut KnowledgeBase) -> R + Send + 'static,
    ) -> Option<std::sync::mpsc::Receiver<Option<(R, KbStats)>>> {
        if !self.second_engine_ready() {
            return None;
        }
        let second = self.second.as_ref()?;
        Some(second.spawn(move |engine| {
            // (the second engine is built as a knowledge base; were it
            // not, the caller would do the task itself)
            let kb = engine.as_any().downcast_mut::<KnowledgeBase>()?;
            let before = kb.stats;
            let r = task(kb);
            Some((r, kb.stats.since(&before)))
        }))
    }

    /// `on_second_engine`, or where the run asked for a second engine
    /// that has not started (the answer store answered every question so
    /// far, so neither engine was built) and this knowledge base holds the
    /// built-in rules alone, on a thread of its own with a twin of it: the
    /// same rules and bounds, built only at a question the store cannot
    /// answer. None: the caller does the task itself.
    pub(crate) fn on_another_thread<R: Send + 'static>(
        &mut self,
        task: impl FnOnce(&mut KnowledgeBase) -> R + Send + 'static,
    ) -> Option<std::sync::mpsc::Receiver<Option<(R, KbStats)>>> {
        if !self.makes_twins() {
            return self.on_second_engine(task);
        }
        let (pushes, in_place) = (self.pushes.clone(), self.in_place.clone());
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            // (an engine cannot move between threads: the twin is made on
            // the thread that uses it)
            let twin = || -> Result<KnowledgeBase, KbError> {
                let mut kb = KnowledgeBase::builtin()?;
                for push in &pushes {
                    kb.apply_bounds(push)?;
                }
                kb.in_place = in_place;
                Ok(kb)
            };
            let done = twin().ok().map(|mut kb| {
                let before = kb.stats;
                let r = task(&mut kb);
                (r, kb.stats.since(&before))
            });
            let _ = tx.send(done);
        });
        Some(rx)
    }

    /// Whether `on_another_thread` hands a task to a twin of this
    /// knowledge base (each its own thread), not to the second engine.
    pub(crate) fn makes_twins(&self) -> bool {
        self.second_when_built && self.state.is_some()
    }

    /// The result of a task handed to the second engine, its questions
    /// counted as the second engine's (None: the engine was lost).
    pub(crate) fn take_from_second_engine<R>(
        &mut self,
        rx: std::sync::mpsc::Receiver<Option<(R, KbStats)>>,
    ) -> Option<R> {
        let (r, used) = rx.recv().ok()??;
        self.stats.engine_queries += used.engine_queries;
        self.stats.cached_queries += used.cached_queries;
        self.stats.stored_answers += used.stored_answers;
        self.stats.second_engine_queries += used.engine_queries;
        self.stats.second_engine_time += used.engine_time;
        Some(r)
    }

    /// Whether a second engine is loaded and answering.
    pub(super) fn second_engine_ready(&self) -> bool {
        self.second.as_ref().and_then(SecondEngine::is_ready) == Some(true)
    }

    /// Runs `change` (a query that sets or restores bounds) here and on
    /// the second engine, in its turn among the work handed to it; the
    /// answers memoised are dropped on both. A second engine on which it
    /// fails stops: it would no longer answer as this one does.
    pub(super) fn change_bounds(&mut self, change: &str) -> Result<(), KbError> {
        self.apply_bounds(change)?;
        self.tell_second_engine(change);
        Ok(())
    }

    /// Has the second engine make `change` in its turn.
    fn tell_second_engine(&self, change: &str) {
        if let Some(second) = &self.second {
            let change = change.to_string();
            second.change(move |engine| {
                engine
                    .as_any()
                    .downcast_mut::<KnowledgeBase>()
                    .is_some_and(|kb| kb.apply_bounds(&change).is_ok())
            });
        }
    }

    /// As this engine's build starts: the second engine asked for by
    /// `start_second_engine_when_built`, told the bounds in force (changed
    /// while the store answered and neither was built).
    pub(super) fn start_second_engine_at_build(&mut self) {
        if std::mem::take(&mut self.second_when_built) {
            self.start_second_engine();
            for push in &self.pushes {
                self.tell_second_engine(push);
            }
        }
    }

    /// `ask_bounded_fresh` for each question, in order. A batch of
    /// `SPLIT_FROM` or more is shared with the second engine when there
    /// is one and it is ready: both take questions in turn.
    pub(super) fn ask_bounded_fresh_all(&mut self, questions: Vec<Question>) -> Vec<Answer> {
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
}
