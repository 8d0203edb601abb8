//! The block meshes finished (the clean-up, smoothing and checks of a
//! run) in their order until one is within the bounds: the first alone,
//! the others two at once where a core is spare; each is finished alone,
//! so the meshes, and the one kept, are those of one at a time.

use super::layouts::Candidate;
use super::{number_without_gaps, Score};
use crate::input::domain::Domain;
use crate::kb::KbStats;
use crate::pipeline::{finish_mesh, Error, MeshResult, Options};
use crate::recursion::Outcome;

/// The best of `candidates` (name in the trace, words in its first
/// step, the layout's outcome; or the line of one that gave none),
/// finished in order until one is within the bounds: fewest elements
/// outside them, then fewest irregular nodes; what each gave is added to
/// `tried`. The meshes' engine counts are the caller's to set (a
/// candidate is made as it is asked for).
pub(super) fn best_finished(
    mut queue: impl Iterator<Item = Candidate>,
    domain: &Domain,
    settings: &crate::settings::Settings,
    opts: &Options,
    kb_before: KbStats,
    tried: &mut Vec<String>,
) -> Result<Option<(Score, MeshResult, String)>, Error> {
    let mut best: Option<(Score, MeshResult, String)> = None;
    let finish = |outcome: Outcome| {
        finish_mesh(outcome, &settings.element, opts, kb_before, kb_before).map(|mut r| {
            number_without_gaps(&mut r.mesh.blocks);
            r
        })
    };
    // the first alone (often within the bounds: no other is needed),
    // the others two at once where a core is spare (each alone: the
    // same meshes), judged in their order
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let mut at_once = 1;
    loop {
        let mut batch = Vec::new();
        while batch.len() < at_once {
            match queue.next() {
                Some(Ok(candidate)) => batch.push(candidate),
                Some(Err(line)) => tried.push(line),
                None => break,
            }
        }
        at_once = if cores > 1 { 2 } else { 1 };
        if batch.is_empty() {
            break;
        }
        let finished: Vec<(String, String, Result<MeshResult, Error>)> =
            std::thread::scope(|scope| {
                let mut batch = batch.into_iter();
                let first = batch.next();
                let others: Vec<_> = batch
                    .map(|(name, words, o)| scope.spawn(move || (name, words, finish(o))))
                    .collect();
                first
                    .map(|(name, words, o)| (name, words, finish(o)))
                    .into_iter()
                    .chain(
                        others
                            .into_iter()
                            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e))),
                    )
                    .collect()
            });
        for (name, words, r) in finished {
            let r = match r {
                Ok(r) => r,
                // a block mesh that fails the mesh check is not kept (the
                // next layout, or the free mesh, is)
                Err(Error::Check(e)) => {
                    tried.push(format!("{words}: {e}"));
                    continue;
                }
                Err(e) => return Err(e),
            };
            let score = Score::of(&r, settings, domain);
            tried.push(format!("{words}: {}", score.words()));
            let within = score.outside == 0;
            if best.as_ref().is_none_or(|(b, _, _)| score < *b) {
                best = Some((score, r, name));
            }
            if within {
                return Ok(best);
            }
        }
    }
    Ok(best)
}
