//! Retries: where a uniform run's free and block meshes both fall short,
//! the domain is meshed again with each variant of `retry_bound/3` (the
//! bounds it names in place), free and then in blocks, the variants side
//! by side on the machine's cores; a variant whose free mesh is the first
//! run's (its bounds changed nothing there) is not tried in blocks. A
//! graded run whose mesh falls short is retried the same way, free only
//! (blocks are uniform), without the variants that need `uniform`.

use super::{best_block_mesh, sharpest_input_corner, Score};
use crate::input::domain::Domain;
use crate::kb::KnowledgeBase;
use crate::pipeline::{mesh_domain, Error, MeshResult, Options};

/// The best mesh so far: its score, the mesh, and its action in the
/// trace's first step.
type Best = Option<(Score, MeshResult, String)>;

/// What one retry gave, and its lines for the trace.
type Retried = (Result<Best, Error>, Vec<String>);

/// A run graded by a max_size: its free mesh made with the bounds of
/// `graded_bound/2` in place of bound/2's from its preparation on (the
/// size field is made there), but those a retry has in place (its own
/// win), which the trace's first step names; then `graded_with_retries`.
/// The mesh kept, and the settings the free mesh went by.
pub(super) fn graded_run(
    domain: &Domain,
    boundary: crate::pipeline::RunBoundary,
    kb: &mut KnowledgeBase,
    opts: &Options,
    retries: super::Retries,
    retried: &mut bool,
    progress: &mut dyn FnMut(usize),
) -> Result<(MeshResult, crate::settings::Settings), Error> {
    let bounds = kb.graded_bounds()?;
    let (made, placed) = kb.with_bounds_not_in_place(&bounds, |kb| {
        let prepared = crate::pipeline::prepare_run(domain, boundary, kb, opts)?;
        let settings = prepared.settings().clone();
        crate::pipeline::mesh_prepared(kb, prepared, progress).map(|free| (free, settings))
    })?;
    let (free, settings) = made?;
    let tried: Vec<String> = (!placed.is_empty())
        .then(|| {
            format!(
                "graded by a max_size: {} in place (graded_bound/2)",
                bound_words(&placed)
            )
        })
        .into_iter()
        .collect();
    let r = graded_with_retries(domain, free, &settings, retries, retried, kb, opts, tried)?;
    progress(r.mesh.quads.len());
    Ok((r, settings))
}

/// A graded run's free mesh, or where it falls short the retry of
/// `retry_bound/3` (meshed free: blocks are uniform) nearest the bounds,
/// where it is nearer than the first; where that still falls short, the
/// mesh without the `max_size` where it is within the bounds
/// (`bound(uniform_when_graded_short, _)`).
#[allow(clippy::too_many_arguments)]
fn graded_with_retries(
    domain: &Domain,
    mut free: MeshResult,
    settings: &crate::settings::Settings,
    retries: super::Retries,
    retried: &mut bool,
    kb: &mut KnowledgeBase,
    opts: &Options,
    mut tried: Vec<String>,
) -> Result<MeshResult, Error> {
    let score = Score::of(&free, settings, domain);
    if score.outside == 0 || retries != super::Retries::Tried {
        return Ok(super::told(free, tried));
    }
    tried.push(format!(
        "graded, free: {} (retried free only: blocks are uniform)",
        score.words()
    ));
    let short = Short {
        free: &free.mesh,
        best: None,
        score,
        blocks_share: 0.0,
        coarse_boundary: false,
        graded: true,
    };
    let (best, retries_time, _) =
        retry_where_short(domain, short, settings, opts, kb, &mut tried, retried)?;
    // kept only nearer the bounds: a graded mesh's irregular nodes, the
    // uniform runs' tie-break, are many whichever way the fronts went
    let (kept_score, kept, name) = match best.filter(|b| b.0.weight < score.weight) {
        Some((s, mut r, name)) => {
            // the kept mesh's own stages are among the retries; the first
            // free mesh, not kept, is before them
            let ph = &mut r.phases;
            ph.retries = retries_time - ph.own();
            ph.blocks = free.phases.own();
            (s, r, name)
        }
        None => {
            free.phases.retries = retries_time;
            (score, free, "free".to_string())
        }
    };
    // (not where an input corner is too sharp for any mesh: the retries'
    // line says so)
    let sharp = sharpest_input_corner(&kept.mesh, domain) < settings.host.retry_sharpest_corner;
    if kept_score.outside > 0 && settings.host.uniform_when_graded_short > 0.0 && !sharp {
        if let Some(u) = uniform_within_the_bounds(domain, kb, opts, settings, &mut tried)? {
            return Ok(u);
        }
    }
    Ok(super::with_first_step(kept, &name, tried))
}

/// The domain meshed as without a `max_size` (uniform at the size, but
/// where coarse fixed counts grade it; blocks, retries and all), where
/// that mesh is within the bounds: its trace's first step has `tried`
/// before what it says itself, and its action in `uniform(..)`.
fn uniform_within_the_bounds(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    opts: &Options,
    settings: &crate::settings::Settings,
    tried: &mut Vec<String>,
) -> Result<Option<MeshResult>, Error> {
    let words = format!(
        "without max_size (bound(uniform_when_graded_short, {}))",
        settings.host.uniform_when_graded_short
    );
    let mut ungraded = domain.clone();
    ungraded.max_size = None;
    let uniform = opts.clone().with_max_size(None);
    let mut u = match super::mesh_free_then_blocks(&ungraded, None, kb, &uniform, &mut |_| {}) {
        Ok(u) => u,
        // a rule at fault is the KB's error, as in the first run
        Err(e @ Error::Kb(_)) => return Err(e),
        Err(e) => {
            tried.push(format!("{words}: {e}"));
            return Ok(None);
        }
    };
    let s = Score::of(&u, settings, domain);
    if s.outside > 0 {
        tried.push(format!("{words}: {}: not kept", s.words()));
        return Ok(None);
    }
    tried.push(format!("{words}: {}: kept", s.words()));
    let tried = std::mem::take(tried);
    match u.trace.first_mut().filter(|t| t.feature == "block") {
        Some(first) => {
            first.redesign.splice(0..0, tried);
            first.action = format!("uniform({})", first.action);
            Ok(Some(u))
        }
        None => Ok(Some(super::with_first_step(u, "uniform", tried))),
    }
}

/// A mesh that may fall short, for `retry_where_short`: the first run's
/// free mesh and its score, the best mesh so far (blocks, where better),
/// the share of free blocks a retry's layout may have (0: a graded run,
/// retried free only) and whether the run is graded for a coarse boundary.
pub(super) struct Short<'a> {
    pub free: &'a crate::mesh::Mesh,
    pub best: Best,
    pub score: Score,
    pub blocks_share: f64,
    pub coarse_boundary: bool,
    /// Graded by a `max_size` (a variant that needs `uniform` is not
    /// tried; one that needs `graded` is tried only then).
    pub graded: bool,
}

/// Where the best mesh so far falls short, the domain meshed again with
/// each variant of `retry_bound/3` that applies (`retry_needs/2`), none
/// on a domain with an input corner under `bound(retry_sharpest_corner,
/// _)`: the best mesh then, the retries' time, and whether a retry's mesh
/// is the one kept. What each gave goes to `tried`; `retried` is set
/// where they are made.
pub(super) fn retry_where_short(
    domain: &Domain,
    short: Short,
    settings: &crate::settings::Settings,
    opts: &Options,
    kb: &mut KnowledgeBase,
    tried: &mut Vec<String>,
    retried: &mut bool,
) -> Result<(Best, f64, bool), Error> {
    let Short {
        free,
        mut best,
        score,
        blocks_share,
        coarse_boundary,
        graded,
    } = short;
    if best.as_ref().map_or(score, |b| b.0).outside == 0 {
        return Ok((best, 0.0, false));
    }
    let sharpest = sharpest_input_corner(free, domain);
    let retry_above = settings.host.retry_sharpest_corner;
    if sharpest < retry_above {
        tried.push(format!(
            "no retry: an input corner of {sharpest:.1} deg, under bound(retry_sharpest_corner, {retry_above}) (no element at it meets the taper bound)"
        ));
        return Ok((best, 0.0, false));
    }
    let fixed_counts = super::has_fixed_counts(domain);
    let variants: Vec<_> = kb
        .retry_variants()?
        .into_iter()
        .filter(|(_, _, needs)| {
            needs.iter().all(|n| match n.as_str() {
                "fixed_counts" => fixed_counts,
                "coarse_boundary" => coarse_boundary,
                "uniform" => !graded,
                "graded" => graded,
                "many_elements" => false,
                _ => true,
            })
        })
        .collect();
    // (a graded run's first run had its graded bounds in place: a
    // variant of bound/2's values may change those)
    let variants = if graded {
        variants
    } else {
        changing_something(kb, variants, tried)?
    };
    if variants.is_empty() {
        return Ok((best, 0.0, false));
    }
    // a graded run's retries have its graded bounds in place too
    let graded_bounds = if graded { kb.graded_bounds()? } else { vec![] };
    let user_files = kb.user_files().to_vec();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let started = std::time::Instant::now();
    *retried = true;
    let retries = retry_in_parallel(
        domain,
        &user_files,
        opts,
        settings,
        blocks_share,
        &variants,
        &graded_bounds,
        cores,
        fingerprint(free),
    );
    let mut retry_kept = false;
    for (retried, said) in retries {
        let so_far = best.as_ref().map_or(score, |b| b.0);
        tried.extend(said);
        if let Some(kept) = retried?.filter(|k| k.0 < so_far) {
            best = Some(kept);
            retry_kept = true;
        }
    }
    Ok((best, started.elapsed().as_secs_f64(), retry_kept))
}

/// The retries of `variants`, as if made one after another in their
/// order until the first within the bounds: that one and those before it,
/// in order. Each worker meshes on an engine of its own (built once, each
/// variant's bounds set in place on it), so as many run at once as there
/// are cores, each core taking the next variant as it is free;
/// a variant after one found within the bounds is not begun, and one
/// begun before is dropped, trace lines and all. A variant whose free
/// mesh is the first run's (`first_free`, its fingerprint) is not tried
/// in blocks. `underneath` are in place too, but where a variant has a
/// bound of the same name (a graded run's `graded_bound/2`).
#[allow(clippy::too_many_arguments)]
pub(super) fn retry_in_parallel(
    domain: &Domain,
    user_files: &[String],
    opts: &Options,
    settings: &crate::settings::Settings,
    share: f64,
    variants: &[crate::kb::RetryVariant],
    underneath: &[(String, f64)],
    workers: usize,
    first_free: u64,
) -> Vec<Retried> {
    let (done, last) = super::in_order::in_order(
        0..variants.len(),
        workers,
        None,
        user_files,
        |engine, i| {
            let (variant, bounds, _) = &variants[i];
            let mut said = Vec::new();
            let r = match engine {
                // the variant's bounds, and beneath them those of
                // `underneath` it has no bound of
                Ok(kb) => kb
                    .with_bounds_in_place(bounds, |kb| {
                        kb.with_bounds_not_in_place(underneath, |kb| {
                            retry_variant(
                                domain, kb, opts, settings, share, variant, bounds, first_free,
                                &mut said,
                            )
                        })
                    })
                    .and_then(|r| r)
                    .map_err(Error::Kb)
                    .and_then(|(r, _)| r),
                Err(e) => Err(Error::Kb(e)),
            };
            (r, said)
        },
        |(r, _)| matches!(r, Ok(Some((s, _, _))) if s.outside == 0),
    );
    done.into_iter()
        .take(last.map_or(usize::MAX, |l| l + 1))
        .flatten()
        .collect()
}

/// The domain meshed free on a knowledge base with `variant`'s `bounds`
/// in place, and in blocks too where that mesh falls short: the better
/// of the two, named as the trace's first step names it (`retry(V)`,
/// `retry(V, layout(F))`); None if the free mesh failed. What each gave
/// goes to `tried`, under the variant's name.
#[allow(clippy::too_many_arguments)]
fn retry_variant(
    domain: &Domain,
    other: &mut KnowledgeBase,
    opts: &Options,
    settings: &crate::settings::Settings,
    share: f64,
    variant: &str,
    bounds: &[(String, f64)],
    first_free: u64,
    tried: &mut Vec<String>,
) -> Result<Best, Error> {
    let said = format!("retry {variant} ({})", bound_words(bounds));
    let r = match mesh_domain(domain, other, opts, &mut |_| {}) {
        Ok(r) => r,
        Err(e) => {
            tried.push(format!("{said}: {e}"));
            return Ok(None);
        }
    };
    let s = Score::of(&r, settings, domain);
    tried.push(format!("{said}: {}", s.words()));
    // within the bounds, or no blocks to try (share 0: a graded run,
    // blocks are uniform)
    if s.outside == 0 || share <= 0.0 {
        return Ok(Some((s, r, format!("retry({variant})"))));
    }
    if fingerprint(&r.mesh) == first_free {
        // the variant's bounds changed nothing the free run reads
        tried.push(format!(
            "{said}: the first run's free mesh again, not tried in blocks"
        ));
        return Ok(Some((s, r, format!("retry({variant})"))));
    }
    let mut also = vec![];
    let before = other.stats;
    let blocks = best_block_mesh(domain, other, opts, settings, before, share, &mut also)?;
    tried.extend(also.into_iter().map(|t| format!("{said}: {t}")));
    Ok(Some(match blocks.filter(|(b, _, _)| *b < s) {
        Some((b, m, name)) => (b, m, format!("retry({variant}, {name})")),
        None => (s, r, format!("retry({variant})")),
    }))
}

/// A mesh's nodes and elements hashed (the same mesh, the same number).
pub(super) fn fingerprint(mesh: &crate::mesh::Mesh) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::hash::DefaultHasher::new();
    for p in &mesh.nodes {
        (p.x.to_bits(), p.y.to_bits()).hash(&mut h);
    }
    mesh.quads.hash(&mut h);
    h.finish()
}

/// `variants` but those whose every bound already has its value in
/// `kb` (their run would be the first run, mesh for mesh): `tried` says
/// which were left out.
pub(super) fn changing_something(
    kb: &mut KnowledgeBase,
    variants: Vec<crate::kb::RetryVariant>,
    tried: &mut Vec<String>,
) -> Result<Vec<crate::kb::RetryVariant>, Error> {
    let mut kept = Vec::with_capacity(variants.len());
    for v in variants {
        if kb.would_change_a_bound(&v.1)? {
            kept.push(v);
        } else {
            tried.push(format!(
                "{} ({}): not run, its bounds are those in place",
                v.0,
                bound_words(&v.1)
            ));
        }
    }
    Ok(kept)
}

/// A variant's bounds as the trace gives them: `bound(N, X), ...`.
pub(super) fn bound_words(bounds: &[(String, f64)]) -> String {
    bounds
        .iter()
        .map(|(n, x)| format!("bound({n}, {x})"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn variants() -> Vec<crate::kb::RetryVariant> {
        ["a", "b", "c"]
            .iter()
            .zip([
                ("min_front_angle", 20.0),
                ("near_node", 0.4),
                ("near_horizontal", 0.2),
            ])
            .map(|(v, (n, x))| (v.to_string(), vec![(n.to_string(), x)], vec![]))
            .collect()
    }

    /// What each retry said for the trace, and its score.
    fn retried(domain: &str, workers: usize) -> Vec<(Vec<String>, Option<Score>)> {
        let domain = Domain::from_json_str(domain).unwrap();
        let mut kb = KnowledgeBase::builtin().unwrap();
        let settings = kb.settings().unwrap();
        let opts = Options::default();
        retry_in_parallel(
            &domain,
            &[],
            &opts,
            &settings,
            0.5,
            &variants(),
            &[],
            workers,
            0,
        )
        .into_iter()
        .map(|(r, said)| (said, r.unwrap().map(|k| k.0)))
        .collect()
    }

    #[test]
    fn retries_made_at_once_give_what_one_after_another_gives() {
        // within the bounds at the first variant: the others dropped
        let square = r#"{"name": "sq", "size": 1, "outer": {"points": [[0,0],[4,0],[4,4],[0,4]]}}"#;
        let alone = retried(square, 1);
        assert_eq!(alone.len(), 1);
        assert_eq!(alone[0].1.map(|s| s.outside), Some(0));
        assert_eq!(retried(square, 2), alone);
        // a 7.6-degree tip no element meets the bounds at: all three, in order
        let spike = r#"{"name": "spike", "size": 1, "outer": {"points": [[0,0],[6,0],[6,0.8]]}}"#;
        let alone = retried(spike, 1);
        let starts: Vec<&str> = alone.iter().map(|(said, _)| &said[0][..7]).collect();
        assert_eq!(starts, ["retry a", "retry b", "retry c"]);
        assert!(alone.iter().all(|(_, s)| s.is_some_and(|s| s.outside > 0)));
        assert_eq!(retried(spike, 2), alone);
        assert_eq!(retried(spike, 3), alone);
    }
}
