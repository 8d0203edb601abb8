//! The block meshes finished (the clean-up, smoothing and checks of a
//! run) and judged in their order until one is within the bounds. Where
//! the layouts are made one by one as the meshes before fall short, the
//! first is finished alone, the others two at once where a core is
//! spare (`best_finished`); where all are made first (`best_made_first`),
//! a helper on the spare core finishes each as soon as it is made, and
//! this thread joins in once all are. Both hand the meshes to one
//! `Pool`: this thread takes them in their judging order, finishing those
//! the helper has not started. Each mesh is finished alone and judged in
//! its turn, so the meshes, and the one kept, are those of one at a time.

use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Condvar, Mutex};

use super::layouts::Candidate;
use super::{irregular_nodes, number_without_gaps, Score};
use crate::input::domain::Domain;
use crate::kb::KbStats;
use crate::pipeline::{finish_mesh, Error, MeshResult, Options};
use crate::recursion::Outcome;
use crate::settings::ElementBounds;

/// The best mesh so far (score, mesh, name in the trace), and the lines
/// of the trace's first step for what each gave.
struct Judging<'a> {
    best: Option<(Score, MeshResult, String)>,
    tried: &'a mut Vec<String>,
    by: &'a Finishing<'a>,
}

impl Judging<'_> {
    /// Judges one finished mesh: whether it is within the bounds (no
    /// other is needed then). A mesh that fails the mesh check is not
    /// kept (the next layout, or the free mesh, is).
    fn judge(
        &mut self,
        name: String,
        words: &str,
        r: Result<MeshResult, Error>,
    ) -> Result<bool, Error> {
        let r = match r {
            Ok(r) => r,
            Err(Error::Check(e)) => {
                self.tried.push(format!("{words}: {e}"));
                return Ok(false);
            }
            Err(e) => return Err(e),
        };
        let score = Score::of(&r, self.by.settings, self.by.domain);
        self.tried.push(format!("{words}: {}", score.words()));
        let within = score.outside == 0;
        if self.best.as_ref().is_none_or(|(b, _, _)| score < *b) {
            self.best = Some((score, r, name));
        }
        Ok(within)
    }
}

/// What the block meshes of a domain are finished and judged by: the
/// domain, its run's settings and options, and the engine's counts
/// before its blocks (the meshes' counts are the caller's to set).
pub(super) struct Finishing<'a> {
    pub domain: &'a Domain,
    pub settings: &'a crate::settings::Settings,
    pub opts: &'a Options,
    pub kb_before: KbStats,
}

/// A block mesh finished as a run's mesh is (its blocks numbered without
/// gaps).
fn finish(
    outcome: Outcome,
    bounds: &ElementBounds,
    opts: &Options,
    kb_before: KbStats,
) -> Result<MeshResult, Error> {
    finish_mesh(outcome, bounds, opts, kb_before, kb_before).map(|mut r| {
        number_without_gaps(&mut r.mesh.blocks);
        r
    })
}

impl Finishing<'_> {
    fn finish(&self, outcome: Outcome) -> Result<MeshResult, Error> {
        finish(outcome, &self.settings.element, self.opts, self.kb_before)
    }

    /// The best of `candidates` (name in the trace, words in its first
    /// step, the layout's outcome; or the line of one that gave none),
    /// finished in order until one is within the bounds: fewest elements
    /// outside them, then fewest irregular nodes; what each gave is added to
    /// `tried`. The meshes' engine counts are the caller's to set (a
    /// candidate is made as it is asked for).
    pub(super) fn best_finished(
        &self,
        mut queue: impl Iterator<Item = Candidate>,
        tried: &mut Vec<String>,
    ) -> Result<Option<(Score, MeshResult, String)>, Error> {
        // the first alone (often within the bounds: no other is needed),
        // the others two at once where a core is spare (the helper starts
        // on one as soon as it is made)
        let helper = std::thread::available_parallelism().is_ok_and(|c| c.get() > 1);
        let pool = self.pool(helper);
        let _closing = Closing(&pool);
        let finish = |outcome: Outcome| self.finish(outcome);
        let mut judging = Judging {
            best: None,
            tried,
            by: self,
        };
        let (mut made, mut at_once) = (0, 1);
        loop {
            let mut batch = Vec::new();
            while batch.len() < at_once {
                match queue.next() {
                    Some(Ok((name, words, o))) => {
                        pool.offer(made, o);
                        batch.push((made, name, words));
                        made += 1;
                    }
                    Some(Err(line)) => judging.tried.push(line),
                    None => break,
                }
            }
            at_once = if helper { 2 } else { 1 };
            if batch.is_empty() {
                break;
            }
            for (i, name, words) in batch {
                if judging.judge(name, &words, pool.take(i, &finish))? {
                    return Ok(judging.best);
                }
            }
        }
        Ok(judging.best)
    }

    /// A pool for the block meshes, with a helper thread finishing them
    /// where `helper` (not joined: a mesh it finishes that is not needed
    /// is left to it once one is kept).
    fn pool(&self, helper: bool) -> Arc<Pool<Outcome, Result<MeshResult, Error>>> {
        let pool = Arc::new(Pool::default());
        if helper {
            let (pool, bounds, opts, kb_before) = (
                pool.clone(),
                self.settings.element,
                self.opts.clone(),
                self.kb_before,
            );
            std::thread::spawn(move || pool.help(&|o| finish(o, &bounds, &opts, kb_before)));
        }
        pool
    }

    /// As `best_finished`, but every candidate is made before any is judged,
    /// and they are judged in order of their irregular nodes (the lines of
    /// those that gave none first; among equals, in the order made). With
    /// `helper`, another thread finishes each as soon as it is made, while
    /// the next is made here.
    pub(super) fn best_made_first(
        &self,
        candidates: impl Iterator<Item = Candidate>,
        helper: bool,
        tried: &mut Vec<String>,
    ) -> Result<Option<(Score, MeshResult, String)>, Error> {
        let pool = self.pool(helper);
        // (closed however this ends, so that the helper stops)
        let _closing = Closing(&pool);
        let mut order: Vec<((u8, usize), usize, Result<(String, String), String>)> = Vec::new();
        for (i, candidate) in candidates.enumerate() {
            order.push(match candidate {
                Ok((name, words, o)) => {
                    let key = (1, irregular_nodes(&o.mesh));
                    pool.offer(i, o);
                    (key, i, Ok((name, words)))
                }
                Err(line) => ((0, 0), i, Err(line)),
            });
        }
        order.sort_by_key(|(key, _, _)| *key);
        pool.in_order(order.iter().map(|(_, i, _)| *i));
        let finish = |outcome: Outcome| self.finish(outcome);
        let mut judging = Judging {
            best: None,
            tried,
            by: self,
        };
        for (_, i, entry) in order {
            match entry {
                Err(line) => judging.tried.push(line),
                Ok((name, words)) => {
                    if judging.judge(name, &words, pool.take(i, &finish))? {
                        break;
                    }
                }
            }
        }
        Ok(judging.best)
    }
}

/// What finishing an item gave, or the panic it met on the helper
/// (raised again where it is taken).
type Finished<R> = std::thread::Result<R>;

/// The items offered and not yet taken: those waiting to be finished
/// (in the order to finish them) and those finished; `closed` once no
/// more is needed.
struct Pool<T, R> {
    state: Mutex<PoolState<T, R>>,
    changed: Condvar,
}

struct PoolState<T, R> {
    waiting: VecDeque<(usize, T)>,
    done: HashMap<usize, Finished<R>>,
    closed: bool,
}

impl<T, R> Default for Pool<T, R> {
    fn default() -> Self {
        Pool {
            state: Mutex::new(PoolState {
                waiting: VecDeque::new(),
                done: HashMap::new(),
                closed: false,
            }),
            changed: Condvar::new(),
        }
    }
}

impl<T, R> Pool<T, R> {
    fn lock(&self) -> std::sync::MutexGuard<'_, PoolState<T, R>> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Item `i`, to be finished.
    fn offer(&self, i: usize, item: T) {
        self.lock().waiting.push_back((i, item));
        self.changed.notify_all();
    }

    /// Those still waiting finished in the order they will be taken.
    fn in_order(&self, order: impl Iterator<Item = usize>) {
        let rank: HashMap<usize, usize> = order.enumerate().map(|(k, i)| (i, k)).collect();
        self.lock()
            .waiting
            .make_contiguous()
            .sort_by_key(|(i, _)| rank.get(i).copied());
    }

    /// Item `i` finished: by the helper, or here; while the helper
    /// finishes it, the next waiting one is finished here.
    fn take(&self, i: usize, finish: &dyn Fn(T) -> R) -> R {
        let mut state = self.lock();
        loop {
            if let Some(done) = state.done.remove(&i) {
                return done.unwrap_or_else(|e| std::panic::resume_unwind(e));
            }
            let pos = state.waiting.iter().position(|(j, _)| *j == i);
            match pos.or((!state.waiting.is_empty()).then_some(0)) {
                Some(pos) => {
                    let (j, item) = state.waiting.remove(pos).expect("a waiting item");
                    drop(state);
                    let r = finish(item);
                    if j == i {
                        return r;
                    }
                    state = self.lock();
                    state.done.insert(j, Ok(r));
                }
                None => state = self.changed.wait(state).unwrap_or_else(|e| e.into_inner()),
            }
        }
    }

    /// The helper's work: the waiting items finished in turn until the
    /// pool is closed.
    fn help(&self, finish: &dyn Fn(T) -> R) {
        let mut state = self.lock();
        loop {
            if let Some((i, item)) = state.waiting.pop_front() {
                drop(state);
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| finish(item)));
                state = self.lock();
                state.done.insert(i, r);
                self.changed.notify_all();
            } else if state.closed {
                return;
            } else {
                state = self.changed.wait(state).unwrap_or_else(|e| e.into_inner());
            }
        }
    }

    /// No more is needed: the helper stops once the item it is
    /// finishing is (those waiting are dropped).
    fn close(&self) {
        let mut state = self.lock();
        state.closed = true;
        state.waiting.clear();
        drop(state);
        self.changed.notify_all();
    }
}

/// Closes the pool when dropped, however the judging ends.
struct Closing<'a, T, R>(&'a Pool<T, R>);

impl<T, R> Drop for Closing<'_, T, R> {
    fn drop(&mut self) {
        self.0.close();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A slow finish, as a mesh's is, so that the helper and the taker
    /// meet.
    fn square(x: u64) -> u64 {
        std::thread::sleep(std::time::Duration::from_millis(x % 3));
        x * x
    }

    #[test]
    fn items_taken_in_any_order_are_those_finished_once_each_by_either_thread() {
        for helper in [false, true] {
            let pool: Arc<Pool<u64, u64>> = Arc::new(Pool::default());
            let finished = Arc::new(std::sync::atomic::AtomicUsize::new(0));
            let counted = {
                let finished = finished.clone();
                move |x: u64| {
                    finished.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                    square(x)
                }
            };
            let away = helper.then(|| {
                let (pool, counted) = (pool.clone(), counted.clone());
                std::thread::spawn(move || pool.help(&counted))
            });
            for i in 0..8 {
                pool.offer(i, 10 + i as u64);
            }
            let order = [5, 0, 7, 2, 1, 6, 3, 4];
            pool.in_order(order.iter().copied());
            for i in order {
                assert_eq!(
                    pool.take(i, &counted),
                    (10 + i as u64).pow(2),
                    "item {i}, helper {helper}"
                );
            }
            pool.close();
            if let Some(h) = away {
                h.join().unwrap();
            }
            assert_eq!(
                finished.load(std::sync::atomic::Ordering::SeqCst),
                8,
                "helper {helper}"
            );
        }
    }

    #[test]
    fn a_closed_pool_lets_its_helper_go_and_drops_what_waits() {
        let pool: Arc<Pool<u64, u64>> = Arc::new(Pool::default());
        let away = {
            let pool = pool.clone();
            std::thread::spawn(move || pool.help(&square))
        };
        pool.offer(0, 3);
        assert_eq!(pool.take(0, &square), 9);
        {
            let _closing = Closing(&*pool);
            pool.offer(1, 4);
        }
        away.join().unwrap();
        assert!(
            pool.lock().waiting.is_empty(),
            "the waiting item is dropped at closing"
        );
    }

    #[test]
    fn a_panic_on_the_helper_is_raised_where_its_item_is_taken() {
        let pool: Arc<Pool<u64, u64>> = Arc::new(Pool::default());
        let refuse = |x: u64| if x == 7 { panic!("seven") } else { x };
        pool.offer(0, 7);
        let away = {
            let pool = pool.clone();
            std::thread::spawn(move || pool.help(&refuse))
        };
        while pool.lock().done.is_empty() {
            std::thread::yield_now();
        }
        let taken =
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| pool.take(0, &refuse)));
        pool.close();
        away.join().unwrap();
        let why = taken.expect_err("the helper's panic, raised here");
        assert_eq!(why.downcast_ref::<&str>(), Some(&"seven"));
    }
}
