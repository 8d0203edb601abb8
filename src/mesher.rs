//! The recursion strategy (Eq. 1): Ω_n = ⟨Q_i, Ω_{n−i}⟩. While the front
//! has loops, take the edge whose feature comes first in the KB's strategy,
//! ask the KB for its design action, place the element, let the redesign
//! rules correct it, commit it, and close four- and six-segment loops with
//! the final patterns. A loop on which no rule gives a valid element is
//! split by a chord (the classic loop subdivision) and the recursion goes on.

use glam::DVec2;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::boundary::Discretised;
use crate::design::{place, Action, Corner, Neighbourhood};
use crate::front::{Front, Fv};
use crate::geometry::{
    interior_angle, orient2d, point_segment_distances, polygon_area, quad_angles,
    segments_intersect, SegmentRelation,
};
use crate::kb::{term_text, KbError, KnowledgeBase};
use crate::mesh::{Mesh, NodeKind};
use crate::second_engine::Question;
use crate::trace::{Angles, TraceStep};
use scryer_prolog::Term;

/// Why meshing stopped short.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The knowledge base failed.
    #[error(transparent)]
    Kb(#[from] KbError),
    /// A loop could be neither meshed by the rules nor split.
    #[error("could not close a loop of {len} segments near ({x:.4}, {y:.4})")]
    Stuck {
        /// Its length.
        len: usize,
        /// Where.
        x: f64,
        /// Where.
        y: f64,
    },
    /// The element count ran far past the estimate (a runaway rule).
    #[error("meshing made {0} elements, far more than the domain needs: stopped (a rule that shrinks elements without end?)")]
    Runaway(usize),
}

/// Counters of one meshing run.
#[derive(Debug, Default, Clone, Copy)]
pub struct MeshStats {
    /// Elements made by design actions.
    pub designed: usize,
    /// Elements made by final patterns.
    pub closed: usize,
    /// Loop splits by the fallback.
    pub fallback_splits: usize,
    /// Redesign rules fired.
    pub redesigns: usize,
    /// Merges of a new corner with a front node (fronts meeting).
    pub merges: usize,
    /// Elements taken back to give a stuck loop room.
    pub unmeshed: usize,
    /// Runs the rules could not finish, meshed whole by the last resort
    /// (triangles split into quads, see triangle_fallback.rs).
    pub triangle_fallbacks: usize,
    /// Edges flipped by the clean-up (cleanup.rs).
    pub cleanup_flips: usize,
    /// Elements collapsed by the clean-up.
    pub cleanup_collapses: usize,
}

/// A front node as the feature recognition sees it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct NodeFeature {
    /// Node id.
    pub node: u32,
    /// Coordinates.
    pub x: f64,
    /// Coordinates.
    pub y: f64,
    /// Interior angle of the remaining domain (deg, rounded).
    pub angle: f64,
    /// Whether the KB calls it a concave point.
    pub concave: bool,
}

/// A front edge read from N1 to N2, with the KB's feature and action.
#[derive(Debug, Clone, serde::Serialize)]
pub struct EdgeFeature {
    /// N1.
    pub n1: u32,
    /// N2.
    pub n2: u32,
    /// The context term the KB was asked with.
    pub ctx: String,
    /// The feature, if any.
    pub feature: Option<String>,
    /// The action the KB would take.
    pub action: Option<String>,
}

/// The features of a front.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct FrontFeatures {
    /// Nodes in loop order.
    pub nodes: Vec<NodeFeature>,
    /// Edges, each in both readings.
    pub edges: Vec<EdgeFeature>,
}

/// What a run needs before it starts: the boundary discretised, the
/// settings read from the KB. Making it is what can fail; starting the
/// run from it cannot.
#[derive(Debug, Clone)]
pub struct Prepared {
    disc: Discretised,
    size: f64,
    area: f64,
    set: Settings,
}

impl Prepared {
    /// Reads the run's settings from the KB for the discretised domain
    /// with boundary size `size` and area `area`.
    pub fn new(
        kb: &mut KnowledgeBase,
        disc: Discretised,
        size: f64,
        area: f64,
    ) -> Result<Prepared, MeshError> {
        Ok(Prepared {
            disc,
            size,
            area,
            set: Settings::read(kb)?,
        })
    }
}

/// Settings read from the KB once per run.
#[derive(Debug, Clone)]
struct Settings {
    rank: HashMap<String, u32>,
    rounds: usize,
}

impl Settings {
    fn read(kb: &mut KnowledgeBase) -> Result<Settings, KbError> {
        let strategy = kb.strategy()?;
        let rank = strategy
            .iter()
            .enumerate()
            .map(|(i, f)| (f.clone(), i as u32))
            .collect();
        Ok(Settings {
            rank,
            rounds: kb.bound("redesign_rounds")?.max(0.0) as usize,
        })
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Candidate {
    rank: u32,
    layer: u32,
    seq: u64,
    key: u32,
    version: u32,
}

/// The labelled occurrences around an oriented edge.
#[derive(Debug, Clone, Copy)]
struct Labels {
    n7: Fv,
    n4: Fv,
    n1: Fv,
    n2: Fv,
    n5: Fv,
    mirrored: bool,
}

/// A corner of a candidate element.
#[derive(Debug, Clone, Copy, PartialEq)]
enum QNode {
    /// An occurrence on the front.
    Front(Fv),
    /// A new node.
    New(DVec2),
    /// A new corner replaced by this front occurrence.
    Merged(Fv),
}

/// What the KB decided for an edge: its feature and action, and the
/// angles it saw (theta7, theta4, theta1, theta2, theta5).
#[derive(Debug, Clone, Copy)]
struct Design {
    /// Index of the KB's answer in `Mesher::known`; NO_DESIGN: none.
    known: u32,
    /// The angles the context had (whole degrees, exact in f32).
    angles: [f32; 5],
}

const NO_DESIGN: Design = Design {
    known: u32::MAX,
    angles: [0.0; 5],
};

/// A feature and action the KB gave a context, with the feature's place
/// in the strategy.
#[derive(Debug, Clone)]
struct KnownDesign {
    feature: std::rc::Rc<str>,
    action: Action,
    rank: u32,
}

/// The trace's record of the angles a design saw.
fn angle_map(angles: &[f64; 5]) -> Angles {
    let names = ["theta7", "theta4", "theta1", "theta2", "theta5"];
    Angles::new(names.into_iter().zip(angles.iter().copied()).collect())
}

/// The meshing run.
pub struct Mesher<'k> {
    kb: &'k mut KnowledgeBase,
    /// The mesh built so far.
    pub mesh: Mesh,
    /// The remaining domain.
    pub front: Front,
    set: Settings,
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
    /// The KB's answers by context (its seven numbers, as the query has
    /// them): the same context gets the same answer, without building
    /// the query text again. Forgotten when the KB changes.
    design_memo: HashMap<[u64; 7], u32>,
    /// The answers the memo points to (None: the context shows no feature).
    known: Vec<Option<KnownDesign>>,
    heap: BinaryHeap<Reverse<Candidate>>,
    seq: u64,
    /// The inference trace (kept when `record_trace`).
    pub trace: Vec<TraceStep>,
    /// Whether steps are recorded in `trace` (they are always counted).
    pub record_trace: bool,
    /// Steps of the inference so far.
    steps: usize,
    /// Counters.
    pub stats: MeshStats,
    max_elements: usize,
    /// No element edge shorter than this: a third of the shortest input
    /// segment, so elements cannot shrink without end.
    min_edge: f64,
    scratch: Vec<Fv>,
    /// Whether a loop that a merge or a take-back leaves must enclose an
    /// area (a region on its left): with lines that end on a loop, a loop
    /// can pass a hole's ring and a merge part that ring off on its own,
    /// which no rule or fallback closes. Only for such domains, so that the
    /// others mesh as they did (on four public domains the guard changes
    /// the mesh, for better and worse).
    guard_loop_areas: bool,
    /// Check every new element against all others (FREEMESH_DEBUG_CHECK;
    /// quadratic, for debugging the rules).
    debug_check: bool,
    fallback_passes: usize,
    /// Loops the design rules gave up on: only the fallback works on them
    /// (and on the loops split from them), so the rules cannot remesh a
    /// region they already failed in.
    fallback_only: HashSet<u32>,
    started: bool,
    /// The element on the left of each directed element edge, kept as
    /// elements come and go once the fallback first asks it (zipping
    /// slits, taking back a layer); most runs never do.
    edge_owner: Option<HashMap<(u32, u32), u32>>,
    /// The area of the domain (what the finished mesh must cover).
    pub area: f64,
}

const NOT_FAILED: u32 = u32::MAX;

/// cos² 4°: a corner whose cosine squared is below this (with a margin)
/// is within [4, 176] degrees.
const COS_4_SQUARED: f64 = 0.995_134_034_370_785_1;
/// Passes of the loop subdivision before the run gives up (and the last
/// resort, triangle_fallback.rs, meshes the domain): 100, and one more
/// for each 1,000 elements the domain needs. The public domains need at
/// most 19; a large domain gets stuck in more places, each needing a
/// pass; past that, a run is going round in circles.
const MAX_FALLBACK_PASSES: usize = 100;
/// No element may leave the remaining domain a sharper corner than this
/// (deg): a spike cannot be meshed.
const MIN_FRONT_ANGLE: f64 = 12.0;

fn deg_round(x: f64) -> f64 {
    x.round()
}

impl<'k> Mesher<'k> {
    /// Starts a run on a discretised domain with boundary size `size`.
    pub fn new(
        kb: &'k mut KnowledgeBase,
        disc: Discretised,
        size: f64,
        area: f64,
    ) -> Result<Mesher<'k>, MeshError> {
        let prepared = Prepared::new(kb, disc, size, area)?;
        Ok(Mesher::start_from(kb, prepared))
    }

    /// Starts a run from what was prepared for it.
    pub fn start_from(kb: &'k mut KnowledgeBase, prepared: Prepared) -> Mesher<'k> {
        let Prepared {
            disc,
            size,
            area,
            set,
        } = prepared;
        let guard_loop_areas = disc.lines_meet;
        let mut front = Front::new(&disc.front_loops[0], size);
        for more in &disc.front_loops[1..] {
            front.add_loop(more, &[]);
        }
        front.index_all(&disc.mesh.nodes);
        let boundary_len: usize = disc.front_loops.iter().map(Vec::len).sum();
        let estimate = (area / (size * size)).max(1.0) + boundary_len as f64;
        let shortest = disc
            .mesh
            .boundary
            .iter()
            .map(|e| (disc.mesh.nodes[e.a as usize] - disc.mesh.nodes[e.b as usize]).length())
            .fold(size, f64::min);
        // the run's tables sized for the elements expected: growing them
        // step by step copies them over and over
        let expected = estimate.min(4e6) as usize;
        let mut mesh = disc.mesh;
        mesh.quads.reserve(expected + expected / 8);
        mesh.nodes.reserve(expected + expected / 8);
        front.reserve(expected + expected / 8);
        let keys = 2 * (expected + expected / 8);
        Mesher {
            kb,
            mesh,
            front,
            set,
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
            trace: Vec::new(),
            record_trace: true,
            steps: 0,
            stats: MeshStats::default(),
            max_elements: (estimate * 4.0) as usize + 1000,
            min_edge: shortest / 3.0,
            scratch: Vec::new(),
            debug_check: std::env::var_os("FREEMESH_DEBUG_CHECK").is_some(),
            guard_loop_areas,
            fallback_passes: 0,
            fallback_only: Default::default(),
            started: false,
            edge_owner: None,
            area,
        }
    }

    fn pos(&self, fv: Fv) -> DVec2 {
        self.mesh.nodes[self.front.node(fv) as usize]
    }

    fn along(&self, fv: Fv, mirrored: bool) -> Fv {
        if mirrored {
            self.front.prev(fv)
        } else {
            self.front.next(fv)
        }
    }

    fn back(&self, fv: Fv, mirrored: bool) -> Fv {
        self.along(fv, !mirrored)
    }

    fn labels(&self, fv: Fv, mirrored: bool) -> Labels {
        let (n1, n2) = if mirrored {
            (self.front.next(fv), fv)
        } else {
            (fv, self.front.next(fv))
        };
        let n4 = self.back(n1, mirrored);
        let n7 = self.back(n4, mirrored);
        let n5 = self.along(n2, mirrored);
        Labels {
            n7,
            n4,
            n1,
            n2,
            n5,
            mirrored,
        }
    }

    fn neighbourhood(&self, lab: &Labels) -> Neighbourhood {
        Neighbourhood {
            p7: self.pos(lab.n7),
            p4: self.pos(lab.n4),
            p1: self.pos(lab.n1),
            p2: self.pos(lab.n2),
            p5: self.pos(lab.n5),
            side: if lab.mirrored { -1.0 } else { 1.0 },
        }
    }

    /// The numbers of an edge's context as the KB sees them: the angles
    /// theta7, theta4, theta1, theta2, theta5 (whole degrees) and the
    /// neighbouring edges l5, l6 relative to N1N2 (two decimals).
    fn context_numbers(&self, lab: &Labels) -> [f64; 7] {
        let pos = &self.mesh.nodes;
        let t = |fv| deg_round(self.front.angle(fv, pos));
        self.context_numbers_given(lab, [t(lab.n7), t(lab.n4), t(lab.n1), t(lab.n2), t(lab.n5)])
    }

    /// `context_numbers` with the five angles given.
    fn context_numbers_given(&self, lab: &Labels, t: [f64; 5]) -> [f64; 7] {
        let l1 = (self.pos(lab.n2) - self.pos(lab.n1)).length().max(1e-300);
        let r = |x: f64| ((x / l1) * 100.0).round() / 100.0;
        [
            t[0],
            t[1],
            t[2],
            t[3],
            t[4],
            r((self.pos(lab.n1) - self.pos(lab.n4)).length()),
            r((self.pos(lab.n5) - self.pos(lab.n2)).length()),
        ]
    }

    /// The angle at an occurrence (whole degrees), measured once a refresh.
    fn angle_this_refresh(&mut self, fv: Fv) -> f64 {
        let seen = self.angle_seen[fv as usize];
        if seen.0 == self.refresh_stamp {
            return seen.1;
        }
        let a = deg_round(self.front.angle(fv, &self.mesh.nodes));
        self.angle_seen[fv as usize] = (self.refresh_stamp, a);
        a
    }

    /// The context term of an edge, as the KB sees it.
    fn context(&self, lab: &Labels) -> String {
        context_text(&self.context_numbers(lab))
    }

    fn ensure_capacity(&mut self) {
        let n = self.front.capacity() * 2;
        if self.version.len() < n {
            self.version.resize(n, 0);
            self.failed.resize(n, NOT_FAILED);
            self.design.resize(n, NO_DESIGN);
            self.angle_seen.resize(n / 2, (0, 0.0));
            self.queued_in.resize(n / 2, 0);
        }
    }

    /// The context of oriented edge `key` as the KB sees it, or None when
    /// the edge is not designed (its loop is closed by a final pattern or
    /// left to the fallback). Its earlier design is dropped either way.
    fn edge_context(&mut self, key: u32) -> Option<(Labels, [f64; 7])> {
        let fv = key / 2;
        let mirrored = key % 2 == 1;
        self.version[key as usize] += 1;
        self.drop_design(key);
        if !self.front.alive(fv)
            || self.front.loop_len(self.front.loop_of(fv)) <= 6
            || self.fallback_only.contains(&self.front.loop_of(fv))
        {
            return None;
        }
        let lab = self.labels(fv, mirrored);
        let mut nums = self.context_numbers_given(&lab, [0.0; 5]);
        for (i, n) in [lab.n7, lab.n4, lab.n1, lab.n2, lab.n5]
            .into_iter()
            .enumerate()
        {
            nums[i] = self.angle_this_refresh(n);
        }
        Some((lab, nums))
    }

    /// Queues oriented edge `key` with the KB's answer `known` for its
    /// context (see `ask_new_contexts`), if the edge shows a feature.
    fn classify(&mut self, key: u32, lab: &Labels, nums: &[f64; 7], known: u32) {
        let Some(k) = &self.known[known as usize] else {
            return;
        };
        let rank = k.rank;
        let layer = self.front.layer(lab.n1).max(self.front.layer(lab.n2));
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
            angles: std::array::from_fn(|i| nums[i] as f32),
        };
    }

    /// Forgets the design of oriented edge `key`.
    fn drop_design(&mut self, key: u32) {
        self.design[key as usize] = NO_DESIGN;
    }

    /// Asks the KB the design of each context not asked before (in one
    /// batch, which a second engine may share) and memoises the answers;
    /// gives, for each context in order, its answer's index in `known`.
    fn ask_new_contexts<'a>(
        &mut self,
        contexts: impl Iterator<Item = &'a [f64; 7]>,
    ) -> Result<Vec<u32>, MeshError> {
        let mut found = Vec::new();
        let mut new: Vec<([f64; 7], u32)> = Vec::new();
        for nums in contexts {
            let key = nums.map(f64::to_bits);
            if let Some(&k) = self.design_memo.get(&key) {
                self.kb.stats.cached_queries += 1;
                found.push(k);
                continue;
            }
            // a slot for the answer, filled below
            let k = self.known.len() as u32;
            self.known.push(None);
            self.design_memo.insert(key, k);
            new.push((*nums, k));
            found.push(k);
        }
        if new.is_empty() {
            return Ok(found);
        }
        // the context as text is for messages: written only for one
        let questions: Vec<Question> = new
            .iter()
            .map(|(n, _)| (design_question(n), String::new()))
            .collect();
        let answers = self.kb.ask_bounded_fresh_all(questions);
        for (&(nums, k), answer) in new.iter().zip(answers) {
            match self.known_design(&nums, answer) {
                Ok(d) => self.known[k as usize] = d,
                Err(e) => {
                    // unasked as far as the memo knows
                    for (n, _) in &new {
                        self.design_memo.remove(&n.map(f64::to_bits));
                    }
                    return Err(e);
                }
            }
        }
        Ok(found)
    }

    /// The KB's answer to a design question, read: feature and action (with
    /// the feature's rank), None when the edge shows no feature.
    fn known_design(
        &self,
        nums: &[f64; 7],
        answer: crate::second_engine::Answer,
    ) -> Result<Option<KnownDesign>, MeshError> {
        let ctx = || context_text(nums);
        let answer = answer.map_err(|e| match e {
            KbError::Rule { rule, why, .. } => KbError::Rule {
                rule,
                why,
                context: ctx(),
            },
            other => other,
        });
        let Some(ans) = answer? else {
            return Ok(None);
        };
        let (feature, action) = match &ans {
            Term::Compound(d, args) if d == "d" && args.len() == 2 => {
                (term_text(&args[0]), Action::from_term(&args[1]))
            }
            _ => (String::new(), None),
        };
        let Some(action) = action.filter(|a| a.is_sound()) else {
            return Err(KbError::Answer {
                query: format!("feature_action({feature}) on {}", ctx()),
                answer: term_text(&ans),
                expected: "d(Feature, Action) with a known, sound action".into(),
            }
            .into());
        };
        let rank = *self.set.rank.get(&feature).unwrap_or(&u32::MAX);
        Ok(Some(KnownDesign {
            feature: std::rc::Rc::from(feature),
            action,
            rank,
        }))
    }

    /// Counts a step of the inference and records it in the trace when
    /// the trace is kept (`make` gets the step's number).
    fn note_step(&mut self, make: impl FnOnce(usize) -> TraceStep) {
        self.steps += 1;
        if self.record_trace {
            let step = make(self.steps);
            self.trace.push(step);
        }
    }

    /// Re-classifies every oriented edge whose context involves a changed
    /// occurrence (three steps either way).
    fn refresh(&mut self, touched: &[Fv]) -> Result<(), MeshError> {
        self.ensure_capacity();
        self.refresh_stamp += 1;
        let mut keys = Vec::new();
        for &t in touched {
            if !self.front.alive(t) {
                continue;
            }
            let mut a = t;
            for _ in 0..3 {
                a = self.front.prev(a);
            }
            let mut fv = a;
            for _ in 0..7 {
                // each edge once (the windows of neighbouring changes overlap)
                if self.queued_in[fv as usize] != self.refresh_stamp {
                    self.queued_in[fv as usize] = self.refresh_stamp;
                    keys.push(fv * 2);
                    keys.push(fv * 2 + 1);
                }
                fv = self.front.next(fv);
            }
        }
        keys.sort_unstable();
        let edges: Vec<(u32, Labels, [f64; 7])> = keys
            .into_iter()
            .filter_map(|k| self.edge_context(k).map(|(lab, nums)| (k, lab, nums)))
            .collect();
        let known = self.ask_new_contexts(edges.iter().map(|e| &e.2))?;
        for ((k, lab, nums), known) in edges.iter().zip(known) {
            self.classify(*k, lab, nums, known);
        }
        Ok(())
    }

    /// The boundary features of the current front, as the KB sees them:
    /// every node with its angle and whether it is concave, every edge in
    /// both readings with its feature and action (None: no feature).
    pub fn front_features(&mut self) -> Result<FrontFeatures, MeshError> {
        let mut out = FrontFeatures::default();
        for l in self.front.live_loops() {
            for fv in self.front.loop_fvs(l) {
                let n = self.front.node(fv);
                let angle = deg_round(self.front.angle(fv, &self.mesh.nodes));
                let concave = !self
                    .kb
                    .run(&format!("angle_concave({}).", crate::kb::fmt_float(angle)))?
                    .is_empty();
                out.nodes.push(NodeFeature {
                    node: n,
                    x: self.mesh.nodes[n as usize].x,
                    y: self.mesh.nodes[n as usize].y,
                    angle,
                    concave,
                });
                for mirrored in [false, true] {
                    let lab = self.labels(fv, mirrored);
                    let ctx = self.context(&lab);
                    let q = format!("fm_design({ctx}, R).");
                    let ans = self.kb.ask_bounded(&q, &ctx)?;
                    let (feature, action) = match &ans {
                        Some(Term::Compound(_, args)) if args.len() == 2 => {
                            (Some(term_text(&args[0])), Some(term_text(&args[1])))
                        }
                        _ => (None, None),
                    };
                    out.edges.push(EdgeFeature {
                        n1: self.front.node(lab.n1),
                        n2: self.front.node(lab.n2),
                        ctx,
                        feature,
                        action,
                    });
                }
            }
        }
        Ok(out)
    }

    /// Runs the recursion to the end.
    pub fn run(&mut self, progress: &mut dyn FnMut(usize)) -> Result<(), MeshError> {
        while self.step()? {
            progress(self.mesh.quads.len());
        }
        Ok(())
    }

    /// True iff every loop of the remaining domain is closed.
    pub fn is_done(&self) -> bool {
        self.started && self.front.live_loops().is_empty()
    }

    /// Closes the loops that are final patterns already and classifies
    /// every front edge (the first step does it).
    fn start(&mut self) -> Result<(), MeshError> {
        self.started = true;
        self.ensure_capacity();
        let all: Vec<Fv> = self
            .front
            .live_loops()
            .iter()
            .flat_map(|&l| self.front.loop_fvs(l))
            .collect();
        for l in self.front.live_loops() {
            self.try_close_loop(l)?;
        }
        self.refresh(&all)
    }

    /// One step of the recursion: the next element the rules make (with
    /// the loops it lets the final patterns close), or, where no rule
    /// applies, one pass of the fallback over the loops. False when the
    /// domain is meshed.
    pub fn step(&mut self) -> Result<bool, MeshError> {
        if !self.started {
            self.start()?;
        }
        if self.heap.len() > 4096 && self.heap.len() > 2 * self.queued_after_prune {
            self.prune_queue();
        }
        while let Some(Reverse(c)) = self.heap.pop() {
            if self.version[c.key as usize] != c.version || self.failed[c.key as usize] == c.version
            {
                continue;
            }
            let fv = c.key / 2;
            if !self.front.alive(fv) {
                continue;
            }
            if self.mesh.quads.len() > self.max_elements {
                return Err(MeshError::Runaway(self.mesh.quads.len()));
            }
            if self.try_design(c.key)? {
                return Ok(true);
            }
            self.failed[c.key as usize] = c.version;
        }
        // No rule applies anywhere: close what the final patterns close,
        // split the rest.
        let loops = self.front.live_loops();
        if loops.is_empty() {
            return Ok(false);
        }
        // Every pass of the fallback must make progress; a bounded number
        // of passes keeps a pathological loop from running forever.
        self.fallback_passes += 1;
        if self.debug_check {
            let lens: Vec<usize> = loops.iter().map(|&l| self.front.loop_len(l)).collect();
            eprintln!(
                "fallback pass {} quads {} loops {:?} stats {:?}",
                self.fallback_passes,
                self.mesh.quads.len(),
                lens,
                self.stats
            );
        }
        let mut changed = false;
        if self.fallback_passes <= MAX_FALLBACK_PASSES + self.max_elements / 4000 {
            let mut open = Vec::new();
            for l in loops {
                let (zipped, rest) = self.zip_slits(l, true);
                changed |= zipped;
                open.extend(rest);
            }
            for l in open {
                if self.front.loop_len(l) <= 6 && self.try_close_loop(l)? {
                    changed = true;
                    continue;
                }
                if self.fallback_split(l)? {
                    changed = true;
                }
            }
        }
        if !changed {
            let l = self.front.live_loops()[0];
            let p = self.pos(self.front.loop_head(l));
            return Err(MeshError::Stuck {
                len: self.front.loop_len(l),
                x: p.x,
                y: p.y,
            });
        }
        let touched = self.front.take_touched();
        self.refresh(&touched)?;
        Ok(true)
    }

    /// Frees what only the recursion needs (the front, its index, the
    /// queue, the memo) once it is done: smoothing and writing a large
    /// mesh then run without it.
    pub fn release_working_state(&mut self) {
        self.front = Front::default();
        self.heap = BinaryHeap::new();
        self.design = Vec::new();
        self.design_memo = HashMap::default();
        self.known = Vec::new();
        self.edge_owner = None;
        self.version = Vec::new();
        self.failed = Vec::new();
    }

    /// Drops the queued edges that were classified again since, were
    /// tried and failed, or left the front: they would only be skipped.
    /// The order of the rest is kept, so the run is the same.
    fn prune_queue(&mut self) {
        let (version, failed, front) = (&self.version, &self.failed, &self.front);
        let live = |key: u32, v: u32| {
            version[key as usize] == v && failed[key as usize] != v && front.alive(key / 2)
        };
        self.heap.retain(|Reverse(c)| live(c.key, c.version));
        self.queued_after_prune = self.heap.len();
    }

    /// Each open loop of the front in loop order, as `each` reads its
    /// occurrences.
    fn map_front_loops<T>(&self, each: impl Fn(Fv) -> T) -> Vec<Vec<T>> {
        self.front
            .live_loops()
            .iter()
            .map(|&l| self.front.loop_fvs(l).into_iter().map(&each).collect())
            .collect()
    }

    /// The open loops of the front, as node ids in loop order.
    pub fn front_node_loops(&self) -> Vec<Vec<u32>> {
        self.map_front_loops(|f| self.front.node(f))
    }

    /// The open loops of the front: each node id with the interior angle
    /// of the remaining domain there (whole degrees), in loop order.
    pub fn front_loop_angles(&self) -> Vec<Vec<(u32, f64)>> {
        self.map_front_loops(|f| {
            (
                self.front.node(f),
                deg_round(self.front.angle(f, &self.mesh.nodes)),
            )
        })
    }

    /// The knowledge base the run asks.
    pub fn kb(&mut self) -> &mut KnowledgeBase {
        self.kb
    }

    /// Ends the run, handing back the knowledge base.
    pub fn into_kb(self) -> &'k mut KnowledgeBase {
        self.kb
    }

    /// Drops the KB's designs memoised by context (the rules may have
    /// changed); edges already queued keep theirs until the front there
    /// changes.
    pub fn forget_answers(&mut self) {
        self.design_memo.clear();
    }

    /// Re-reads the settings and re-classifies every front edge: the
    /// knowledge base changed (a file was consulted mid-run).
    pub fn kb_changed(&mut self) -> Result<(), MeshError> {
        self.set = Settings::read(self.kb)?;
        self.heap.clear();
        self.design_memo.clear();
        if !self.started {
            return Ok(());
        }
        let all: Vec<Fv> = self
            .front
            .live_loops()
            .iter()
            .flat_map(|&l| self.front.loop_fvs(l))
            .collect();
        self.refresh(&all)
    }

    /// States the current front to the KB as facts (kb/front.pl):
    /// node_xy/3, front_edge/2, node_angle/2 and edge_context/2 for
    /// both readings of every edge.
    pub fn publish_front(&mut self) -> Result<(), MeshError> {
        let f = crate::kb::fmt_float;
        let (mut nodes, mut edges, mut angles, mut ctxs) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut seen = HashSet::default();
        for l in self.front.live_loops() {
            for fv in self.front.loop_fvs(l) {
                let n = self.front.node(fv);
                let p = self.mesh.nodes[n as usize];
                if seen.insert(n) {
                    nodes.push(format!("xy({n}, {}, {})", f(p.x), f(p.y)));
                }
                let next = self.front.node(self.front.next(fv));
                edges.push(format!("e({n}, {next})"));
                let theta = deg_round(self.front.angle(fv, &self.mesh.nodes));
                angles.push(format!("a({n}, {})", f(theta)));
                for mirrored in [false, true] {
                    let lab = self.labels(fv, mirrored);
                    let ctx = self.context(&lab);
                    let (a, b) = (self.front.node(lab.n1), self.front.node(lab.n2));
                    ctxs.push(format!("c({a}-{b}, {ctx})"));
                }
            }
        }
        let q = format!(
            "fm_front_set([{}], [{}], [{}], [{}]).",
            nodes.join(","),
            edges.join(","),
            angles.join(","),
            ctxs.join(",")
        );
        self.kb.run(&q)?;
        Ok(())
    }

    /// The element of an action over the labelled edge: its corners
    /// N1 N2 N3 N4 (labelled order), or None if it cannot be placed.
    fn element(&self, action: &Action, lab: &Labels) -> Option<[QNode; 4]> {
        let nb = self.neighbourhood(lab);
        let (p3, p4) = place(action, &nb)?;
        let n3 = match (action, p3) {
            (Action::A3, _) => QNode::Front(lab.n5),
            (_, Some(p)) => QNode::New(p),
            _ => return None,
        };
        let n4 = match p4 {
            Some(p) => QNode::New(p),
            None => QNode::Front(lab.n4),
        };
        Some([QNode::Front(lab.n1), QNode::Front(lab.n2), n3, n4])
    }

    fn qpos(&self, q: QNode) -> DVec2 {
        match q {
            QNode::Front(fv) | QNode::Merged(fv) => self.pos(fv),
            QNode::New(p) => p,
        }
    }

    fn qnode_id(&self, q: QNode) -> Option<u32> {
        match q {
            QNode::Front(fv) | QNode::Merged(fv) => Some(self.front.node(fv)),
            QNode::New(_) => None,
        }
    }

    /// Counter-clockwise corner positions of an element.
    fn ccw(&self, q: &[QNode; 4], mirrored: bool) -> [DVec2; 4] {
        let p = q.map(|x| self.qpos(x));
        if mirrored {
            [p[3], p[2], p[1], p[0]]
        } else {
            p
        }
    }

    /// Hard validity: a convex element, no front edge crossing it, no front
    /// node inside it.
    fn element_valid(&mut self, q: &[QNode; 4], mirrored: bool) -> bool {
        let p = self.ccw(q, mirrored);
        let ids: Vec<Option<u32>> = {
            let v = q.map(|x| self.qnode_id(x));
            if mirrored {
                vec![v[3], v[2], v[1], v[0]]
            } else {
                v.to_vec()
            }
        };
        for i in 0..4 {
            if orient2d(p[i], p[(i + 1) % 4], p[(i + 2) % 4]) <= 0.0 {
                return false;
            }
            if let (Some(a), Some(b)) = (ids[i], ids[(i + 1) % 4]) {
                if a == b {
                    return false;
                }
            }
        }
        // every corner in [4, 176] degrees: told without trigonometry where
        // clearly so (|cos| below cos 4 with a margin), measured elsewhere
        let clearly_open = (0..4).all(|i| {
            let a = p[(i + 1) % 4] - p[i];
            let b = p[(i + 3) % 4] - p[i];
            let d = a.dot(b);
            d * d < COS_4_SQUARED * (1.0 - 1e-9) * a.length_squared() * b.length_squared()
        });
        if !clearly_open && quad_angles(p).iter().any(|&a| !(4.0..=176.0).contains(&a)) {
            return false;
        }
        // No sliver: every edge at least a quarter of the base edge, so a
        // rule that keeps shrinking an element cannot run away.
        let base = (self.qpos(q[1]) - self.qpos(q[0])).length();
        if (0..4).any(|i| (p[(i + 1) % 4] - p[i]).length() < (0.25 * base).max(self.min_edge)) {
            return false;
        }
        self.quad_clear(p, &ids, 0.15 * base)
    }

    /// True iff no front edge crosses the element `p` (counter-clockwise;
    /// `ids` the node ids of its corners, None for new ones), no front node
    /// lies inside it, and, with `gap` > 0, no new corner comes closer than
    /// `gap` to a front edge nor a front node to a new edge.
    fn quad_clear(&mut self, p: [DVec2; 4], ids: &[Option<u32>], gap: f64) -> bool {
        let pad = DVec2::splat(gap);
        let lo = p.iter().fold(DVec2::splat(f64::MAX), |a, &b| a.min(b)) - pad;
        let hi = p.iter().fold(DVec2::splat(f64::MIN), |a, &b| a.max(b)) + pad;
        let mut near = std::mem::take(&mut self.scratch);
        self.front.edges_near(lo, hi, &mut near);
        let is_quad_node = |n: u32| ids.contains(&Some(n));
        let mut ok = true;
        'edges: for &e in &near {
            let (na, nb) = (self.front.node(e), self.front.node(self.front.next(e)));
            let (a, b) = (self.mesh.nodes[na as usize], self.mesh.nodes[nb as usize]);
            // a front node strictly inside the element
            if !is_quad_node(na) && (0..4).all(|i| orient2d(p[i], p[(i + 1) % 4], a) > 0.0) {
                ok = false;
                break;
            }
            // no sliver left between the element and the front: a new
            // corner keeps off front edges, a front node off new edges
            if gap > 0.0 && !is_quad_node(na) && !is_quad_node(nb) {
                for i in 0..4 {
                    if ids[i].is_none() && crate::geometry::point_segment_distance(p[i], a, b) < gap
                    {
                        ok = false;
                        break 'edges;
                    }
                }
            }
            if gap > 0.0 && !is_quad_node(na) {
                for i in 0..4 {
                    let new_edge = ids[i].is_none() || ids[(i + 1) % 4].is_none();
                    if new_edge
                        && crate::geometry::point_segment_distance(a, p[i], p[(i + 1) % 4]) < gap
                    {
                        ok = false;
                        break 'edges;
                    }
                }
            }
            for i in 0..4 {
                let (qa, qb) = (ids[i], ids[(i + 1) % 4]);
                if let (Some(x), Some(y)) = (qa, qb) {
                    if (x == na && y == nb) || (x == nb && y == na) {
                        continue; // the front edge is this element edge
                    }
                }
                match segments_intersect(p[i], p[(i + 1) % 4], a, b) {
                    SegmentRelation::Disjoint => {}
                    SegmentRelation::Touch => {
                        // only at a node the two share
                        let shared = [qa, qb]
                            .iter()
                            .any(|q| q.is_some_and(|q| q == na || q == nb));
                        if !shared {
                            ok = false;
                            break 'edges;
                        }
                    }
                    _ => {
                        ok = false;
                        break 'edges;
                    }
                }
            }
        }
        self.scratch = near;
        ok
    }

    /// The relations the redesign rules judge, as Prolog terms, and the
    /// nearest front occurrence to each new corner (a merge target).
    fn relations(
        &mut self,
        q: &[QNode; 4],
        lab: &Labels,
        action: &Action,
    ) -> (Vec<String>, [Option<Fv>; 2]) {
        let pos: Vec<DVec2> = q.iter().map(|&x| self.qpos(x)).collect();
        let s = (0..4)
            .map(|i| (pos[(i + 1) % 4] - pos[i]).length())
            .sum::<f64>()
            / 4.0;
        let mut rel = Vec::new();
        let mut targets = [None, None];
        let ids: Vec<Option<u32>> = q.iter().map(|&x| self.qnode_id(x)).collect();
        let is_quad_node = |n: u32| ids.contains(&Some(n));
        let f = crate::kb::fmt_float;
        let r3 = |x: f64| (x * 1000.0).round() / 1000.0;
        // the element's corners in labelled order (unsigned: it is convex
        // when it matters), and what the remaining domain keeps
        let qa: [f64; 4] =
            std::array::from_fn(|i| corner_angle(pos[(i + 3) % 4], pos[i], pos[(i + 1) % 4]));
        let th = |fv: Fv| self.front.angle(fv, &self.mesh.nodes);
        let small = |rel: &mut Vec<String>, what: &str, name: &str, deg: f64| {
            if deg < 90.0 {
                rel.push(format!("{what}({name}, {})", f(deg_round(deg))));
            }
        };
        match action {
            Action::A1 { .. } => {
                small(&mut rel, "outer_corner", "n1", th(lab.n1) - qa[0]);
                small(&mut rel, "outer_corner", "n2", th(lab.n2) - qa[1]);
            }
            Action::A2 { .. } | Action::A4 => {
                small(&mut rel, "outer_corner", "n2", th(lab.n2) - qa[1]);
                small(&mut rel, "outer_corner", "n4", th(lab.n4) - qa[3]);
            }
            Action::A3 => {
                for (name, i, fv) in [("n3", 2usize, lab.n5), ("n4", 3, lab.n4)] {
                    if qa[i] < 90.0 || qa[i] > 120.0 {
                        rel.push(format!("inner_corner({name}, {})", f(deg_round(qa[i]))));
                    }
                    small(&mut rel, "remaining_corner", name, th(fv) - qa[i]);
                }
            }
            _ => {}
        }
        // new corners near front nodes and segments
        for (ci, &qi) in [2usize, 3].iter().enumerate() {
            let QNode::New(c) = q[qi] else { continue };
            let name = if qi == 2 { "n3" } else { "n4" };
            let r = s;
            let mut near = std::mem::take(&mut self.scratch);
            self.front
                .edges_near(c - DVec2::splat(r), c + DVec2::splat(r), &mut near);
            let mut best: Option<(f64, Fv)> = None;
            let mut worst_seg: Option<(f64, f64, f64)> = None;
            for &e in &near {
                let (na, nb) = (self.front.node(e), self.front.node(self.front.next(e)));
                if !is_quad_node(na) && self.front.loop_of(e) == self.front.loop_of(lab.n1) {
                    let d = (self.mesh.nodes[na as usize] - c).length();
                    if best.is_none_or(|b| d < b.0) {
                        best = Some((d, e));
                    }
                }
                if is_quad_node(na) || is_quad_node(nb) {
                    continue;
                }
                let (v, h) = point_segment_distances(
                    c,
                    self.mesh.nodes[na as usize],
                    self.mesh.nodes[nb as usize],
                );
                if worst_seg.is_none_or(|w| v + h < w.0 + w.1) {
                    worst_seg = Some((v, h, v + h));
                }
            }
            self.scratch = near;
            if let Some((d, e)) = best {
                if d < s {
                    rel.insert(
                        0,
                        format!("corner_node({name}, {}, {})", f(r3(d / s)), f(1.0)),
                    );
                    targets[ci] = Some(e);
                }
            }
            if let Some((v, h, _)) = worst_seg.filter(|w| w.0 < s && w.1 < s) {
                rel.push(format!(
                    "corner_segment({name}, {}, {}, {})",
                    f(r3(v / s)),
                    f(r3(h / s)),
                    f(1.0)
                ));
            }
        }
        // element edges near concave front nodes
        for (name, i, j) in [("e23", 1usize, 2usize), ("e34", 2, 3), ("e41", 3, 0)] {
            if !matches!(q[i], QNode::New(_)) && !matches!(q[j], QNode::New(_)) {
                continue;
            }
            let (a, b) = (pos[i], pos[j]);
            let lo = a.min(b) - DVec2::splat(s * 0.5);
            let hi = a.max(b) + DVec2::splat(s * 0.5);
            let mut near = std::mem::take(&mut self.scratch);
            self.front.edges_near(lo, hi, &mut near);
            let mut worst: Option<(f64, f64, f64)> = None;
            for &e in &near {
                let n = self.front.node(e);
                if is_quad_node(n) {
                    continue;
                }
                let t = self.front.angle(e, &self.mesh.nodes);
                if t <= 180.0 {
                    continue;
                }
                let (v, h) = point_segment_distances(self.mesh.nodes[n as usize], a, b);
                if worst.is_none_or(|w| v + h < w.0 + w.1) {
                    worst = Some((v, h, t));
                }
            }
            self.scratch = near;
            if let Some((v, h, t)) = worst.filter(|w| w.0 < s && w.1 < s) {
                rel.push(format!(
                    "edge_point({name}, {}, {}, {}, {})",
                    f(r3(v / s)),
                    f(r3(h / s)),
                    f(1.0),
                    f(deg_round(t))
                ));
            }
        }
        (rel, targets)
    }

    /// Tries the design for oriented edge `key`: place, redesign, check,
    /// commit. False when no valid element came of it.
    fn try_design(&mut self, key: u32) -> Result<bool, MeshError> {
        let Design { known, angles } = self.design[key as usize];
        let Some(Some(KnownDesign {
            feature,
            mut action,
            ..
        })) = self.known.get(known as usize).cloned()
        else {
            return Ok(false);
        };
        let angles = angles.map(f64::from);
        let mut lab = self.labels(key / 2, key % 2 == 1);
        let mut fired = Vec::new();
        let mut merges: [Option<Fv>; 2] = [None, None];
        let mut q = None;
        for round in 0..=self.set.rounds {
            let Some(el) = self.element(&action, &lab) else {
                break;
            };
            let (rel, targets) = self.relations(&el, &lab, &action);
            q = Some(el);
            if round == self.set.rounds || rel.is_empty() {
                break;
            }
            let ctx = self.context(&lab);
            let query = format!("fm_redesign({ctx}, {action}, [{}], R).", rel.join(", "));
            let Some(ans) = self.kb.ask_bounded(&query, &ctx)? else {
                break;
            };
            let Term::Compound(_, args) = &ans else { break };
            let rule = term_text(&args[0]);
            let Some(new) = Action::from_term(&args[1]).filter(|a| a.is_sound()) else {
                return Err(KbError::Answer {
                    query: format!("redesign rule {rule}"),
                    answer: term_text(&args[1]),
                    expected: "a known, sound action".into(),
                }
                .into());
            };
            fired.push(rule);
            self.stats.redesigns += 1;
            match new {
                Action::Shift(a) => {
                    lab = self.labels_shifted(&lab);
                    action = *a;
                    merges = [None, None];
                }
                Action::Merge(c, a) => {
                    let slot = if c == Corner::N3 { 0 } else { 1 };
                    if targets[slot].is_none() {
                        break;
                    }
                    merges[slot] = targets[slot];
                    action = *a;
                    // the merged corner is fixed now: judge the rest
                    let el = self
                        .element(&action, &lab)
                        .map(|e| self.apply_merges(e, &merges));
                    q = el;
                    break;
                }
                a => action = a,
            }
            q = None;
        }
        let Some(mut el) = q.or_else(|| self.element(&action, &lab)) else {
            return Ok(false);
        };
        el = self.apply_merges(el, &merges);
        if !self.element_valid(&el, lab.mirrored) {
            // the merge made it invalid: try without
            if merges.iter().any(|m| m.is_some()) {
                let Some(plain) = self.element(&action, &lab) else {
                    return Ok(false);
                };
                if !self.element_valid(&plain, lab.mirrored) {
                    return Ok(false);
                }
                el = plain;
            } else {
                return Ok(false);
            }
        }
        let edge_nodes = (self.front.node(lab.n1), self.front.node(lab.n2));
        let Some(ids) = self.commit_element(&el, &lab, &action)? else {
            return Ok(false);
        };
        self.stats.designed += 1;
        self.note_step(|step| TraceStep {
            step,
            edge: [edge_nodes.0 as i64, edge_nodes.1 as i64],
            angles: angle_map(&angles),
            feature: feature.to_string(),
            action: action.to_string(),
            redesign: fired,
            element: ids.iter().map(|&x| x as i64).collect(),
        });
        Ok(true)
    }

    /// Adds an element, noting it as the owner of its edges.
    fn push_quad(&mut self, q: [u32; 4]) {
        let qi = self.mesh.quads.len() as u32;
        if let Some(owner) = &mut self.edge_owner {
            own_edges(owner, q, qi);
        }
        self.mesh.quads.push(q);
    }

    /// Removes element `qi` (the last element takes its place).
    fn remove_quad(&mut self, qi: usize) -> [u32; 4] {
        let q = self.mesh.quads.swap_remove(qi);
        if let Some(owner) = &mut self.edge_owner {
            for i in 0..4 {
                let e = (q[i], q[(i + 1) % 4]);
                if owner.get(&e) == Some(&(qi as u32)) {
                    owner.remove(&e);
                }
            }
            if let Some(&moved) = self.mesh.quads.get(qi) {
                own_edges(owner, moved, qi as u32);
            }
        }
        q
    }

    /// The owners of the element edges, gathered the first time they are
    /// asked for and kept from then on.
    fn edge_owners(&mut self) -> &HashMap<(u32, u32), u32> {
        let quads = &self.mesh.quads;
        self.edge_owner.get_or_insert_with(|| {
            let mut owner =
                HashMap::with_capacity_and_hasher(4 * quads.len() + 1024, Default::default());
            for (qi, &q) in quads.iter().enumerate() {
                own_edges(&mut owner, q, qi as u32);
            }
            owner
        })
    }

    fn labels_shifted(&self, lab: &Labels) -> Labels {
        Labels {
            n7: lab.n4,
            n4: lab.n1,
            n1: lab.n2,
            n2: lab.n5,
            n5: self.along(lab.n5, lab.mirrored),
            mirrored: lab.mirrored,
        }
    }

    fn apply_merges(&self, mut el: [QNode; 4], merges: &[Option<Fv>; 2]) -> [QNode; 4] {
        for (slot, qi) in [(0usize, 2usize), (1, 3)] {
            if let (Some(t), QNode::New(_)) = (merges[slot], el[qi]) {
                el[qi] = QNode::Merged(t);
            }
        }
        el
    }

    /// Commits an element: new nodes, the front path replaced, pinches
    /// split. Undone (None) if a loop would be left odd or degenerate.
    fn commit_element(
        &mut self,
        el: &[QNode; 4],
        lab: &Labels,
        action: &Action,
    ) -> Result<Option<[u32; 4]>, MeshError> {
        let nodes_before = self.mesh.nodes.len();
        let layer = self.front.layer(lab.n1).max(self.front.layer(lab.n2)) + 1;
        let id = |q: QNode, mesh: &mut Mesh, front: &Front| -> u32 {
            match q {
                QNode::Front(fv) | QNode::Merged(fv) => front.node(fv),
                QNode::New(p) => mesh.add_node(p, NodeKind::Interior),
            }
        };
        let n1 = id(el[0], &mut self.mesh, &self.front);
        let n2 = id(el[1], &mut self.mesh, &self.front);
        let n3 = id(el[2], &mut self.mesh, &self.front);
        let n4 = id(el[3], &mut self.mesh, &self.front);
        self.front.begin();
        // the front path replaced, in loop order
        let (a, b, mid): (Fv, Fv, Vec<u32>) = match action {
            Action::A1 { .. } => (lab.n1, lab.n2, vec![n4, n3]),
            Action::A2 { .. } | Action::A4 => (lab.n4, lab.n2, vec![n3]),
            Action::A3 => (lab.n4, lab.n5, vec![]),
            _ => return Ok(None),
        };
        let (a, b, mid) = if lab.mirrored {
            (b, a, mid.into_iter().rev().collect())
        } else {
            (a, b, mid)
        };
        let made = self.front.replace_path(a, b, &mid, layer);
        // split at merged corners
        let mut ok = true;
        let mut parted = false;
        for q in el.iter().skip(2) {
            let QNode::Merged(target) = *q else { continue };
            let node = self.front.node(target);
            let Some(&occ) = made.iter().find(|&&m| self.front.node(m) == node) else {
                ok = false;
                break;
            };
            if !self.front.alive(target) || self.front.loop_of(target) != self.front.loop_of(occ) {
                ok = false;
                break;
            }
            self.front.split_pinch(occ, target);
            parted = true;
        }
        // a merge parts the loop into two regions side by side, never a
        // hole's ring on its own (a loop round no area); see
        // `guard_loop_areas`
        if ok && parted && self.guard_loop_areas {
            ok = self
                .touched_loops()
                .iter()
                .all(|&l| self.loop_area(l) > 0.0);
        }
        if ok {
            for l in self.touched_loops() {
                let n = self.front.loop_len(l);
                if n % 2 == 1 || n < 4 {
                    ok = false;
                }
            }
            // no spike: the remaining domain keeps a usable angle at every
            // occurrence the element touched
            ok = ok
                && self
                    .front
                    .touched_live()
                    .iter()
                    .all(|&fv| self.front.angle(fv, &self.mesh.nodes) > MIN_FRONT_ANGLE);
        }
        if !ok {
            self.front.rollback();
            self.mesh.nodes.truncate(nodes_before);
            self.mesh.kinds.truncate(nodes_before);
            return Ok(None);
        }
        self.front.commit(&self.mesh.nodes);
        let ids = if lab.mirrored {
            [n4, n3, n2, n1]
        } else {
            [n1, n2, n3, n4]
        };
        self.push_quad(ids);
        if self.debug_check {
            self.debug_overlap(self.mesh.quads.len() - 1);
        }
        if action_is_merge(el) {
            self.stats.merges += 1;
        }
        self.after_change()?;
        Ok(Some(ids))
    }

    /// After a committed change: close the loops it left with four or six
    /// segments, and re-classify the edges round everything it touched.
    fn after_change(&mut self) -> Result<(), MeshError> {
        let touched = self.front.take_touched();
        let mut loops: Vec<u32> = touched
            .iter()
            .filter(|&&t| self.front.alive(t))
            .map(|&t| self.front.loop_of(t))
            .collect();
        loops.sort_unstable();
        loops.dedup();
        for l in loops {
            self.try_close_loop(l)?;
        }
        let mut all = touched;
        all.extend(self.front.take_touched());
        self.refresh(&all)
    }

    /// The signed area a loop encloses (positive: a region on its left).
    fn loop_area(&self, l: u32) -> f64 {
        let pts: Vec<DVec2> = self
            .front
            .loop_fvs(l)
            .iter()
            .map(|&f| self.mesh.nodes[self.front.node(f) as usize])
            .collect();
        polygon_area(&pts)
    }

    fn touched_loops(&self) -> Vec<u32> {
        self.front.touched_loops()
    }

    fn debug_overlap(&self, qi: usize) {
        let p = self.mesh.quad_points(qi);
        for j in 0..qi {
            let r = self.mesh.quad_points(j);
            let inside =
                |x: DVec2, q: &[DVec2; 4]| (0..4).all(|i| orient2d(q[i], q[(i + 1) % 4], x) > 0.0);
            let mut bad = p.iter().any(|&x| inside(x, &r)) || r.iter().any(|&x| inside(x, &p));
            for a in 0..4 {
                for b in 0..4 {
                    if segments_intersect(p[a], p[(a + 1) % 4], r[b], r[(b + 1) % 4])
                        == SegmentRelation::Cross
                    {
                        bad = true;
                    }
                }
            }
            if bad {
                eprintln!(
                    "DEBUG: quad {qi} {:?} overlaps quad {j} {:?} at step {}",
                    self.mesh.quads[qi],
                    self.mesh.quads[j],
                    self.steps + 1
                );
            }
        }
    }

    /// Closes a loop of four or six segments with the final patterns.
    fn try_close_loop(&mut self, l: u32) -> Result<bool, MeshError> {
        let n = self.front.loop_len(l);
        if n != 4 && n != 6 {
            return Ok(false);
        }
        let fvs = self.front.loop_fvs(l);
        let ids: Vec<u32> = fvs.iter().map(|&f| self.front.node(f)).collect();
        let p: Vec<DVec2> = ids.iter().map(|&i| self.mesh.nodes[i as usize]).collect();
        let angles: Vec<f64> = fvs
            .iter()
            .map(|&f| deg_round(self.front.angle(f, &self.mesh.nodes)))
            .collect();
        let names = ["a1", "a2", "a3", "a4", "a5", "a6"];
        let angle_map = Angles::new(names.into_iter().zip(angles.iter().copied()).collect());
        if n == 4 {
            let q = [p[0], p[1], p[2], p[3]];
            if convex_ok(&q)
                && distinct(&ids)
                && self.quad_clear(q, &ids.iter().map(|&x| Some(x)).collect::<Vec<_>>(), 0.0)
            {
                let quad = [ids[0], ids[1], ids[2], ids[3]];
                self.close_with(l, vec![quad], &[], "final4", "quad".into(), angle_map);
                return Ok(true);
            }
            return Ok(false);
        }
        if !distinct(&ids) {
            return Ok(false);
        }
        let list = angles
            .iter()
            .map(|a| crate::kb::fmt_float(*a))
            .collect::<Vec<_>>()
            .join(", ");
        let q = format!("fm_patterns([{list}], R).");
        let Some(Term::Compound(_, mut ps)) = self.kb.ask_bounded(&q, &format!("[{list}]"))? else {
            return Ok(false);
        };
        let Some(Term::List(pats)) = ps.pop() else {
            return Ok(false);
        };
        for pat in pats {
            let Term::Compound(name, args) = &pat else {
                continue;
            };
            let Some(k) = args.first().and_then(crate::kb::term_number) else {
                continue;
            };
            let k = k as usize % 6;
            let at = |i: usize| (k + i) % 6; // the paper's N_{i+1}
            let (quads, new_pts): (Vec<[usize; 4]>, Vec<DVec2>) = match name.as_str() {
                "pattern3" => (
                    vec![[at(2), at(3), at(4), at(5)], [at(5), at(0), at(1), at(2)]],
                    vec![],
                ),
                "pattern1" | "pattern2" => {
                    let c = if name == "pattern1" {
                        (p[at(1)] + p[at(3)] + p[at(5)]) / 3.0
                    } else {
                        (3.0 * p[at(2)] + 3.0 * p[at(4)] + p[at(1)] + p[at(5)]) / 8.0
                    };
                    // 6 stands for the new node
                    let quads = vec![
                        [at(0), at(1), 6, at(5)],
                        [at(1), at(2), at(3), 6],
                        [at(3), at(4), at(5), 6],
                    ];
                    // where Eq. 5/6 gives a bad element, the builtin moves the
                    // node to the best place it finds in the loop
                    let c = best_centre(&p, &quads, c);
                    (quads, vec![c])
                }
                _ => continue,
            };
            let pt = |i: usize| if i < 6 { p[i] } else { new_pts[i - 6] };
            let clear = quads.iter().all(|qd| convex_ok(&qd.map(pt)))
                && quads.iter().all(|qd| {
                    let qids: Vec<Option<u32>> = qd
                        .iter()
                        .map(|&i| if i < 6 { Some(ids[i]) } else { None })
                        .collect();
                    self.quad_clear(qd.map(pt), &qids, 0.0)
                });
            if clear {
                let mut extra = Vec::new();
                for &c in &new_pts {
                    extra.push(c);
                }
                let base = self.mesh.nodes.len() as u32;
                let quads_ids: Vec<[u32; 4]> = quads
                    .iter()
                    .map(|qd| qd.map(|i| if i < 6 { ids[i] } else { base + (i - 6) as u32 }))
                    .collect();
                self.close_with(l, quads_ids, &extra, "final6", term_text(&pat), angle_map);
                return Ok(true);
            }
        }
        Ok(false)
    }

    fn close_with(
        &mut self,
        l: u32,
        quads: Vec<[u32; 4]>,
        new_nodes: &[DVec2],
        feature: &str,
        action: String,
        angles: Angles,
    ) {
        for &c in new_nodes {
            self.mesh.add_node(c, NodeKind::Interior);
        }
        let head = self.front.loop_head(l);
        let edge = [
            self.front.node(head),
            self.front.node(self.front.next(head)),
        ];
        self.front.begin();
        self.front.close_loop(l);
        self.front.commit(&self.mesh.nodes);
        for q in quads {
            self.push_quad(q);
            if self.debug_check {
                self.debug_overlap(self.mesh.quads.len() - 1);
            }
            self.stats.closed += 1;
            self.note_step(|step| TraceStep {
                step,
                edge: edge.map(|x| x as i64),
                angles: angles.clone(),
                feature: feature.into(),
                action: action.clone(),
                redesign: vec![],
                element: q.iter().map(|&x| x as i64).collect(),
            });
        }
    }

    /// The fallback: split a loop by the best chord between two of its
    /// nodes, subdivided so both parts are even (loop subdivision after
    /// Sluiter et al., the paper's refs. 11, 23, 27); a non-convex loop of
    /// four is closed by a ring of four elements round a fifth.
    fn fallback_split(&mut self, l: u32) -> Result<bool, MeshError> {
        // a clear chord first, a tight one if there is none, then the ring;
        // last, any chord at all (bounded: it may not shrink the loop)
        if self.chord_split(l, 1.0, true)? || self.chord_split(l, 0.2, true)? || self.close_ring(l)
        {
            return Ok(true);
        }
        // Give the loop room: take back the elements along it, so the
        // enlarged loop has a better shape for the next try.
        if self.stats.unmeshed < self.max_elements / 8 && self.unmesh_layer(l)? {
            return Ok(true);
        }
        if self.stats.fallback_splits < self.max_elements / 4 {
            return self.chord_split(l, 0.05, false);
        }
        Ok(false)
    }

    fn chord_split(&mut self, l: u32, clearance: f64, strict: bool) -> Result<bool, MeshError> {
        let n = self.front.loop_len(l);
        if n == 4 {
            return Ok(false);
        }
        let fvs = self.front.loop_fvs(l);
        let ids: Vec<u32> = fvs.iter().map(|&f| self.front.node(f)).collect();
        let p: Vec<DVec2> = ids.iter().map(|&i| self.mesh.nodes[i as usize]).collect();
        let theta: Vec<f64> = fvs
            .iter()
            .map(|&f| self.front.angle(f, &self.mesh.nodes))
            .collect();
        let elen: Vec<f64> = (0..n).map(|i| (p[(i + 1) % n] - p[i]).length()).collect();
        let mut cands: Vec<(f64, usize, usize, usize, f64)> = Vec::new();
        let stride = if n > 300 { n / 300 } else { 1 };
        for i in (0..n).step_by(stride) {
            for j in (i + 2..n).step_by(stride) {
                let gap = j - i;
                if gap > n - 2 || ids[i] == ids[j] {
                    continue;
                }
                let d = p[j] - p[i];
                let len = d.length();
                if len <= 0.0 {
                    continue;
                }
                // inside the wedges at both ends
                let min_split = if strict { 15.0 } else { 5.0 };
                let (Some(si), Some(sj)) = (
                    wedge_split(p[i], p[(i + 1) % n], d, theta[i]),
                    wedge_split(p[j], p[(j + 1) % n], -d, theta[j]),
                ) else {
                    continue;
                };
                if si < min_split || sj < min_split {
                    continue;
                }
                let h = (elen[i] + elen[(i + n - 1) % n] + elen[j] + elen[(j + n - 1) % n]) / 4.0;
                let t = len / h;
                let parity = gap % 2;
                let mut k = (t.round() as usize).max(1);
                if k % 2 != parity {
                    k = if (k as f64) < t || k == 1 {
                        k + 1
                    } else {
                        k - 1
                    };
                }
                if k == 0 {
                    k = 2;
                }
                if gap + k < 4 || n - gap + k < 4 {
                    if gap + k + 2 >= 4 && n - gap + k + 2 >= 4 {
                        k += 2;
                    } else {
                        continue;
                    }
                }
                // a part of four segments is one element: the chord must be
                // a single edge and the element convex
                let quad_part = |from: usize| -> bool {
                    convex_ok(&[
                        p[from % n],
                        p[(from + 1) % n],
                        p[(from + 2) % n],
                        p[(from + 3) % n],
                    ])
                };
                if strict
                    && ((gap + k == 4 && (k != 1 || !quad_part(i)))
                        || (n - gap + k == 4 && (k != 1 || !quad_part(j)))
                        || k >= gap
                        || k >= n - gap)
                {
                    continue;
                }
                // no chord segment far below the run's minimum edge
                if len / (k as f64) < self.min_edge / 4.0 {
                    continue;
                }
                let score = si.min(sj).min(90.0) - 40.0 * ((len / k as f64) / h).ln().abs()
                    + 10.0 * (gap.min(n - gap) as f64 / n as f64);
                cands.push((score, i, j, k, h));
            }
        }
        // the best chord that is clear: sort first, test clearance after
        cands.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut best = None;
        for &(score, i, j, k, h) in &cands {
            if self.chord_clear(p[i], p[j], ids[i], ids[j], h * clearance) {
                best = Some((score, i, j, k));
                break;
            }
        }
        let Some((_, i, j, k)) = best else {
            return Ok(false);
        };
        let (pi, pj) = (p[i], p[j]);
        let inner: Vec<u32> = (1..k)
            .map(|s| {
                self.mesh
                    .add_node(pi + (pj - pi) * (s as f64 / k as f64), NodeKind::Interior)
            })
            .collect();
        let mut path: Vec<u32> = inner.clone();
        path.push(ids[j]);
        path.extend(inner.iter().rev());
        path.push(ids[i]);
        self.front.begin();
        let layer = self.front.layer(fvs[i]).max(self.front.layer(fvs[j]));
        let made = self
            .front
            .replace_path(fvs[i], self.front.next(fvs[i]), &path, layer);
        let parts = self.front.split_pinch(made[k - 1], fvs[j]);
        if self.fallback_only.contains(&l) {
            self.fallback_only.extend(parts);
        }
        self.front.commit(&self.mesh.nodes);
        self.stats.fallback_splits += 1;
        let angles = Angles::new(vec![
            ("theta1", deg_round(theta[i])),
            ("theta2", deg_round(theta[j])),
        ]);
        self.note_step(|step| TraceStep {
            step,
            edge: [ids[i] as i64, ids[j] as i64],
            angles,
            feature: "stuck".into(),
            action: format!("split({k})"),
            redesign: vec![],
            element: vec![],
        });
        self.after_change()?;
        Ok(true)
    }

    /// Whether the front edge a-b, met both ways, bounds nothing: elements
    /// on both sides (fronts that met), or none on either side and not an
    /// input line (left where elements were taken back). An inner line of
    /// the input, with no element yet, bounds the domain on both sides.
    fn slit_is_inside(&self, owner: &HashMap<(u32, u32), u32>, a: u32, b: u32) -> bool {
        let owned = (owner.contains_key(&(a, b)), owner.contains_key(&(b, a)));
        let input = |n: u32| self.mesh.kinds[n as usize] == NodeKind::Boundary;
        match owned {
            (true, true) => true,
            (false, false) => !(input(a) && input(b)),
            _ => false,
        }
    }

    /// Zips the slits of loop `l`: a front edge met both ways, a->b->a,
    /// that bounds nothing (see `slit_is_inside`); with `pinches` (a loop
    /// the fallback works on, not one just grown by taking elements back)
    /// also parts it where it touches itself (see `pinch_to_split`).
    /// Returns whether it changed anything, and the loops left.
    fn zip_slits(&mut self, l: u32, pinches: bool) -> (bool, Vec<u32>) {
        let mut zipped = false;
        let mut open = vec![l];
        let mut done = Vec::new();
        self.edge_owners();
        while let Some(l) = open.pop() {
            // a slit (an edge there and back bounding nothing), or else a
            // node the loop passes twice
            let slit = self.edge_owner.as_ref().and_then(|owner| {
                self.front.loop_fvs(l).into_iter().find_map(|fv| {
                    let (p, n) = (self.front.prev(fv), self.front.next(fv));
                    let (a, b) = (self.front.node(p), self.front.node(fv));
                    (p != n && self.front.node(n) == a && self.slit_is_inside(owner, a, b))
                        .then_some((p, n))
                })
            });
            match slit.or_else(|| pinches.then(|| self.pinch_to_split(l)).flatten()) {
                Some((u, v)) => {
                    self.front.begin();
                    let rest = self.front.split_pinch(u, v);
                    self.front.commit(&self.mesh.nodes);
                    zipped = true;
                    open.extend(rest);
                }
                None => done.push(l),
            }
        }
        (zipped, done)
    }

    /// Two occurrences of one node on loop `l` (the loop touches itself
    /// there) that part it into two loops of even length, each bounding
    /// its own region (positive area, neither inside the other): the loop
    /// is two loops already.
    fn pinch_to_split(&self, l: u32) -> Option<(Fv, Fv)> {
        let fvs = self.front.loop_fvs(l);
        let at = |i: usize| self.mesh.nodes[self.front.node(fvs[i % fvs.len()]) as usize];
        let index: HashMap<Fv, usize> = fvs.iter().enumerate().map(|(i, &f)| (f, i)).collect();
        for (i, &u) in fvs.iter().enumerate() {
            for v in self.front.occurrences(self.front.node(u)) {
                let Some(&j) = index.get(&v) else { continue };
                if j <= i || (j - i) % 2 == 1 {
                    continue;
                }
                let first: Vec<DVec2> = (i..j).map(at).collect();
                let second: Vec<DVec2> = (j..i + fvs.len()).map(at).collect();
                // side by side, not one inside the other
                let apart = |a: &[DVec2], b: &[DVec2]| {
                    a[1..]
                        .iter()
                        .all(|&x| !crate::geometry::point_in_polygon(x, b))
                };
                if polygon_area(&first) > 0.0
                    && polygon_area(&second) > 0.0
                    && apart(&first, &second)
                    && apart(&second, &first)
                {
                    return Some((u, v));
                }
            }
        }
        None
    }

    /// Takes back every element that shares an edge with loop `l`; the
    /// loop grows round them. False if there is none.
    fn unmesh_layer(&mut self, l: u32) -> Result<bool, MeshError> {
        let edges: Vec<(u32, u32)> = self
            .front
            .loop_fvs(l)
            .iter()
            .map(|&fv| (self.front.node(self.front.next(fv)), self.front.node(fv)))
            .collect();
        let owner = self.edge_owners();
        let mut victims: Vec<usize> = edges
            .iter()
            .filter_map(|e| owner.get(e).map(|&q| q as usize))
            .collect();
        victims.sort_unstable();
        victims.dedup();
        if victims.is_empty() {
            return Ok(false);
        }
        let mut removed = Vec::new();
        for &qi in &victims {
            let q = self.mesh.quads[qi];
            // a front edge a->b that the element runs b->a
            let mut found = None;
            for i in 0..4 {
                let (b, a) = (q[i], q[(i + 1) % 4]);
                if let Some(fa) = self
                    .front
                    .occurrences(a)
                    .find(|&fa| self.front.node(self.front.next(fa)) == b)
                {
                    found = Some((i, fa));
                    break;
                }
            }
            let Some((i, fa)) = found else { continue };
            let fb = self.front.next(fa);
            let x = q[(i + 2) % 4];
            let y = q[(i + 3) % 4];
            self.front.begin();
            let layer = self.front.layer(fa);
            let made = self.front.replace_path(fa, fb, &[x, y], layer);
            for m in made {
                let node = self.front.node(m);
                let others: Vec<Fv> = self.front.occurrences(node).filter(|&o| o != m).collect();
                for o in others {
                    if !self.front.alive(o) || !self.front.alive(m) {
                        continue;
                    }
                    if self.front.loop_of(o) == self.front.loop_of(m) {
                        self.front.split_pinch(m, o);
                    } else {
                        self.front.join_pinch(m, o);
                    }
                }
            }
            if self.front.touched_loops().iter().any(|&t| {
                self.front.loop_len(t) % 2 == 1
                    || (self.guard_loop_areas && self.loop_area(t) <= 0.0)
            }) {
                self.front.rollback();
                continue;
            }
            self.front.commit(&self.mesh.nodes);
            removed.push(qi);
        }
        if removed.is_empty() {
            return Ok(false);
        }
        removed.sort_unstable();
        for &qi in removed.iter().rev() {
            let q = self.remove_quad(qi);
            self.stats.unmeshed += 1;
            self.note_step(|step| TraceStep {
                step,
                edge: [q[0] as i64, q[1] as i64],
                angles: Angles::default(),
                feature: "stuck".into(),
                action: "unmesh".into(),
                redesign: vec![],
                element: q.iter().map(|&x| x as i64).collect(),
            });
        }
        // edges between two elements taken back bound nothing now
        for t in self.front.touched_loops() {
            self.zip_slits(t, false);
        }
        let touched = self.front.take_touched();
        for &t in &touched {
            if self.front.alive(t) {
                self.fallback_only.insert(self.front.loop_of(t));
            }
        }
        self.ensure_capacity();
        self.refresh(&touched)?;
        Ok(true)
    }

    /// True iff the chord crosses no front edge and passes no front node
    /// closer than a fifth of the local size.
    fn chord_clear(&mut self, a: DVec2, b: DVec2, na: u32, nb: u32, h: f64) -> bool {
        let mut near = std::mem::take(&mut self.scratch);
        let pad = DVec2::splat(h * 0.25);
        self.front
            .edges_near(a.min(b) - pad, a.max(b) + pad, &mut near);
        let mut ok = true;
        for &e in &near {
            let (x, y) = (self.front.node(e), self.front.node(self.front.next(e)));
            let (px, py) = (self.mesh.nodes[x as usize], self.mesh.nodes[y as usize]);
            if x != na && x != nb && crate::geometry::point_segment_distance(px, a, b) < 0.2 * h {
                ok = false;
                break;
            }
            let rel = segments_intersect(a, b, px, py);
            if x == na || x == nb || y == na || y == nb {
                // sharing an end is fine; lying along the chord is not
                if rel == SegmentRelation::Overlap || (x == na && y == nb) || (x == nb && y == na) {
                    ok = false;
                    break;
                }
                continue;
            }
            if rel != SegmentRelation::Disjoint {
                ok = false;
                break;
            }
        }
        self.scratch = near;
        ok
    }

    /// The last resort for a loop the rules and chords cannot mesh: a
    /// ring of n elements round a new convex loop of n nodes on a circle
    /// about a centre that sees every node of the loop. The inner loop is
    /// convex whatever the loop's shape, so the final patterns or a chord
    /// close it.
    fn close_ring(&mut self, l: u32) -> bool {
        let fvs = self.front.loop_fvs(l);
        let n = fvs.len();
        let ids: Vec<u32> = fvs.iter().map(|&f| self.front.node(f)).collect();
        if !distinct(&ids) || n > 12 {
            return false;
        }
        let p: Vec<DVec2> = ids.iter().map(|&i| self.mesh.nodes[i as usize]).collect();
        // The centre and radius: the best of a grid over the loop's box,
        // judged by the smallest angle of the ring's elements.
        // a quarter of the rules' minimum: a ring may be finer than the
        // elements round it, but rings in rings cannot shrink for ever
        // (a loop of four gets a ring round a convex four, closed at once:
        // no nesting, so its ring may go finer)
        let min_edge = self.min_edge / if n == 4 { 32.0 } else { 4.0 };
        // the ring's elements, judged by their smallest angle; None too
        // once it is sure to be no better than `floor` (the best so far)
        let judge = |inner: Vec<DVec2>, floor: f64| -> Option<(f64, Vec<DVec2>)> {
            if (0..n).any(|i| orient2d(inner[i], inner[(i + 1) % n], inner[(i + 2) % n]) <= 0.0) {
                return None;
            }
            // no edge below the run's minimum: rings inside rings would
            // otherwise shrink without end
            if (0..n).any(|i| {
                (inner[(i + 1) % n] - inner[i]).length() < min_edge
                    || (inner[i] - p[i]).length() < min_edge
            }) {
                return None;
            }
            let mut worst = f64::MAX;
            for i in 0..n {
                let q = [p[i], p[(i + 1) % n], inner[(i + 1) % n], inner[i]];
                let angles = convex_angles(&q)?;
                worst = worst.min(
                    angles
                        .iter()
                        .map(|&x| x.min(180.0 - x))
                        .fold(f64::MAX, f64::min),
                );
                if worst <= floor {
                    return None;
                }
            }
            Some((worst, inner))
        };
        // inner nodes on a circle round a centre c
        let ring = |c: DVec2, t: f64, floor: f64| -> Option<(f64, Vec<DVec2>)> {
            let rmax = p.iter().map(|&x| (x - c).length()).fold(f64::MAX, f64::min);
            if rmax <= 0.0 {
                return None;
            }
            judge(
                p.iter()
                    .map(|&x| c + (x - c).normalize_or_zero() * rmax * t)
                    .collect(),
                floor,
            )
        };
        // or each inner node in from its loop node along the bisector of
        // the loop's corner there: a loop with a reflex or flat corner
        // (no centre sees it well) gets its ring this way
        let bisector_ring = |t: f64, floor: f64| -> Option<(f64, Vec<DVec2>)> {
            judge(
                (0..n)
                    .map(|i| {
                        let (prev, v, next) = (p[(i + n - 1) % n], p[i], p[(i + 1) % n]);
                        let half = crate::geometry::interior_angle(prev, v, next) / 2.0;
                        let dir = DVec2::from_angle(half).rotate((next - v).normalize_or_zero());
                        v + dir * t * (next - v).length().min((prev - v).length())
                    })
                    .collect(),
                floor,
            )
        };
        let lo = p.iter().fold(DVec2::splat(f64::MAX), |a, &b| a.min(b));
        let hi = p.iter().fold(DVec2::splat(f64::MIN), |a, &b| a.max(b));
        let mut best: Option<(f64, Vec<DVec2>)> = None;
        let floor =
            |best: &Option<(f64, Vec<DVec2>)>| best.as_ref().map_or(f64::NEG_INFINITY, |b| b.0);
        let steps = 48;
        for ix in 1..steps {
            for iy in 1..steps {
                let c =
                    lo + (hi - lo) * DVec2::new(ix as f64 / steps as f64, iy as f64 / steps as f64);
                for t in [0.25, 0.5, 0.75] {
                    if let Some(r) = ring(c, t, floor(&best)) {
                        best = Some(r);
                    }
                }
            }
        }
        for t in [0.2, 0.35, 0.5] {
            if let Some(r) = bisector_ring(t, floor(&best)) {
                best = Some(r);
            }
        }
        if let Some((_, inner)) = best {
            for i in 0..n {
                let q = [p[i], p[(i + 1) % n], inner[(i + 1) % n], inner[i]];
                if !self.quad_clear(q, &[Some(ids[i]), Some(ids[(i + 1) % n]), None, None], 0.0) {
                    return false;
                }
            }
            let base = self.mesh.nodes.len() as u32;
            for &x in &inner {
                self.mesh.add_node(x, NodeKind::Interior);
            }
            let qs: Vec<[u32; 4]> = (0..n)
                .map(|i| {
                    [
                        ids[i],
                        ids[(i + 1) % n],
                        base + ((i + 1) % n) as u32,
                        base + i as u32,
                    ]
                })
                .collect();
            let inner_ids: Vec<u32> = (0..n as u32).map(|i| base + i).collect();
            self.stats.fallback_splits += 1;
            let layer = self.front.layer(fvs[0]) + 1;
            self.close_with(l, qs, &[], "stuck", "ring".into(), Angles::default());
            self.front.begin();
            let nl = self.front.add_loop(&inner_ids, &vec![layer; n]);
            self.front.commit(&self.mesh.nodes);
            self.ensure_capacity();
            let _ = self.try_close_loop(nl);
            return true;
        }
        false
    }
}

/// The position of an inner node (index 6 in `quads`) that makes the
/// elements convex with the largest smallest angle: `first` if it is good,
/// else the best of a grid over the loop's bounding box.
fn best_centre(p: &[DVec2], quads: &[[usize; 4]], first: DVec2) -> DVec2 {
    // the smallest angle of the elements, or a value at most `floor` as
    // soon as one shows the place no better than that
    let score = |c: DVec2, floor: f64| -> f64 {
        let pt = |i: usize| if i < p.len() { p[i] } else { c };
        let mut worst = f64::MAX;
        for q in quads {
            let qp = q.map(pt);
            let s = if (0..4).any(|i| orient2d(qp[i], qp[(i + 1) % 4], qp[(i + 2) % 4]) <= 0.0) {
                -1.0
            } else {
                let a = quad_angles(qp);
                a.iter().map(|&x| x.min(180.0 - x)).fold(f64::MAX, f64::min)
            };
            worst = worst.min(s);
            if worst <= floor {
                break;
            }
        }
        worst
    };
    let mut best = (score(first, f64::NEG_INFINITY), first);
    if best.0 >= 30.0 {
        return first;
    }
    let lo = p.iter().fold(DVec2::splat(f64::MAX), |a, &b| a.min(b));
    let hi = p.iter().fold(DVec2::splat(f64::MIN), |a, &b| a.max(b));
    let steps = 24;
    for ix in 1..steps {
        for iy in 1..steps {
            let c = lo + (hi - lo) * DVec2::new(ix as f64 / steps as f64, iy as f64 / steps as f64);
            let sc = score(c, best.0);
            if sc > best.0 {
                best = (sc, c);
            }
        }
    }
    best.1
}

/// The unsigned angle at `v` between the directions to `a` and `b` (deg).
/// The context term of the KB's design question.
/// The design question for a context, in as few tokens as the engine's
/// reader allows (reading the query text is half the engine's cost): the
/// five whole-degree angles packed in base 1000, the two length ratios in
/// hundredths; `fm_design_packed/4` of the loader unpacks them into the
/// same `ctx/7` term. Contexts it cannot pack exactly are asked as text.
fn design_question(n: &[f64; 7]) -> String {
    let angles_packable = n[..5]
        .iter()
        .all(|&a| a.fract() == 0.0 && (0.0..1000.0).contains(&a));
    let hundredths = |x: f64| {
        let h = (x * 100.0).round();
        (h.abs() < 1e15 && h / 100.0 == x).then_some(h as i64)
    };
    match (angles_packable, hundredths(n[5]), hundredths(n[6])) {
        (true, Some(h5), Some(h6)) => {
            let packed = n[..5].iter().fold(0i64, |p, &a| p * 1000 + a as i64);
            format!("fm_design_packed({packed},{h5},{h6},R).")
        }
        _ => format!("fm_design({}, R).", context_text(n)),
    }
}

fn context_text(n: &[f64; 7]) -> String {
    format!(
        "ctx({}, {}, {}, {}, {}, {}, {})",
        n[0],
        n[1],
        n[2],
        n[3],
        n[4],
        crate::kb::fmt_float(n[5]),
        crate::kb::fmt_float(n[6])
    )
}

fn corner_angle(a: DVec2, v: DVec2, b: DVec2) -> f64 {
    let (x, y) = (a - v, b - v);
    x.perp_dot(y).abs().atan2(x.dot(y)).to_degrees()
}

fn action_is_merge(el: &[QNode; 4]) -> bool {
    el.iter().any(|q| matches!(q, QNode::Merged(_)))
}

fn distinct(ids: &[u32]) -> bool {
    let mut v = ids.to_vec();
    v.sort_unstable();
    v.windows(2).all(|w| w[0] != w[1])
}

/// Notes element `qi` (corners `q`) as the owner of its directed edges.
fn own_edges(owner: &mut HashMap<(u32, u32), u32>, q: [u32; 4], qi: u32) {
    for i in 0..4 {
        owner.insert((q[i], q[(i + 1) % 4]), qi);
    }
}

fn convex_ok(q: &[DVec2; 4]) -> bool {
    convex_angles(q).is_some()
}

/// The corner angles of `q` if it passes `convex_ok`.
fn convex_angles(q: &[DVec2; 4]) -> Option<[f64; 4]> {
    if !(0..4).all(|i| orient2d(q[i], q[(i + 1) % 4], q[(i + 2) % 4]) > 0.0) {
        return None;
    }
    let a = quad_angles(*q);
    a.iter().all(|&a| (1.0..=179.0).contains(&a)).then_some(a)
}

/// How a chord leaving `v` (whose next loop node is `next`) in direction
/// `d` splits the interior angle
/// `theta` (deg) at `v`: the smaller part in degrees, or None if it leaves
/// the domain.
fn wedge_split(v: DVec2, next: DVec2, d: DVec2, theta: f64) -> Option<f64> {
    // a: the ccw turn from the direction to next round to d
    let a = interior_angle(v + d, v, next).to_degrees();
    if a <= 1.0 || a >= theta - 1.0 {
        return None;
    }
    Some(a.min(theta - a))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run on one loop through boundary nodes at `pts`.
    fn mesher_on_loop<'k>(
        kb: &'k mut KnowledgeBase,
        pts: &[(f64, f64)],
        front_loop: Vec<u32>,
        size: f64,
        area: f64,
    ) -> Mesher<'k> {
        let mut mesh = Mesh::default();
        for &(x, y) in pts {
            mesh.add_node(DVec2::new(x, y), NodeKind::Boundary);
        }
        let disc = Discretised {
            mesh,
            front_loops: vec![front_loop],
            cuts: vec![],
            lines_meet: false,
        };
        Mesher::new(kb, disc, size, area).unwrap()
    }

    #[test]
    fn a_loop_touching_itself_is_parted_at_the_node() {
        // two unit squares meeting at the corner (1, 1): one loop through
        // that node twice; each square is one element
        let pts = [
            (0., 0.),
            (1., 0.),
            (1., 1.),
            (2., 1.),
            (2., 2.),
            (1., 2.),
            (0., 1.),
        ];
        let mut kb = KnowledgeBase::builtin().unwrap();
        let mut m = mesher_on_loop(&mut kb, &pts, vec![0, 1, 2, 3, 4, 5, 2, 6], 1.0, 2.0);
        m.run(&mut |_| {}).unwrap();
        let mut quads: Vec<[u32; 4]> = m.mesh.quads.clone();
        for q in &mut quads {
            let k = (0..4).min_by_key(|&i| q[i]).unwrap();
            q.rotate_left(k);
        }
        quads.sort();
        assert_eq!(quads, vec![[0, 1, 2, 6], [2, 3, 4, 5]]);
    }

    #[test]
    fn z_shaped_six_loop_splits_by_a_chord() {
        let pts = [
            (540.02, 802.49),
            (511.33, 801.06),
            (488.95, 838.29),
            (533.6, 838.29),
            (511.23, 875.53),
            (535.24, 875.53),
        ]
        .map(|(x, y)| (x, -y));
        let mut kb = KnowledgeBase::builtin().unwrap();
        let mut m = mesher_on_loop(&mut kb, &pts, vec![0, 1, 2, 3, 4, 5], 30.0, 1000.0);
        let r = m.run(&mut |_| {});
        for t in &m.trace {
            eprintln!("{}", t.to_json_line());
        }
        r.unwrap();
        assert!(m.mesh.quads.len() >= 3);
    }
}
