//! A second engine, on a thread of its own, with the same rules as the
//! first: when a change of the front raises several new design questions
//! at once, both engines take questions from the batch in turn until none
//! is left (see `KnowledgeBase::designs`). Both hold the same
//! clauses and a design answer depends only on its question, so the mesh
//! and the trace are the same as with one engine, whoever answers what.
//!
//! The thread builds its engine itself (an engine is not sent between
//! threads) while the first one starts meshing; until it is ready, and
//! whenever it is slow to wake, the first engine answers everything.
//!
//! It also takes whole tasks that need an engine of their own (with
//! `--blocks`, one of the layouts): the task runs there while the first
//! engine does other work, and its result comes back by a channel.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Receiver, Sender, TryRecvError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use scryer_prolog::Term;

use crate::kb::error::KbError;

/// A question: the query text and the context named if a rule fails.
pub type Question = (String, String);

/// An answer: the first answer's `R`, or the rule at fault.
pub type Answer = Result<Option<Term>, KbError>;

/// An engine that answers questions (the knowledge base; each engine
/// built on the thread that uses it).
pub trait Answerer {
    /// The answer to one question.
    fn answer(&mut self, question: &Question) -> Answer;
    /// The engine itself, for a task that needs more than answers.
    fn as_any(&mut self) -> &mut dyn std::any::Any;
}

/// A whole piece of work for the second engine (it gets the engine);
/// false stops the engine (it can no longer answer as the first would).
pub type Task = Box<dyn FnOnce(&mut dyn Answerer) -> bool + Send>;

/// What the second engine's thread is handed.
enum Job {
    Batch(Arc<Batch>),
    Task(Task),
}

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
    fn work(&self, kb: &mut dyn Answerer) -> u64 {
        let mut mine = 0;
        loop {
            let i = self.next.fetch_add(1, Ordering::SeqCst);
            let Some(question) = self.questions.get(i) else {
                return mine;
            };
            let answer = kb.answer(question);
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
    jobs: Sender<Job>,
    shared: Arc<Shared>,
}

impl SecondEngine {
    /// Starts the thread, which makes its engine by `make` (None: it
    /// failed to load).
    pub fn start(
        make: impl FnOnce() -> Option<Box<dyn Answerer>> + Send + 'static,
    ) -> SecondEngine {
        let (jobs, job_rx) = mpsc::channel();
        let shared = Arc::new(Shared::default());
        let theirs = Arc::clone(&shared);
        std::thread::spawn(move || serve(make, job_rx, theirs));
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
    pub fn share(&self, kb: &mut dyn Answerer, questions: Vec<Question>) -> (Vec<Answer>, u64) {
        let n = questions.len();
        let batch = Arc::new(Batch::new(questions));
        let handed = self.jobs.send(Job::Batch(Arc::clone(&batch))).is_ok();
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
            .map(|(a, question)| a.unwrap_or_else(|| kb.answer(question)))
            .collect();
        (answers, theirs)
    }

    /// Hands `task` to the second engine; its result comes by the
    /// receiver (which reports a disconnection if the thread is gone).
    pub fn spawn<R: Send + 'static>(
        &self,
        task: impl FnOnce(&mut dyn Answerer) -> R + Send + 'static,
    ) -> Receiver<R> {
        let (tx, rx) = mpsc::channel();
        let job = Job::Task(Box::new(move |kb| {
            let _ = tx.send(task(kb));
            true
        }));
        let _ = self.jobs.send(job);
        rx
    }

    /// Hands `task` to the second engine after the work handed before it
    /// and before any handed after; where it answers false, the engine
    /// stops (and the first answers alone from then on).
    pub fn change(&self, task: impl FnOnce(&mut dyn Answerer) -> bool + Send + 'static) {
        let _ = self.jobs.send(Job::Task(Box::new(task)));
    }
}

fn serve(
    make: impl FnOnce() -> Option<Box<dyn Answerer>>,
    jobs: Receiver<Job>,
    shared: Arc<Shared>,
) {
    let _gone = GoneOnDrop(Arc::clone(&shared));
    let Some(mut kb) = make() else {
        return;
    };
    shared.ready.store(true, Ordering::SeqCst);
    let mut last = Instant::now();
    loop {
        let job = match jobs.try_recv() {
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
        match job {
            Job::Batch(batch) => {
                let t0 = Instant::now();
                batch.work(kb.as_mut());
                shared
                    .nanos
                    .fetch_add(t0.elapsed().as_nanos() as u64, Ordering::SeqCst);
            }
            // (a task's questions are counted by the task itself)
            Job::Task(task) => {
                if !task(kb.as_mut()) {
                    return;
                }
            }
        }
        last = Instant::now();
    }
}
