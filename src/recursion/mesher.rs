//! The recursion strategy (Eq. 1): Ω_n = ⟨Q_i, Ω_{n−i}⟩. While the front
//! has loops, take the edge whose feature comes first in the KB's strategy
//! (the design queue), let the redesign rules correct its action, check
//! the element and commit it, and close four- and six-segment loops with
//! the final patterns. Where no rule gives a valid element anywhere, one
//! pass of the fallbacks works on the stuck loops and the recursion goes
//! on.

mod coarsen;

use crate::fallback::{chords, rings, slits, unmesh};
use crate::features::{
    angle_map, deg_round, front_facts, front_features, labels, FrontFeatures, Labels,
};
use crate::final_patterns;
use crate::front::{Front, Fv};
use crate::initial_design::{element, is_merged, QNode};
use crate::input::boundary::Discretised;
use crate::kb::Action;
use crate::kb::{KbError, KnowledgeBase};
use crate::mesh::{Mesh, NodeKind};
use crate::partial_mesh::{MeshStats, PartialMesh};
use crate::recursion::queue::{DesignQueue, QueuedDesign};
use crate::redesign::{redesign, Redesign};
use crate::report::trace::{By, TraceStep, Veto};
use crate::settings::Settings;
use crate::validity::{element_valid, Vetoed};

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

/// What a run needs before it starts: the boundary discretised, the
/// settings read from the KB once (the stages that follow the recursion
/// get them from the same read, in the pipeline).
#[derive(Debug, Clone)]
pub struct Prepared {
    disc: Discretised,
    size: f64,
    area: f64,
    set: Settings,
    /// The interior's size limit of a graded run (None: uniform).
    max_size: Option<f64>,
}

impl Prepared {
    /// A run over the discretised domain with boundary size `size` and
    /// area `area`, by the settings `set`.
    pub fn new(disc: Discretised, size: f64, area: f64, set: Settings) -> Prepared {
        Prepared {
            disc,
            size,
            area,
            set,
            max_size: None,
        }
    }

    /// The run graded from the boundary's sizes up to `max_size` (the
    /// size field, size_field.rs); uniform when it is None or no larger
    /// than the size.
    pub fn with_max_size(mut self, max_size: Option<f64>) -> Prepared {
        self.max_size = max_size.filter(|&m| grades(m, self.size));
        self
    }
    /// The settings the run goes by.
    pub fn settings(&self) -> &Settings {
        &self.set
    }
}

/// Whether a limit of `max_size` grades a run at `size` (a limit no
/// larger than the size leaves it uniform).
pub fn grades(max_size: f64, size: f64) -> bool {
    max_size > size * (1.0 + 1e-9)
}

/// Passes of the loop subdivision before the run gives up (and the last
/// resort, fallback/triangles.rs, meshes the domain): 100, and one more
/// for each 1,000 elements the domain needs. The public domains need at
/// most 19; a large domain gets stuck in more places, each needing a
/// pass; past that, a run is going round in circles.
const MAX_FALLBACK_PASSES: usize = 100;

/// What a finished recursion hands over.
#[derive(Clone)]
pub struct Outcome {
    /// The elements made.
    pub mesh: Mesh,
    /// The steps (kept when the trace is).
    pub trace: Vec<TraceStep>,
    /// The designs the validity check refused (kept with the trace).
    pub vetoes: Vec<Veto>,
    /// The counters.
    pub stats: MeshStats,
    /// The domain's area.
    pub area: f64,
    /// A graded run's size field and what the stages after the recursion
    /// do with it (None where they do nothing with it).
    pub grading: Option<Grading>,
}

/// What smoothing and the clean-up do with a graded run's size field.
#[derive(Clone)]
pub struct Grading {
    /// The field.
    pub field: crate::size_field::SizeField,
    /// `bound(graded_collapse_below, F)`: elements under F times the
    /// field's size are collapsed or merged (0: none; cleanup/coarsen.rs).
    pub collapse_below: f64,
    /// `bound(coarsest_edge, C)`: no collapse leaves an edge longer than C
    /// times the field's limit.
    pub coarsest_edge: f64,
    /// `bound(weighted_laplace, 1)`: Laplace weighted by the field
    /// (smoothing/laplace.rs).
    pub weighted_laplace: bool,
}

/// The meshing run.
pub struct Mesher<'k> {
    kb: &'k mut KnowledgeBase,
    pm: PartialMesh,
    queue: DesignQueue,
    set: Settings,
    fallback_passes: usize,
    started: bool,
    /// Stuck loops already searched for a whole closing (the same loop
    /// is often stuck again after a refused split).
    closings: final_patterns::closing::Memo,
}

impl<'k> Mesher<'k> {
    /// Starts a run on a discretised domain with boundary size `size`.
    #[cfg(test)]
    pub fn new(
        kb: &'k mut KnowledgeBase,
        disc: Discretised,
        size: f64,
        area: f64,
    ) -> Result<Mesher<'k>, MeshError> {
        let prepared = Prepared::new(disc, size, area, kb.settings()?);
        Ok(Mesher::start_from(kb, prepared))
    }

    /// Starts a run from what was prepared for it.
    pub fn start_from(kb: &'k mut KnowledgeBase, prepared: Prepared) -> Mesher<'k> {
        let Prepared {
            disc,
            size,
            area,
            set,
            max_size,
        } = prepared;
        let (mut pm, expected) = PartialMesh::new(disc, size, area);
        pm.host = set.host;
        pm.bounds = set.element;
        if let Some(m) = max_size {
            pm.grade(set.host.size_growth, m);
        }
        Mesher {
            kb,
            pm,
            queue: DesignQueue::with_capacity(expected),
            set,
            fallback_passes: 0,
            started: false,
            closings: Default::default(),
        }
    }

    /// The mesh built so far.
    pub fn mesh(&self) -> &Mesh {
        &self.pm.mesh
    }

    /// The inference trace so far.
    pub fn trace(&self) -> &[TraceStep] {
        &self.pm.trace
    }

    /// The counters so far.
    pub fn stats(&self) -> MeshStats {
        self.pm.stats
    }

    /// Whether the run is graded (it has a size field).
    pub fn is_graded(&self) -> bool {
        self.pm.size_field.is_some()
    }

    /// The settings in force, as read from the KB.
    pub fn settings(&self) -> &Settings {
        &self.set
    }

    /// Whether steps are recorded in the trace (they are always counted).
    pub fn set_record_trace(&mut self, on: bool) {
        self.pm.record_trace = on;
    }

    /// Checks every element placed for overlaps, and reports the
    /// fallbacks' passes on standard error (`Options::self_check`).
    pub fn set_self_check(&mut self, on: bool) {
        self.pm.debug_check = on;
    }

    /// Ends a run whose recursion is done: frees what only the recursion
    /// needs and hands over the mesh, the trace (steps and vetoes), the
    /// counters and the
    /// domain's area. The run is left empty.
    pub fn take_outcome(&mut self) -> Outcome {
        self.release_working_state();
        Outcome {
            mesh: std::mem::take(&mut self.pm.mesh),
            trace: std::mem::take(&mut self.pm.trace),
            vetoes: std::mem::take(&mut self.pm.vetoes),
            stats: self.pm.stats,
            area: self.pm.area,
            grading: {
                let host = &self.pm.host;
                let (below, weighted) = (host.graded_collapse_below, host.weighted_laplace >= 1.0);
                let field = self
                    .pm
                    .size_field
                    .take()
                    .filter(|_| below > 0.0 || weighted);
                field.map(|field| Grading {
                    field,
                    collapse_below: below,
                    coarsest_edge: host.coarsest_edge,
                    weighted_laplace: weighted,
                })
            },
        }
    }

    /// The boundary features of the current front, as the KB sees them.
    pub fn front_features(&mut self) -> Result<FrontFeatures, MeshError> {
        Ok(front_features(&self.pm, self.kb)?)
    }

    /// Runs the recursion to the end.
    #[cfg(test)]
    pub fn run(&mut self, progress: &mut dyn FnMut(usize)) -> Result<(), MeshError> {
        while self.step()? {
            progress(self.pm.mesh.quads.len());
        }
        Ok(())
    }

    /// True iff every loop of the remaining domain is closed.
    pub fn is_done(&self) -> bool {
        self.started && self.pm.front.live_loops().is_empty()
    }

    /// Every front occurrence, loop by loop.
    fn all_occurrences(&self) -> Vec<Fv> {
        let front = &self.pm.front;
        front
            .live_loops()
            .iter()
            .flat_map(|&l| front.loop_fvs(l))
            .collect()
    }

    /// Closes the loops that are final patterns already and classifies
    /// every front edge (the first step does it).
    fn start(&mut self) -> Result<(), MeshError> {
        self.started = true;
        self.queue.ensure_capacity(&self.pm.front);
        let all = self.all_occurrences();
        for l in self.pm.front.live_loops() {
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
        self.queue.prune_if_stale(&self.pm.front);
        while let Some(c) = self.queue.pop_live(&self.pm.front) {
            if self.pm.mesh.quads.len() > self.pm.max_elements {
                return Err(MeshError::Runaway(self.pm.mesh.quads.len()));
            }
            if self.try_design(c.key)? {
                return Ok(true);
            }
            self.queue.mark_failed(&c);
        }
        // No rule applies anywhere: close what the final patterns close,
        // split the rest.
        let loops = self.pm.front.live_loops();
        if loops.is_empty() {
            return Ok(false);
        }
        // Every pass of the fallback must make progress; a bounded number
        // of passes keeps a pathological loop from running forever.
        self.fallback_passes += 1;
        if self.pm.debug_check {
            let lens: Vec<usize> = loops.iter().map(|&l| self.pm.front.loop_len(l)).collect();
            eprintln!(
                "fallback pass {} quads {} loops {:?} stats {:?}",
                self.fallback_passes,
                self.pm.mesh.quads.len(),
                lens,
                self.pm.stats
            );
        }
        let mut changed = false;
        if self.fallback_passes <= MAX_FALLBACK_PASSES + self.pm.max_elements / 4000 {
            let mut open = Vec::new();
            for l in loops {
                let (zipped, rest) = slits::zip_slits(&mut self.pm, l, true);
                changed |= zipped;
                open.extend(rest);
            }
            for l in open {
                // a loop an earlier one's fallback took in (its elements
                // taken back) is gone: its old nodes are no loop to close
                if !self.pm.front.is_live(l) {
                    continue;
                }
                if self.pm.front.loop_len(l) <= 6 && self.try_close_loop(l)? {
                    changed = true;
                    continue;
                }
                if self.close_stuck_loop(l, true)? || self.fallback_split(l)? {
                    changed = true;
                }
            }
        }
        if !changed {
            // nothing else moves: a small loop closed whole with convex
            // elements is better than the open loops' fallback
            for l in self.pm.front.live_loops() {
                if !self.pm.front.is_live(l) {
                    continue;
                }
                changed |= self.close_stuck_loop(l, false)?;
            }
        }
        if !changed {
            let l = self.pm.front.live_loops()[0];
            let p = self.pm.pos(self.pm.front.loop_head(l));
            return Err(MeshError::Stuck {
                len: self.pm.front.loop_len(l),
                x: p.x,
                y: p.y,
            });
        }
        let touched = self.pm.front.take_touched();
        self.refresh(&touched)?;
        Ok(true)
    }

    /// Frees what only the recursion needs (the front, its index, the
    /// queue, the memo) once it is done: smoothing and writing a large
    /// mesh then run without it.
    pub fn release_working_state(&mut self) {
        self.pm.release_working_state();
        self.queue.release();
    }

    /// The open loops of the front, as node ids in loop order.
    pub fn front_node_loops(&self) -> Vec<Vec<u32>> {
        self.pm.map_front_loops(|f| self.pm.front.node(f))
    }

    /// The open loops of the front: each node id with the interior angle
    /// of the remaining domain there (whole degrees), in loop order.
    pub fn front_loop_angles(&self) -> Vec<Vec<(u32, f64)>> {
        self.pm.map_front_loops(|f| {
            (
                self.pm.front.node(f),
                deg_round(self.pm.front.angle(f, &self.pm.mesh.nodes)),
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
        self.queue.forget_answers();
    }

    /// Re-reads the settings and re-classifies every front edge: the
    /// knowledge base changed (a file was consulted mid-run).
    pub fn kb_changed(&mut self) -> Result<(), MeshError> {
        self.set = self.kb.settings()?;
        self.pm.host = self.set.host;
        self.pm.bounds = self.set.element;
        self.queue.clear();
        if !self.started {
            return Ok(());
        }
        let all = self.all_occurrences();
        self.refresh(&all)
    }

    /// States the current front to the KB as facts (kb/front.pl).
    pub fn publish_front(&mut self) -> Result<(), MeshError> {
        let facts = front_facts(&self.pm);
        self.kb.publish_front(&facts)?;
        Ok(())
    }

    /// Re-classifies the edges round the occurrences touched.
    fn refresh(&mut self, touched: &[Fv]) -> Result<(), MeshError> {
        Ok(self.queue.refresh(&self.pm, self.kb, &self.set, touched)?)
    }

    /// Tries the design for oriented edge `key`: redesign, check, commit.
    /// False when no valid element came of it.
    fn try_design(&mut self, key: u32) -> Result<bool, MeshError> {
        let Some(QueuedDesign {
            feature,
            action,
            angles,
            ratio,
        }) = self.queue.design_of(key)
        else {
            return Ok(false);
        };
        let lab = labels(&self.pm.front, key / 2, key % 2 == 1);
        match action {
            Action::T3 { .. } => {
                return self.try_coarsen(lab, &action, &feature, angle_map(&angles, ratio))
            }
            Action::R3 { .. } => {
                return self.try_refine(lab, &action, &feature, angle_map(&angles, ratio))
            }
            _ => {}
        }
        let Redesign {
            element: el,
            action,
            labels: lab,
            merges,
            fired,
        } = redesign(&mut self.pm, self.kb, self.set.redesign_rounds, action, lab)?;
        let Some(mut el) = el else {
            return Ok(false);
        };
        let edge_nodes = (self.pm.front.node(lab.n1), self.pm.front.node(lab.n2));
        // each refusal of the validity check is counted and traced
        let veto = |pm: &mut PartialMesh, why: Vetoed, outcome: &'static str| {
            pm.note_veto(|before_step| Veto {
                before_step,
                edge: [edge_nodes.0 as i64, edge_nodes.1 as i64],
                feature: feature.to_string(),
                action: action.to_string(),
                reason: why.reason(),
                outcome,
            })
        };
        if let Err(why) = element_valid(&mut self.pm, &el, lab.mirrored) {
            // the merge made it invalid: try without
            if merges.iter().any(|m| m.is_some()) {
                let Some(plain) = element(&self.pm.front, &self.pm.mesh.nodes, &action, &lab)
                else {
                    veto(&mut self.pm, why, "nothing");
                    return Ok(false);
                };
                if let Err(why) = element_valid(&mut self.pm, &plain, lab.mirrored) {
                    veto(&mut self.pm, why, "nothing");
                    return Ok(false);
                }
                veto(&mut self.pm, why, "placed_unmerged");
                el = plain;
            } else {
                veto(&mut self.pm, why, "nothing");
                return Ok(false);
            }
        }
        let ids = match self.commit_element(&el, &lab, &action)? {
            Ok(ids) => ids,
            Err(why) => {
                veto(&mut self.pm, why, "nothing");
                return Ok(false);
            }
        };
        self.pm.stats.designed += 1;
        self.pm.note_step(|step| TraceStep {
            step,
            edge: [edge_nodes.0 as i64, edge_nodes.1 as i64],
            angles: angle_map(&angles, ratio),
            feature: feature.to_string(),
            action: action.to_string(),
            by: By::Rule,
            redesign: fired,
            element: ids.iter().map(|&x| x as i64).collect(),
        });
        Ok(true)
    }

    /// Commits an element: new nodes, the front path replaced, pinches
    /// split. Undone (Err) if a loop would be left odd or degenerate.
    fn commit_element(
        &mut self,
        el: &[QNode; 4],
        lab: &Labels,
        action: &Action,
    ) -> Result<Result<[u32; 4], Vetoed>, MeshError> {
        let nodes_before = self.pm.mesh.nodes.len();
        let layer = self.pm.front.layer(lab.n1).max(self.pm.front.layer(lab.n2)) + 1;
        let id = |q: QNode, mesh: &mut Mesh, front: &Front| -> u32 {
            match q {
                QNode::Front(fv) | QNode::Merged(fv) => front.node(fv),
                QNode::New(p) => mesh.add_node(p, NodeKind::Interior),
            }
        };
        let n1 = id(el[0], &mut self.pm.mesh, &self.pm.front);
        let n2 = id(el[1], &mut self.pm.mesh, &self.pm.front);
        let n3 = id(el[2], &mut self.pm.mesh, &self.pm.front);
        let n4 = id(el[3], &mut self.pm.mesh, &self.pm.front);
        self.pm.front.begin();
        // the front path replaced, in loop order
        let (a, b, mid): (Fv, Fv, Vec<u32>) = match action {
            Action::A1 { .. } => (lab.n1, lab.n2, vec![n4, n3]),
            Action::A2 { .. } | Action::A4 => (lab.n4, lab.n2, vec![n3]),
            Action::A3 => (lab.n4, lab.n5, vec![]),
            _ => return Ok(Err(Vetoed::NotPlaceable)),
        };
        let (a, b, mid) = if lab.mirrored {
            (b, a, mid.into_iter().rev().collect())
        } else {
            (a, b, mid)
        };
        let made = self.pm.front.replace_path(a, b, &mid, layer);
        // split at merged corners
        let mut ok = true;
        let mut parted = false;
        for q in el.iter().skip(2) {
            let QNode::Merged(target) = *q else { continue };
            let node = self.pm.front.node(target);
            let Some(&occ) = made.iter().find(|&&m| self.pm.front.node(m) == node) else {
                ok = false;
                break;
            };
            if !self.pm.front.alive(target)
                || self.pm.front.loop_of(target) != self.pm.front.loop_of(occ)
                || self.pm.parts_a_line_seam(occ, target)
            {
                ok = false;
                break;
            }
            self.pm.front.split_pinch(occ, target);
            parted = true;
        }
        // a merge parts the loop into two regions side by side, never a
        // hole's ring on its own (a loop round no area: the rules would
        // place elements inside the hole, no front edge crossing them)
        if ok && parted {
            ok = self
                .pm
                .front
                .touched_loops()
                .iter()
                .all(|&l| self.pm.loop_area(l) > 0.0);
        }
        if ok {
            for l in self.pm.front.touched_loops() {
                let n = self.pm.front.loop_len(l);
                if n % 2 == 1 || n < 4 {
                    ok = false;
                }
            }
            // no spike: the remaining domain keeps a usable angle at every
            // occurrence the element touched
            ok = ok
                && self.pm.front.touched_live().iter().all(|&fv| {
                    self.pm.front.angle(fv, &self.pm.mesh.nodes) > self.pm.host.min_front_angle
                });
        }
        if !ok {
            self.pm.front.rollback();
            self.pm.mesh.nodes.truncate(nodes_before);
            self.pm.mesh.kinds.truncate(nodes_before);
            return Ok(Err(Vetoed::Loop));
        }
        self.pm.front.commit(&self.pm.mesh.nodes);
        let ids = if lab.mirrored {
            [n4, n3, n2, n1]
        } else {
            [n1, n2, n3, n4]
        };
        self.pm.push_quad(ids);
        if self.pm.debug_check {
            self.pm.debug_overlap(self.pm.mesh.quads.len() - 1);
        }
        if is_merged(el) {
            self.pm.stats.merges += 1;
        }
        self.after_change()?;
        Ok(Ok(ids))
    }

    /// After a committed change: close the loops it left with four or six
    /// segments, and re-classify the edges round everything it touched.
    fn after_change(&mut self) -> Result<(), MeshError> {
        let touched = self.pm.front.take_touched();
        let mut loops: Vec<u32> = touched
            .iter()
            .filter(|&&t| self.pm.front.alive(t))
            .map(|&t| self.pm.front.loop_of(t))
            .collect();
        loops.sort_unstable();
        loops.dedup();
        for l in loops {
            self.try_close_loop(l)?;
        }
        let mut all = touched;
        all.extend(self.pm.front.take_touched());
        self.refresh(&all)
    }

    /// Closes a loop of four or six segments with the final patterns.
    fn try_close_loop(&mut self, l: u32) -> Result<bool, MeshError> {
        Ok(final_patterns::try_close_loop(&mut self.pm, self.kb, l)?)
    }

    /// Closes a small loop the rules are stuck on whole (the KB's
    /// `closing_way/2`); with `strict`, only with every corner inside the
    /// window.
    fn close_stuck_loop(&mut self, l: u32, strict: bool) -> Result<bool, MeshError> {
        Ok(final_patterns::try_close_stuck_loop(
            &mut self.pm,
            self.kb,
            &mut self.closings,
            l,
            strict,
        )?)
    }

    /// One loop the rules are stuck on, to the fallbacks: a clear chord
    /// first, a tight one if there is none, then a ring whose sizes fit
    /// the elements round it; else the elements along it taken back to
    /// give it room; then any ring; last, any chord at all (bounded: it
    /// may not shrink the loop).
    fn fallback_split(&mut self, l: u32) -> Result<bool, MeshError> {
        if self.chord_split(l, 1.0, true)?
            || self.chord_split(l, 0.2, true)?
            || self.close_ring(l, true)
        {
            return Ok(true);
        }
        // taking back is costly (the rules mesh the region again): a small
        // budget, the open-loop fallback closes what it leaves
        if self.pm.stats.unmeshed < self.pm.max_elements / 32 && self.unmesh_layer(l)? {
            return Ok(true);
        }
        // a ring whose sizes do not fit is better than none
        if self.close_ring(l, false) {
            return Ok(true);
        }
        if self.pm.stats.fallback_splits < self.pm.max_elements / 4 {
            return self.chord_split(l, 0.05, false);
        }
        Ok(false)
    }

    fn chord_split(&mut self, l: u32, clearance: f64, strict: bool) -> Result<bool, MeshError> {
        if !chords::chord_split(&mut self.pm, l, clearance, strict) {
            return Ok(false);
        }
        self.after_change()?;
        Ok(true)
    }

    /// A ring in loop `l`; with `sizes_fit`, only one whose sizes fit.
    fn close_ring(&mut self, l: u32, sizes_fit: bool) -> bool {
        let jump = self.set.element.max_size_jump;
        let Some(inner) = rings::close_ring(&mut self.pm, l, jump, sizes_fit) else {
            return false;
        };
        self.queue.ensure_capacity(&self.pm.front);
        // the inner loop is convex: a final pattern may close it at once
        let _ = self.try_close_loop(inner);
        true
    }

    fn unmesh_layer(&mut self, l: u32) -> Result<bool, MeshError> {
        let Some(touched) = unmesh::unmesh_layer(&mut self.pm, l) else {
            return Ok(false);
        };
        self.queue.ensure_capacity(&self.pm.front);
        self.refresh(&touched)?;
        Ok(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

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
            thin_wall_edges: 0,
            near_line_edges: 0,
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
        let mut quads: Vec<[u32; 4]> = m.mesh().quads.clone();
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
        for t in m.trace() {
            eprintln!("{}", t.to_json_line());
        }
        r.unwrap();
        assert!(m.mesh().quads.len() >= 3);
    }
}
