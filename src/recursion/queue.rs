//! The design queue: every oriented edge of the live front with the
//! feature and action the KB gives its context, ordered by the feature's
//! place in the strategy, then by layer (the front nearest the boundary
//! first), then by age. A change of the front re-classifies the edges
//! round it; an answer is memoised by context, so the same context never
//! goes to the engine twice.

use rustc_hash::FxHashMap as HashMap;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::features::{deg_round, labels, Labels};
use crate::front::{Front, Fv};
use crate::kb::Action;
use crate::kb::{Context, Designed, KbError, KnowledgeBase};
use crate::partial_mesh::PartialMesh;
use crate::settings::Settings;

/// An edge in the queue, ordered by the strategy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Candidate {
    rank: u32,
    layer: u32,
    seq: u64,
    /// The oriented edge: occurrence * 2, + 1 when mirrored.
    pub key: u32,
    version: u32,
}

/// What the KB decided for an edge: its feature and action, and the
/// angles it saw (theta7, theta4, theta1, theta2, theta5) and the grading
/// ratio.
#[derive(Debug, Clone, Copy)]
struct Design {
    /// Index of the KB's answer in `DesignQueue::known`; NO_DESIGN: none.
    known: u32,
    /// The angles the context had (whole degrees, exact in f32).
    angles: [f32; 5],
    /// The grading ratio in tenths, times ten (exact in f32).
    ratio_tenths: f32,
}

const NO_DESIGN: Design = Design {
    known: u32::MAX,
    angles: [0.0; 5],
    ratio_tenths: 10.0,
};

const NOT_FAILED: u32 = u32::MAX;

/// A feature and action the KB gave a context, with the feature's place
/// in the strategy.
#[derive(Debug, Clone)]
struct KnownDesign {
    feature: std::rc::Rc<str>,
    action: Action,
    rank: u32,
}

/// The design of a queued edge: the feature, the action and the angles
/// the KB saw.
pub struct QueuedDesign {
    /// The feature.
    pub feature: std::rc::Rc<str>,
    /// Its action.
    pub action: Action,
    /// theta7, theta4, theta1, theta2, theta5 (deg).
    pub angles: [f64; 5],
    /// The grading ratio the KB saw (1 in a uniform run).
    pub ratio: f64,
}

/// The queue of designs.
pub struct DesignQueue {
    version: Vec<u32>,
    failed: Vec<u32>,
    /// The angle at each occurrence as this refresh measured it (the
    /// refresh's stamp, degrees): a refresh asks each up to ten times.
    angle_seen: Vec<(u64, f64)>,
    /// The refresh that last queued each occurrence's two edges.
    queued_in: Vec<u64>,
    refresh_stamp: u64,
    /// The KB's design for each oriented edge (by key) of the live front.
    design: Vec<Design>,
    /// The length of the queue when it was last pruned (all live then):
    /// it is pruned again once it holds twice that, most of it stale.
    queued_after_prune: usize,
    /// The KB's answers by context (its eight numbers, as the query has
    /// them): the same context gets the same answer, without building
    /// the query text again. Forgotten when the KB changes.
    design_memo: HashMap<[u64; 8], u32>,
    /// The answers the memo points to (None: the context shows no feature).
    known: Vec<Option<KnownDesign>>,
    heap: BinaryHeap<Reverse<Candidate>>,
    seq: u64,
}

impl DesignQueue {
    /// An empty queue sized for a run expected to make `expected` elements.
    pub fn with_capacity(expected: usize) -> DesignQueue {
        let keys = 2 * (expected + expected / 8);
        DesignQueue {
            version: Vec::with_capacity(keys),
            angle_seen: Vec::with_capacity(keys / 2),
            queued_in: Vec::with_capacity(keys / 2),
            refresh_stamp: 0,
            failed: Vec::with_capacity(keys),
            design: Vec::with_capacity(keys),
            queued_after_prune: 0,
            design_memo: HashMap::with_capacity_and_hasher(expected / 2, Default::default()),
            known: Vec::with_capacity(expected / 2),
            heap: BinaryHeap::with_capacity(1 << 14),
            seq: 0,
        }
    }

    /// Makes room for every oriented edge of the front.
    pub fn ensure_capacity(&mut self, front: &Front) {
        let n = front.capacity() * 2;
        if self.version.len() < n {
            self.version.resize(n, 0);
            self.failed.resize(n, NOT_FAILED);
            self.design.resize(n, NO_DESIGN);
            self.angle_seen.resize(n / 2, (0, 0.0));
            self.queued_in.resize(n / 2, 0);
        }
    }

    /// The angle at an occurrence (whole degrees), measured once a refresh.
    fn angle_this_refresh(&mut self, pm: &PartialMesh, fv: Fv) -> f64 {
        let seen = self.angle_seen[fv as usize];
        if seen.0 == self.refresh_stamp {
            return seen.1;
        }
        let a = deg_round(pm.front.angle(fv, &pm.mesh.nodes));
        self.angle_seen[fv as usize] = (self.refresh_stamp, a);
        a
    }

    /// The context of oriented edge `key` as the KB sees it, or None when
    /// the edge is not designed (its loop is closed by a final pattern or
    /// left to the fallback). Its earlier design is dropped either way.
    fn edge_context(&mut self, pm: &PartialMesh, key: u32) -> Option<(Labels, Context)> {
        let fv = key / 2;
        let mirrored = key % 2 == 1;
        self.version[key as usize] += 1;
        self.design[key as usize] = NO_DESIGN;
        let front = &pm.front;
        if !front.alive(fv)
            || front.loop_len(front.loop_of(fv)) <= 6
            || pm.fallback_only.contains(&front.loop_of(fv))
        {
            return None;
        }
        let lab = labels(front, fv, mirrored);
        let mut ctx = crate::features::context_given(pm, &lab, [0.0; 5]);
        for (i, n) in [lab.n7, lab.n4, lab.n1, lab.n2, lab.n5]
            .into_iter()
            .enumerate()
        {
            ctx.0[i] = self.angle_this_refresh(pm, n);
        }
        Some((lab, ctx))
    }

    /// Queues oriented edge `key` with the KB's answer `known` for its
    /// context (see `ask_new_contexts`), if the edge shows a feature.
    fn classify(&mut self, front: &Front, key: u32, lab: &Labels, ctx: &Context, known: u32) {
        let Some(k) = &self.known[known as usize] else {
            return;
        };
        let rank = k.rank;
        let layer = front.layer(lab.n1).max(front.layer(lab.n2));
        self.seq += 1;
        self.heap.push(Reverse(Candidate {
            rank,
            layer,
            seq: self.seq,
            key,
            version: self.version[key as usize],
        }));
        self.design[key as usize] = Design {
            known,
            angles: std::array::from_fn(|i| ctx.0[i] as f32),
            ratio_tenths: (ctx.0[7] * 10.0).round() as f32,
        };
    }

    /// Asks the KB the design of each context not asked before (in one
    /// batch, which a second engine may share) and memoises the answers;
    /// gives, for each context in order, its answer's index in `known`.
    fn ask_new_contexts<'a>(
        &mut self,
        kb: &mut KnowledgeBase,
        settings: &Settings,
        contexts: impl Iterator<Item = &'a Context>,
    ) -> Result<Vec<u32>, KbError> {
        let mut found = Vec::new();
        let mut new: Vec<(Context, u32)> = Vec::new();
        for ctx in contexts {
            let key = ctx.0.map(f64::to_bits);
            if let Some(&k) = self.design_memo.get(&key) {
                kb.stats.cached_queries += 1;
                found.push(k);
                continue;
            }
            // a slot for the answer, filled below
            let k = self.known.len() as u32;
            self.known.push(None);
            self.design_memo.insert(key, k);
            new.push((*ctx, k));
            found.push(k);
        }
        if new.is_empty() {
            return Ok(found);
        }
        let contexts: Vec<Context> = new.iter().map(|(c, _)| *c).collect();
        let answers = kb.designs(&contexts);
        for (&(_, k), answer) in new.iter().zip(answers) {
            match answer {
                Ok(d) => {
                    self.known[k as usize] = d.map(|Designed { feature, action }| KnownDesign {
                        rank: settings.rank(&feature),
                        feature: std::rc::Rc::from(feature),
                        action,
                    })
                }
                Err(e) => {
                    // unasked as far as the memo knows
                    for (c, _) in &new {
                        self.design_memo.remove(&c.0.map(f64::to_bits));
                    }
                    return Err(e);
                }
            }
        }
        Ok(found)
    }

    /// Re-classifies every oriented edge whose context involves a changed
    /// occurrence (three steps either way).
    pub fn refresh(
        &mut self,
        pm: &PartialMesh,
        kb: &mut KnowledgeBase,
        settings: &Settings,
        touched: &[Fv],
    ) -> Result<(), KbError> {
        self.ensure_capacity(&pm.front);
        self.refresh_stamp += 1;
        let front = &pm.front;
        let mut keys = Vec::new();
        for &t in touched {
            if !front.alive(t) {
                continue;
            }
            let mut a = t;
            for _ in 0..3 {
                a = front.prev(a);
            }
            let mut fv = a;
            for _ in 0..7 {
                // each edge once (the windows of neighbouring changes overlap)
                if self.queued_in[fv as usize] != self.refresh_stamp {
                    self.queued_in[fv as usize] = self.refresh_stamp;
                    keys.push(fv * 2);
                    keys.push(fv * 2 + 1);
                }
                fv = front.next(fv);
            }
        }
        keys.sort_unstable();
        let edges: Vec<(u32, Labels, Context)> = keys
            .into_iter()
            .filter_map(|k| self.edge_context(pm, k).map(|(lab, ctx)| (k, lab, ctx)))
            .collect();
        let known = self.ask_new_contexts(kb, settings, edges.iter().map(|e| &e.2))?;
        for ((k, lab, ctx), known) in edges.iter().zip(known) {
            self.classify(front, *k, lab, ctx, known);
        }
        Ok(())
    }

    /// Prunes the queue once it holds twice what it held after the last
    /// pruning, most of it stale (see `prune`).
    pub fn prune_if_stale(&mut self, front: &Front) {
        if self.heap.len() > 4096 && self.heap.len() > 2 * self.queued_after_prune {
            self.prune(front);
        }
    }

    /// The next queued edge still live (classified as it is now, not
    /// tried and failed, on the front), None when the queue is empty.
    pub fn pop_live(&mut self, front: &Front) -> Option<Candidate> {
        while let Some(Reverse(c)) = self.heap.pop() {
            if self.version[c.key as usize] != c.version || self.failed[c.key as usize] == c.version
            {
                continue;
            }
            if !front.alive(c.key / 2) {
                continue;
            }
            return Some(c);
        }
        None
    }

    /// Notes that the design of a candidate gave no valid element: it is
    /// not tried again until the front there changes.
    pub fn mark_failed(&mut self, c: &Candidate) {
        self.failed[c.key as usize] = c.version;
    }

    /// The design queued for oriented edge `key`, if any.
    pub fn design_of(&self, key: u32) -> Option<QueuedDesign> {
        let Design {
            known,
            angles,
            ratio_tenths,
        } = self.design[key as usize];
        let k = self.known.get(known as usize)?.as_ref()?;
        Some(QueuedDesign {
            feature: k.feature.clone(),
            action: k.action.clone(),
            angles: angles.map(f64::from),
            ratio: f64::from(ratio_tenths) / 10.0,
        })
    }

    /// Drops the queued edges that were classified again since, were
    /// tried and failed, or left the front: they would only be skipped.
    /// The order of the rest is kept, so the run is the same.
    fn prune(&mut self, front: &Front) {
        let (version, failed) = (&self.version, &self.failed);
        let live = |key: u32, v: u32| {
            version[key as usize] == v && failed[key as usize] != v && front.alive(key / 2)
        };
        self.heap.retain(|Reverse(c)| live(c.key, c.version));
        self.queued_after_prune = self.heap.len();
    }

    /// Forgets every queued edge and every memoised answer (the rules
    /// changed).
    pub fn clear(&mut self) {
        self.heap.clear();
        self.design_memo.clear();
    }

    /// Drops the memoised answers (the rules may have changed); edges
    /// already queued keep theirs until the front there changes.
    pub fn forget_answers(&mut self) {
        self.design_memo.clear();
    }

    /// Frees the queue once the recursion is done.
    pub fn release(&mut self) {
        self.heap = BinaryHeap::new();
        self.design = Vec::new();
        self.design_memo = HashMap::default();
        self.known = Vec::new();
        self.version = Vec::new();
        self.failed = Vec::new();
    }
}
