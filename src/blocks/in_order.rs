//! Whole runs made on several engines at once as if one after another:
//! the retries' variants and the coarser pass's. Each worker takes the
//! next item as it is free, on an engine of its own (built on its
//! thread: an engine cannot move), and no item is begun after the first
//! one found to end the order; each item's run depends on the item
//! alone, so what comes out is what one engine would make in turn.

use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use crate::kb::{KbError, KnowledgeBase};

/// The runs of `items`, `workers` at once: one on `main` where given
/// (else on an engine built from `user_files`, as the others are), each
/// item given to `run` with its worker's engine, or the error building
/// it. Returns each run by its item's index (None: not begun, or before
/// `items`) and the first item whose run `ends` (the order stops there:
/// runs after it are dropped by the caller).
pub(super) fn in_order<T: Send>(
    items: Range<usize>,
    workers: usize,
    main: Option<&mut KnowledgeBase>,
    user_files: &[String],
    run: impl Fn(Result<&mut KnowledgeBase, KbError>, usize) -> T + Sync,
    ends: impl Fn(&T) -> bool + Sync,
) -> (Vec<Option<T>>, Option<usize>) {
    let next = AtomicUsize::new(items.start);
    let last = AtomicUsize::new(usize::MAX);
    let done: Mutex<Vec<Option<T>>> = Mutex::new((0..items.end).map(|_| None).collect());
    let work = |mut main: Option<&mut KnowledgeBase>| {
        let mut own: Option<KnowledgeBase> = None;
        loop {
            let i = next.fetch_add(1, Ordering::SeqCst);
            if i >= items.end || i > last.load(Ordering::SeqCst) {
                return;
            }
            let r = match main.as_deref_mut() {
                Some(kb) => run(Ok(kb), i),
                None => match own
                    .take()
                    .map_or_else(|| KnowledgeBase::with_user_files(user_files), Ok)
                {
                    Ok(mut kb) => {
                        let r = run(Ok(&mut kb), i);
                        own = Some(kb);
                        r
                    }
                    Err(e) => run(Err(e), i),
                },
            };
            if ends(&r) {
                last.fetch_min(i, Ordering::SeqCst);
            }
            done.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(r);
        }
    };
    std::thread::scope(|scope| {
        let helpers: Vec<_> = (1..workers.min(items.len()))
            .map(|_| scope.spawn(|| work(None)))
            .collect();
        work(main);
        for h in helpers {
            h.join().unwrap_or_else(|e| std::panic::resume_unwind(e));
        }
    });
    let last = last.load(Ordering::SeqCst);
    let done = done.into_inner().unwrap_or_else(|e| e.into_inner());
    (done, (last != usize::MAX).then_some(last))
}
