//! Coarser where small features spread their fine elements: a uniform
//! run whose mesh has more than `bound(coarser_when_over, K)` times the
//! domain's area over the size squared in elements (a small hole, a
//! narrow part or fine fixed counts whose elements spread inward until
//! the fronts meet; a run graded for a coarse boundary, over the square
//! of the boundary's mean segment length where that asks for fewer) is
//! meshed again with each variant of
//! `retry_needs(V, many_elements)` (its `retry_bound/3` bounds in place:
//! the transitions then grow those elements back to the size), in their
//! order until one is within the bounds with no more than K times those
//! elements, and the mesh nearest the bounds kept, or as near with fewer
//! elements. The trace's first step says what was tried and kept.
//! Where a core is spare the variants after the first run two at once
//! (the run's own engine and one built from the same files; the first
//! alone, as it is often the only one needed), judged in their order:
//! each run depends on its variant's bounds alone, so the meshes, the
//! one kept and the trace are those of one at a time.

use super::retries::bound_words;
use super::{mesh_uniform_run, Retries, Score, UniformRun};
use crate::input::domain::Domain;
use crate::kb::{KnowledgeBase, RetryVariant};
use crate::pipeline::{Error, MeshResult, Options};
use crate::report::trace::By;
use crate::settings::Settings;

/// The uniform run's mesh, or a coarser one of the same domain where it
/// has many more elements than its area asks for (`first_run`: the
/// uniform run's time, for `Phases::coarser`).
pub(super) fn coarser_when_over(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    opts: &Options,
    run: UniformRun,
    first_run: f64,
) -> Result<MeshResult, Error> {
    let UniformRun {
        result: r,
        settings,
        graded,
        retried,
        boundary_asks,
    } = run;
    let over = settings.host.coarser_when_over;
    let size = opts.size.unwrap_or(domain.size());
    // a boundary coarser than the size asks for fewer: its segments'
    // mean length over the area
    let area_count = domain.area() / (size * size);
    let (area_count, asks_words) = match boundary_asks {
        Some(asks) if asks < area_count => (
            asks,
            "the area over the boundary's mean segment length squared",
        ),
        _ => (area_count, "the domain's area over the size squared"),
    };
    let count = r.mesh.quads.len();
    if over <= 0.0 || graded || (count as f64) <= over * area_count {
        return Ok(r);
    }
    // the patches follow the boundary's counts alone: the variants'
    // bounds, read by the rules, do not change them
    let patches = r
        .trace
        .first()
        .is_some_and(|t| t.by == By::Block && t.action.starts_with("four_sided("));
    if patches && settings.host.coarser_after_four_sided <= 0.0 {
        return Ok(tell_first(
            r,
            None,
            vec![format!(
                "{count} elements, over bound(coarser_when_over, {over}) times {asks_words} ({area_count:.0}); made in four-sided patches from the boundary's counts: not meshed again coarser (bound(coarser_after_four_sided, 0))"
            )],
        ));
    }
    let variants: Vec<_> = kb
        .retry_variants()?
        .into_iter()
        .filter(|(_, _, needs)| needs.iter().any(|n| n == "many_elements"))
        .collect();
    if variants.is_empty() {
        return Ok(r);
    }
    let mut said = vec![format!(
        "{count} elements, over bound(coarser_when_over, {over}) times {asks_words} ({area_count:.0})"
    )];
    let mut kept = (Score::of(&r, &settings, domain), r, None);
    said.push(format!("the first run: {}", kept.0.words()));
    let variants = super::retries::changing_something(kb, variants, &mut said)?;
    if variants.is_empty() {
        return Ok(tell_first(kept.1, None, said));
    }
    let limit = over * area_count;
    // a first run within the bounds keeps a variant only within them as
    // well: a variant's own retries, each a whole run, are not made then
    let first_within = kept.0.outside == 0;
    let retries = if retried || first_within {
        Retries::LeftToTheFirstRun
    } else {
        Retries::Tried
    };
    // the variants' runs, the first alone, the others two at once where
    // a core is spare (each run depends on its variant's bounds alone:
    // the same meshes either way)
    let started = std::time::Instant::now();
    let mut runs = VariantRuns::new(kb, (domain, opts, &settings), &variants, retries, limit);
    // the kept run's own time (the rest is the pass's)
    let mut kept_run = first_run;
    for (i, (variant, bounds, _)) in variants.iter().enumerate() {
        // a variant after one kept within the bounds and with few enough
        // elements is not needed
        let enough = (kept.1.mesh.quads.len() as f64) <= limit;
        if kept.0.outside == 0 && enough {
            said.push(format!(
                "coarser: within the bounds with at most bound(coarser_when_over, {over}) times the area's elements, {} variants after it not tried",
                variants.len() - i
            ));
            break;
        }
        let words = bound_words(bounds);
        let (run, this_run) = runs.take(i, kb);
        let c = match run {
            Ok(c) => c.result,
            // a rule at fault is the KB's error, not this variant's
            Err(e @ Error::Kb(_)) => return Err(e),
            Err(e) => {
                said.push(format!("coarser {variant} ({words}): {e}"));
                continue;
            }
        };
        let s = Score::of(&c, &settings, domain);
        let nearer = (s.weight, s.outside) < (kept.0.weight, kept.0.outside);
        let as_near = (s.weight, s.outside) == (kept.0.weight, kept.0.outside)
            && c.mesh.quads.len() < kept.1.mesh.quads.len();
        let verdict = if nearer || as_near {
            "kept"
        } else {
            "not kept"
        };
        said.push(format!(
            "coarser {variant} ({words}): {} elements, {}: {verdict}",
            c.mesh.quads.len(),
            s.words()
        ));
        if retried {
            said.push(format!(
                "coarser {variant}: no retries of its own (a retry's engine has the user's files and its own bounds alone: they are the first run's, mesh for mesh)"
            ));
        } else if first_within && s.outside > 0 {
            said.push(format!(
                "coarser {variant}: no retries of its own (the first run is within the bounds)"
            ));
        }
        if nearer || as_near {
            kept = (s, c, Some(variant.clone()));
            kept_run = this_run;
        }
    }
    let all_runs = first_run + started.elapsed().as_secs_f64();
    let (_, mut r, variant) = kept;
    r.phases.coarser = (all_runs - kept_run).max(0.0);
    Ok(tell_first(r, variant.as_deref(), said))
}

/// Puts `said` first in the trace's first step (a step of its own where
/// the run told nothing before), its action `coarser(V, ...)` where
/// variant V's mesh is the one kept.
fn tell_first(r: MeshResult, variant: Option<&str>, said: Vec<String>) -> MeshResult {
    let told = r
        .trace
        .first()
        .is_some_and(|t| t.by == By::Block && t.edge == [-1, -1]);
    let mut r = if told {
        r
    } else {
        super::with_first_step(r, "free", vec![])
    };
    let Some(first) = r.trace.first_mut() else {
        return r;
    };
    if let Some(v) = variant {
        first.action = match first.action.as_str() {
            "free" => format!("coarser({v})"),
            a => format!("coarser({v}, {a})"),
        };
    }
    first.redesign.splice(0..0, said);
    r
}

/// A variant's run (the run, or why it failed) and its own time.
type VariantRun = (Result<UniformRun, Error>, f64);

/// The coarser pass's runs of the variants: those made ahead, two at
/// once, and the rest made when asked for, one by one on this engine.
struct VariantRuns<'a> {
    made: Vec<Option<VariantRun>>,
    /// Whether the runs after the first may be made ahead, two at once.
    ahead: bool,
    domain: &'a Domain,
    opts: &'a Options,
    variants: &'a [RetryVariant],
    retries: Retries,
    settings: &'a Settings,
    /// The elements a mesh within the bounds may have for the pass to
    /// stop at it.
    limit: f64,
}

impl<'a> VariantRuns<'a> {
    /// Runs made ahead where a core is spare and no outer call has
    /// bounds in place (the other engine is built from the user's files
    /// alone).
    fn new(
        kb: &KnowledgeBase,
        (domain, opts, settings): (&'a Domain, &'a Options, &'a Settings),
        variants: &'a [RetryVariant],
        retries: Retries,
        limit: f64,
    ) -> VariantRuns<'a> {
        let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
        VariantRuns {
            made: (0..variants.len()).map(|_| None).collect(),
            ahead: cores > 1 && variants.len() > 2 && !kb.has_bounds_in_place(),
            domain,
            opts,
            variants,
            retries,
            settings,
            limit,
        }
    }

    /// Variant `i`'s run. The first is made alone on `kb` (often the
    /// pass needs no other); once a later one is asked for, it and
    /// those after it are made ahead two at once, `kb` taking one and an
    /// engine of the same files the other, in their order up to the
    /// first within the bounds with at most `limit` elements (the pass
    /// stops there or before it).
    fn take(&mut self, i: usize, kb: &mut KnowledgeBase) -> VariantRun {
        if i > 0 && self.ahead && self.made[i].is_none() {
            self.ahead = false;
            self.run_ahead(i, kb);
        }
        let (domain, opts, retries) = (self.domain, self.opts, self.retries);
        self.made[i]
            .take()
            .unwrap_or_else(|| variant_run(domain, kb, opts, &self.variants[i], retries))
    }

    fn run_ahead(&mut self, from: usize, kb: &mut KnowledgeBase) {
        let (domain, opts, variants, retries) =
            (self.domain, self.opts, self.variants, self.retries);
        let (settings, limit) = (self.settings, self.limit);
        let user_files = kb.user_files().to_vec();
        let (made, _) = super::in_order::in_order(
            from..variants.len(),
            2,
            Some(kb),
            &user_files,
            |engine, i| match engine {
                Ok(kb) => variant_run(domain, kb, opts, &variants[i], retries),
                Err(e) => (Err(Error::Kb(e)), 0.0),
            },
            // within the bounds with few enough elements: the pass stops
            // there or before it
            |(run, _)| {
                run.as_ref().is_ok_and(|u| {
                    Score::of(&u.result, settings, domain).outside == 0
                        && (u.result.mesh.quads.len() as f64) <= limit
                })
            },
        );
        for (i, run) in made.into_iter().enumerate() {
            if run.is_some() {
                self.made[i] = run;
            }
        }
    }
}

/// The domain meshed uniform on `kb` with the variant's bounds in place
/// (as an engine built with them answers), and the run's time.
fn variant_run(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    opts: &Options,
    (_, bounds, _): &RetryVariant,
    retries: Retries,
) -> VariantRun {
    let started = std::time::Instant::now();
    let run = match kb.with_bounds_in_place(bounds, |kb| {
        mesh_uniform_run(domain, None, kb, opts, retries, &mut |_| {})
    }) {
        Ok(run) => run,
        Err(e) => Err(Error::Kb(e)),
    };
    (run, started.elapsed().as_secs_f64())
}
