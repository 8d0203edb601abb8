//! The layouts a domain's blocks are made of (the rules' meshes of it
//! at a coarse size), given in order from the coarsest, each made as it
//! is asked for: blocks/mod.rs asks for all of them where the first is
//! small, to keep the fewest irregular nodes, and for the next only where
//! the block meshes before it fell short where the first has many blocks
//! (`bound(finer_layouts_up_to, K)`): a finer layout costs more there
//! than all the rest of the run. The finest is made on another thread
//! meanwhile where one is to be had (the coarser ones here, in turn), and
//! stopped, unused, where it is not needed: as soon as the first
//! layout's rules have made more elements than that bound (the other
//! thread's work would slow this one's, and is made here again if it is
//! needed after all), or once a mesh is kept. The meshes, and the one
//! kept, are those of one layout at a time.
//!
//! Where the first layout's rules made more elements than
//! `bound(layout_sizes_free_over, K)`, every layout of the domain is
//! finished by its blocks' corners and taper alone
//! (`ElementBounds::for_layout`): on many blocks that finish costs most
//! of the run, spent on sizes the blocks' division makes no matter.

use std::cell::Cell;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;
use std::sync::Arc;

use crate::input::curves::Curve;
use crate::input::domain::Domain;
use crate::kb::{KbStats, KnowledgeBase};
use crate::pipeline::{discretise_for_run, prepare_run, Error, MeshResult, Options, Run};
use crate::recursion::Outcome;

/// The layout's element size is tried at `bound(block_size, K)`, then at
/// three quarters and half of it (never under 1.5 element sizes), in that
/// order, until a block mesh is within the bounds.
const LAYOUT_STEPS: [f64; 3] = [1.0, 0.75, 0.5];

/// Why a layout stopped before it was made: no longer needed.
const STOPPED: &str = "not needed";

/// How a layout's finish is told: the first decides by its rules'
/// elements (over `up_to`: `halt` set; over `free_over`: `told` set, and
/// it is finished by its blocks' corners and taper), the others are told
/// by it.
#[derive(Clone, Copy)]
enum Finish<'a> {
    First {
        halt: &'a AtomicBool,
        up_to: f64,
        told: &'a Cell<bool>,
        free_over: f64,
    },
    CornersAndTaper(bool),
}

/// A layout made on another thread: its block mesh, or why none.
type Away = Receiver<Option<(Result<Outcome, String>, KbStats)>>;

/// A block mesh of the layouts, or the line the trace's first step says
/// of a layout that gave none.
pub(super) type Candidate = Result<(String, String, Outcome), String>;

/// How a layout becomes its blocks' mesh (blocks/mod.rs, `blocks_of`):
/// the layout, the domain, the size, the knowledge base, whether the
/// trace is kept, the largest share of free blocks; Err says why none.
pub(super) type BlocksOf =
    fn(MeshResult, &Domain, f64, &mut KnowledgeBase, bool, f64) -> Result<Outcome, String>;

/// The layouts of a domain in order from the coarsest, each with its
/// action in the trace's first step (`layout(F)`) and the words its line
/// in that step starts with.
pub(super) struct Layouts<'a> {
    domain: &'a Domain,
    kb: &'a mut KnowledgeBase,
    opts: &'a Options,
    size: f64,
    arc_step: f64,
    max_free_share: f64,
    blocks_of: BlocksOf,
    /// The factors still to give, each with its layout on its way where
    /// another thread makes it.
    queue: VecDeque<(f64, Option<Away>)>,
    /// Set once no layout is needed.
    stop: Arc<AtomicBool>,
    /// Set once the one made on another thread is not needed there.
    stop_away: Arc<AtomicBool>,
    /// `bound(finer_layouts_up_to, K)`, `bound(layout_sizes_free_over,
    /// K)`, whether a layout was given, and whether the first told the
    /// layouts to be finished by their corners and taper.
    up_to: f64,
    free_over: f64,
    given: bool,
    corners_and_taper: Cell<bool>,
}

impl<'a> Layouts<'a> {
    /// The layouts of `domain` at `bound(block_size, K)` and its steps:
    /// each is made here as it is asked for, but the finest (the
    /// costliest), started on another thread now where there are two.
    pub(super) fn new(
        domain: &'a Domain,
        kb: &'a mut KnowledgeBase,
        opts: &'a Options,
        settings: &crate::settings::Settings,
        (max_free_share, blocks_of): (f64, BlocksOf),
    ) -> Layouts<'a> {
        let size = opts.size.unwrap_or(domain.size());
        let arc_step = settings.host.block_arc_step.to_radians();
        let (stop, stop_away) = (Arc::default(), Arc::default());
        // (the first factor is always taken: never empty)
        let queue: VecDeque<(f64, Option<Away>)> = LAYOUT_STEPS
            .iter()
            .map(|step| settings.host.block_size * step)
            .enumerate()
            .take_while(|&(k, factor)| k == 0 || factor >= 1.5)
            .map(|(_, factor)| (factor, None))
            .collect();
        let mut layouts = Layouts {
            domain,
            kb,
            opts,
            size,
            arc_step,
            max_free_share,
            blocks_of,
            queue,
            stop,
            stop_away,
            up_to: settings.host.finer_layouts_up_to,
            free_over: settings.host.layout_sizes_free_over,
            given: false,
            corners_and_taper: Cell::new(false),
        };
        if layouts.queue.len() > 1 {
            layouts.start_away();
        }
        layouts
    }

    /// Hands the finest layout to another thread, where one is to be had
    /// (the second engine, or a twin of this knowledge base).
    fn start_away(&mut self) {
        let Some(last) = self.queue.back_mut() else {
            return;
        };
        let factor = last.0;
        let (d, o, halt) = (
            self.domain.clone(),
            self.opts.clone(),
            self.stop_away.clone(),
        );
        let (size, arc_step) = (self.size, self.arc_step);
        let blocks = (self.max_free_share, self.blocks_of);
        let task = move |kb: &mut KnowledgeBase| {
            let finish = Finish::CornersAndTaper(false);
            block_layout(
                &d,
                kb,
                &o,
                (size, factor, arc_step),
                blocks,
                (&halt, finish),
            )
        };
        last.1 = self.kb.on_another_thread(task);
    }

    /// Whether a layout is made on another thread (there is a spare
    /// core for this run).
    pub(super) fn made_away(&self) -> bool {
        self.queue.iter().any(|(_, away)| away.is_some())
    }

    /// Stops the layouts not given (none is needed now) and waits for
    /// those on their way to stop: the knowledge base's counts then hold
    /// their questions.
    pub(super) fn stop(mut self) -> &'a mut KnowledgeBase {
        self.stop.store(true, Ordering::Relaxed);
        self.stop_away.store(true, Ordering::Relaxed);
        for (_, away) in std::mem::take(&mut self.queue) {
            if let Some(rx) = away {
                let _ = self.kb.take_from_second_engine(rx);
            }
        }
        self.kb
    }
}

impl Iterator for Layouts<'_> {
    type Item = Candidate;

    fn next(&mut self) -> Option<Candidate> {
        let (factor, away) = self.queue.pop_front()?;
        // the first one stops the other thread's once it proves large,
        // and tells how the others are finished
        let finish = match std::mem::replace(&mut self.given, true) {
            false => Finish::First {
                halt: &self.stop_away,
                up_to: self.up_to,
                told: &self.corners_and_taper,
                free_over: self.free_over,
            },
            true => Finish::CornersAndTaper(self.corners_and_taper.get()),
        };
        let made = away
            .and_then(|rx| self.kb.take_from_second_engine(rx))
            // (stopped there, or finished otherwise than the first
            // tells: made here)
            .filter(|made| {
                !self.corners_and_taper.get() && !matches!(made, Err(why) if why == STOPPED)
            })
            .unwrap_or_else(|| {
                block_layout(
                    self.domain,
                    self.kb,
                    self.opts,
                    (self.size, factor, self.arc_step),
                    (self.max_free_share, self.blocks_of),
                    (&self.stop, finish),
                )
            });
        Some(match made {
            Ok(o) => Ok((
                format!("layout({factor})"),
                match self.corners_and_taper.get() {
                    false => format!("blocks of {factor} element sizes"),
                    true => format!(
                        "blocks of {factor} element sizes, finished by their corners and taper alone (the first layout of over bound(layout_sizes_free_over, {}) elements)",
                        self.free_over
                    ),
                },
                o,
            )),
            Err(why) => Err(format!("blocks of {factor} element sizes: {why}")),
        })
    }
}

/// The blocks of a layout of `factor` element sizes (arcs in steps of
/// `arc_step`), each meshed as a mapping element (or the free blocks by
/// the rules) by `blocks_of`, or why there are none (among the reasons:
/// more than `max_free_share` of them free, or `stop` set while it was
/// made); `finish` tells how it is finished.
fn block_layout(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    opts: &Options,
    (size, factor, arc_step): (f64, f64, f64),
    (max_free_share, blocks_of): (f64, BlocksOf),
    (stop, finish): (&AtomicBool, Finish),
) -> Result<Outcome, String> {
    let coarse = size * factor;
    let layout_opts = Options {
        size: Some(coarse),
        max_size: Some(coarse),
        layout: true,
        ..opts.clone()
    };
    let layout_domain = layout_for(domain, coarse, arc_step);
    let made = layout(&layout_domain, kb, &layout_opts, (stop, finish))?;
    if stop.load(Ordering::Relaxed) {
        return Err(STOPPED.into());
    }
    blocks_of(made, domain, size, kb, opts.trace, max_free_share)
}

/// The layout: `domain` meshed by the rules at the coarse size of
/// `opts`. A layout the rules cannot finish is of no use (its open loops
/// would be closed by triangles), so the run stops as soon as the rules
/// stop, or once it has taken `bound(layout_steps, 3)` times as many
/// steps as elements are expected, and 30 more (the rules struggling:
/// fallbacks taking elements back and splitting loops, long and to no
/// use), or `stop` is set (a layout no longer needed). `finish` tells
/// whether it is finished by its blocks' corners and taper alone.
fn layout(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    opts: &Options,
    (stop, finish): (&AtomicBool, Finish),
) -> Result<MeshResult, String> {
    let coarse = opts.size.unwrap_or(domain.size());
    let words = |e: Error| format!("the layout could not be made: {e}");
    let boundary = discretise_for_run(domain, opts.size).map_err(words)?;
    let prepared = prepare_run(domain, boundary, kb, opts).map_err(words)?;
    // (the expected count whole, then times the bound: the built-in 3
    // gives 3 steps an element exactly)
    let expected = (domain.area() / (coarse * coarse)).floor();
    let budget = 30 + (prepared.settings().host.layout_steps * expected) as usize;
    let mut run = Run::start(kb, prepared);
    let mut steps = 0;
    while run.step().map_err(words)? {
        if stop.load(Ordering::Relaxed) {
            return Err(STOPPED.into());
        }
        steps += 1;
        if steps > budget {
            return Err(format!(
                "the rules took over {budget} steps at size {coarse}"
            ));
        }
    }
    let stopped = format!("the rules stopped at size {coarse}");
    if run.stopped().is_some() {
        return Err(stopped);
    }
    let elements = run.mesher_ref().mesh().quads.len() as f64;
    let corners_and_taper = match finish {
        Finish::First {
            halt,
            up_to,
            told,
            free_over,
        } => {
            if elements > up_to {
                halt.store(true, Ordering::Relaxed);
            }
            told.set(elements > free_over);
            told.get()
        }
        Finish::CornersAndTaper(told) => told,
    };
    if corners_and_taper {
        run.finish_by_corners_and_taper();
    }
    // the finished mesh may still fail its check and go to the fallbacks
    let r = run.finish().map_err(words)?;
    if r.stats.triangle_fallbacks > 0 || r.stats.open_loops_closed > 0 {
        return Err(stopped);
    }
    Ok(r)
}

/// The domain the layout is made of: the same boundary at the coarse
/// size, uniform, each fixed count cut down to what the coarse size
/// gives (a block edge takes at least one element of the count).
fn layout_for(domain: &Domain, coarse: f64, arc_step: f64) -> Domain {
    let mut d = domain.clone();
    d.size = coarse;
    d.max_size = None;
    let originals: Vec<&crate::input::curves::Chain> = domain.chains().collect();
    let chains = std::iter::once(&mut d.outer)
        .chain(d.holes.iter_mut())
        .chain(d.lines.iter_mut());
    for (chain, original) in chains.zip(originals) {
        for e in &mut chain.edges {
            let natural = ((e.curve.length() / coarse).round() as usize)
                .max(crate::input::curves::min_arc_segments(&e.curve))
                .max(1);
            e.segments = match e.segments {
                Some(n) => Some(n.min(natural)),
                // an arc in short enough steps that a block's corner
                // measured along the arc is within a few degrees of the
                // layout's, measured along its chord (an even count
                // leaves the loop's parity to its straight edges)
                None if !matches!(e.curve, Curve::Line { .. }) => {
                    let steps = (e.curve.sweep() / arc_step).ceil() as usize;
                    Some(natural.max(steps).next_multiple_of(2))
                }
                None => None,
            };
        }
        // counts cut down can leave a loop whose every count is fixed
        // odd: one more on the edge the cut took most from
        let fixed: Option<Vec<usize>> = chain.edges.iter().map(|e| e.segments).collect();
        if fixed.is_some_and(|n| n.iter().sum::<usize>() % 2 == 1) {
            let cut = |i: usize| {
                original.edges[i].segments.unwrap_or(0) as i64
                    - chain.edges[i].segments.unwrap_or(0) as i64
            };
            if let Some(i) = (0..chain.edges.len())
                .filter(|&i| cut(i) > 0)
                .max_by_key(|&i| (cut(i), std::cmp::Reverse(i)))
            {
                chain.edges[i].segments = chain.edges[i].segments.map(|n| n + 1);
            }
        }
    }
    d
}
