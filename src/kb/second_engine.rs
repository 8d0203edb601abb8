//! A second engine, on a thread of its own, with the same rules as the
//! first: when a change of the front raises several new design questions
//! at once, both engines take questions from the batch in turn until none
//! is left (see `KnowledgeBase::ask_bounded_fresh_all`). Both hold the same
//! clauses and a design answer depends only on its question, so the mesh
//! and the trace are the same as with one engine, whoever answers what.
//!
//! The thread builds its engine itself (an engine is not sent between
//! threads) while the first one starts meshing; until it is ready, and
//! whenever it is slow to wake, the first engine answers everything.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Receiver, Sender, TryRecvError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use scryer_prolog::Term;

use crate::kb::{KbError, KnowledgeBase};

/// A question: the query text and the context named if a rule fails.
pub type Question = (String, String);

/// An answer as `KnowledgeBase::ask_bounded_fresh` gives it.
pub type Answer = Result<Option<Term>, KbError>;

/// A batch both engines work through: each takes the next question by
/// `next` and files its answer; `done` counts the answers filed.
pub struct Batch {
    questions: Vec<Question>,
    next: AtomicUsize,
    done: AtomicUsize,
    answers: Mutex<Vec<Option<Answer>>>,
}

impl Batch {
    fn new(questions: Vec<Question>) -> Batch {
        let n = questions.len();
        Batch {
            questions,
            next: AtomicUsize::new(0),
            done: AtomicUsize::new(0),
            answers: Mutex::new((0..n).map(|_| None).collect()),
        }
    }

    /// Answers questions of the batch until none is left to take;
    /// returns how many this engine answered.
    fn work(&self, kb: &mut KnowledgeBase) -> u64 {
        let mut mine = 0;
        loop {
            let i = self.next.fetch_add(1, Ordering::SeqCst);
            let Some((q, ctx)) = self.questions.get(i) else {
                return mine;
            };
            let answer = kb.ask_bounded_fresh(q, ctx);
            if let Ok(mut answers) = self.answers.lock() {
                answers[i] = Some(answer);
            }
            self.done.fetch_add(1, Ordering::SeqCst);
            mine += 1;
        }
    }
}

/// What the two threads share besides the batches.
#[derive(Default)]
struct Shared {
    ready: AtomicBool,
    gone: AtomicBool,
    nanos: AtomicU64,
}

/// The thread's state goes to `gone` however it ends, so that the first
/// engine never waits for a question the second will not answer.
struct GoneOnDrop(Arc<Shared>);

impl Drop for GoneOnDrop {
    fn drop(&mut self) {
        self.0.gone.store(true, Ordering::SeqCst);
    }
}

/// After a batch the second engine waits busily this long for the next
/// before sleeping: the questions come in bursts, and waking a sleeping
/// thread costs about as much as answering a question.
const SPIN: Duration = Duration::from_micros(300);

/// The handle the first engine keeps of the second.
pub struct SecondEngine {
    jobs: Sender<Arc<Batch>>,
    shared: Arc<Shared>,
}

impl SecondEngine {
    /// Starts the thread: the built-in rules, then `user_files` in order.
    pub fn start(user_files: Vec<String>) -> SecondEngine {
        let (jobs, job_rx) = mpsc::channel();
        let shared = Arc::new(Shared::default());
        let theirs = Arc::clone(&shared);
        std::thread::spawn(move || serve(user_files, job_rx, theirs));
        SecondEngine { jobs, shared }
    }

    /// Some(true) once the thread's engine is loaded, Some(false) before;
    /// None for good when it failed to load or is gone.
    pub fn is_ready(&self) -> Option<bool> {
        if self.shared.gone.load(Ordering::SeqCst) {
            None
        } else {
            Some(self.shared.ready.load(Ordering::SeqCst))
        }
    }

    /// The second engine's time on its questions so far.
    pub fn time(&self) -> Duration {
        Duration::from_nanos(self.shared.nanos.load(Ordering::SeqCst))
    }

    /// Works through `questions` with `kb` while the second engine does
    /// the same; the answers in order, and how many the second engine gave.
    pub fn share(&self, kb: &mut KnowledgeBase, questions: Vec<Question>) -> (Vec<Answer>, u64) {
        let n = questions.len();
        let batch = Arc::new(Batch::new(questions));
        let handed = self.jobs.send(Arc::clone(&batch)).is_ok();
        let mine = batch.work(kb);
        // wait for the questions the second engine took (each one is
        // bounded by the inference limit), unless it is gone
        while handed && batch.done.load(Ordering::SeqCst) < n {
            if self.shared.gone.load(Ordering::SeqCst) {
                break;
            }
            std::hint::spin_loop();
        }
        let mut answers = match batch.answers.lock() {
            Ok(mut a) => std::mem::take(&mut *a),
            Err(_) => Vec::new(),
        };
        answers.resize_with(n, || None);
        let theirs = answers.iter().filter(|a| a.is_some()).count() as u64 - mine;
        let answers = answers
            .into_iter()
            .zip(&batch.questions)
            // a question the second engine took and never answered
            .map(|(a, (q, ctx))| a.unwrap_or_else(|| kb.ask_bounded_fresh(q, ctx)))
            .collect();
        (answers, theirs)
    }
}

fn serve(user_files: Vec<String>, jobs: Receiver<Arc<Batch>>, shared: Arc<Shared>) {
    let _gone = GoneOnDrop(Arc::clone(&shared));
    let kb = KnowledgeBase::builtin().and_then(|mut kb| {
        for f in &user_files {
            kb.consult_file(f)?;
        }
        Ok(kb)
    });
    let Ok(mut kb) = kb else {
        return;
    };
    shared.ready.store(true, Ordering::SeqCst);
    let mut last = Instant::now();
    loop {
        let batch = match jobs.try_recv() {
            Ok(b) => b,
            Err(TryRecvError::Empty) if last.elapsed() < SPIN => {
                std::hint::spin_loop();
                continue;
            }
            Err(TryRecvError::Empty) => match jobs.recv() {
                Ok(b) => b,
                Err(_) => return,
            },
            Err(TryRecvError::Disconnected) => return,
        };
        let t0 = Instant::now();
        batch.work(&mut kb);
        shared
            .nanos
            .fetch_add(t0.elapsed().as_nanos() as u64, Ordering::SeqCst);
        last = Instant::now();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn design_question(ctx: &str) -> Question {
        (format!("fm_design({ctx}, R)."), ctx.to_string())
    }

    #[test]
    fn a_shared_batch_gets_the_answers_one_engine_gives() {
        let questions: Vec<Question> = [90, 120, 150, 180, 200, 240, 270, 300]
            .iter()
            .flat_map(|t| {
                [
                    design_question(&format!("ctx(180, 180, {t}, 180, 180, 1.0, 1.0)")),
                    design_question(&format!("ctx(90, 180, 90, {t}, 90, 0.8, 1.2)")),
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
        let t0 = Instant::now();
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
                t0.elapsed() < Duration::from_secs(60),
                "the second engine never answered"
            );
        }
    }

    #[test]
    fn a_rule_at_fault_is_named_whichever_engine_asks() {
        let mut kb = KnowledgeBase::builtin().unwrap();
        kb.consult_file("tests/kb/throws-on-a-reflex-corner.pl")
            .unwrap();
        kb.start_second_engine();
        let questions: Vec<Question> = (265..=275)
            .map(|t| design_question(&format!("ctx(180, 180, {t}, 180, 180, 1.0, 1.0)")))
            .collect();
        let t0 = Instant::now();
        while kb.stats.second_engine_queries == 0 {
            for a in kb.ask_bounded_fresh_all(questions.clone()) {
                let e = a.unwrap_err().to_string();
                assert!(e.contains("the rule feature(b6) raised"), "{e}");
            }
            assert!(
                t0.elapsed() < Duration::from_secs(60),
                "the second engine never answered"
            );
        }
    }
}
