//! Where the recursion stops short or its mesh fails the check: the
//! segments its elements lost mended where they are, the loops left open
//! closed by triangles split into quads (the rules' elements kept), and
//! only where both fail the whole domain by the last resort.

use super::{finish_mesh, Error, MeshResult, Run, StoppedShort};
use crate::fallback::stuck_loops::{self, LoopsClosed};
use crate::fallback::triangles::mesh_by_triangles;
use crate::mesh::Mesh;
use crate::recursion::Outcome;
use crate::report::check;
use crate::report::trace::{By, TraceStep};

impl Run<'_> {
    /// Where the rules' elements lost boundary or line segments: the
    /// elements round them taken back and the region meshed by triangles
    /// (see `close_regions`), the segments in it (see
    /// `fallback::stuck_loops::reopen_lost_segment`), the rest of the
    /// rules' mesh kept. Each way the segments may lie in the region is
    /// tried (inside it, or bounding it either way round); None when no
    /// way gives a mesh that passes its check.
    pub(super) fn reopen_lost_segments(
        &mut self,
        lost: &[(u32, u32)],
        reason: &str,
        stopped_short: &StoppedShort,
    ) -> Result<Option<MeshResult>, Error> {
        let spacing = self.spacing(self.size);
        let outcome = self.mesher.take_outcome();
        self.close_regions(
            outcome,
            1,
            spacing,
            reason,
            stopped_short,
            |run, mesh, spacing| run.mend_lost(mesh, lost, spacing),
        )
    }

    /// The spacings of the open loops' triangles: bound(fallback_pairs)
    /// lengths of the loop's edges where they are paired,
    /// bound(fallback_spacing) times `size` where they are split.
    fn spacing(&self, size: f64) -> stuck_loops::Spacing {
        let host = self.mesher.settings().host;
        stuck_loops::Spacing {
            pairs: host.fallback_pairs,
            split: host.fallback_spacing * size,
        }
    }

    /// `mesh` with its `lost` segments mended (see `reopen_lost_segments`),
    /// checked; None when no way passes the check.
    fn mend_lost(
        &self,
        mesh: &Mesh,
        lost: &[(u32, u32)],
        spacing: stuck_loops::Spacing,
    ) -> Option<LoopsClosed> {
        let host = self.mesher.settings().host;
        // bound(fallback_reopen_rings, K): how far round the segments
        let rings = host.fallback_reopen_rings as usize;
        let holes = self.domain.holes.len() as u32;
        let back: Vec<(u32, u32)> = lost.iter().map(|&(a, b)| (b, a)).collect();
        let both: Vec<(u32, u32)> = lost.iter().chain(&back).copied().collect();
        let ways = [both, lost.to_vec(), back];
        ways.iter().find_map(|lost| {
            let closed =
                stuck_loops::reopen_lost_segment(mesh, lost, rings, &self.domain, spacing).ok()?;
            // checked before the rules' outcome is taken (once only)
            let area = closed.mesh.boundary_area(1 + holes);
            let fits = check::check_boundary_followed(&closed.mesh).is_ok()
                && check::check_mesh(&closed.mesh, area).is_ok();
            fits.then_some(closed)
        })
    }

    /// Where the recursion stopped short: the loops left open meshed by
    /// triangles (see `close_regions`), the rules'
    /// elements kept. None when that fails or its mesh fails the check:
    /// the last resort then meshes the whole domain.
    pub(super) fn close_open_loops(
        &mut self,
        reason: &str,
        stopped_short: &StoppedShort,
    ) -> Result<Option<MeshResult>, Error> {
        let loops = self.mesher.front_node_loops();
        if loops.is_empty() {
            // the rules closed every loop (their mesh failed its check)
            return Ok(None);
        }
        let size = stuck_loops::open_loop_size(
            self.mesher.mesh(),
            &loops,
            self.size,
            self.mesher.is_graded(),
        );
        let spacing = self.spacing(size);
        let outcome = self.mesher.take_outcome();
        let count = loops.len();
        self.close_regions(
            outcome,
            count,
            spacing,
            reason,
            stopped_short,
            |run, mesh, spacing| run.closed_loops(mesh, &loops, spacing),
        )
    }

    /// The rules' `outcome` with its open regions closed by `close` at
    /// `spacing` (`loops` of them): their triangles paired into quads,
    /// those left over split in three (fallback/pairs.rs). Where that
    /// closing cannot be made or its mesh fails the check, the regions are
    /// closed with every triangle split in three (no pairs, as with
    /// `bound(fallback_pairs, 0)`). None when neither closes them and
    /// passes the check.
    fn close_regions(
        &mut self,
        outcome: Outcome,
        loops: usize,
        spacing: stuck_loops::Spacing,
        reason: &str,
        stopped_short: &StoppedShort,
        close: impl Fn(&Self, &Mesh, stuck_loops::Spacing) -> Option<LoopsClosed>,
    ) -> Result<Option<MeshResult>, Error> {
        if spacing.pairs > 0.0 {
            if let Some(closed) = close(self, &outcome.mesh, spacing) {
                let paired =
                    self.finish_closed(outcome.clone(), closed, loops, reason, stopped_short)?;
                if paired.is_some() {
                    return Ok(paired);
                }
            }
        }
        let split = stuck_loops::Spacing {
            pairs: 0.0,
            ..spacing
        };
        match close(self, &outcome.mesh, split) {
            Some(closed) => self.finish_closed(outcome, closed, loops, reason, stopped_short),
            None => Ok(None),
        }
    }

    /// The open `loops` of the rules' `mesh` closed at `spacing`, the
    /// segments the closing lost mended; None where either fails.
    fn closed_loops(
        &self,
        mesh: &Mesh,
        loops: &[Vec<u32>],
        spacing: stuck_loops::Spacing,
    ) -> Option<LoopsClosed> {
        let host = self.mesher.settings().host;
        let closed = stuck_loops::close_open_loops(
            mesh,
            loops,
            &self.domain,
            spacing,
            Some(host.fallback_take_back * self.size * self.size),
        )
        .ok()?;
        // the closing may lose a segment in its turn: mended the same way
        let lost = check::lost_segments(&closed.mesh);
        if lost.is_empty() {
            return Some(closed);
        }
        let mended = self.mend_lost(&closed.mesh, &lost, spacing)?;
        Some(LoopsClosed {
            loop_elements: closed.loop_elements + mended.loop_elements,
            split_elements: closed.split_elements + mended.split_elements,
            taken_back: closed.taken_back + mended.taken_back,
            paired: closed.paired || mended.paired,
            mesh: mended.mesh,
        })
    }

    /// The rules' outcome with `closed`'s mesh (`loops` regions closed by
    /// triangles), traced and finished; None if it fails its check.
    fn finish_closed(
        &mut self,
        mut outcome: Outcome,
        closed: LoopsClosed,
        loops: usize,
        reason: &str,
        stopped_short: &StoppedShort,
    ) -> Result<Option<MeshResult>, Error> {
        let recursion = self.t0.elapsed().as_secs_f64() - self.prepare;
        let bounds = self.finish_bounds();
        let kb_after = self.mesher.kb().stats;
        outcome.mesh = closed.mesh;
        // the halved boundary segments' nodes are on the curves: the
        // area the elements must cover is the new boundary's
        outcome.area = outcome
            .mesh
            .boundary_area(1 + self.domain.holes.len() as u32);
        outcome.stats.loop_triangle_elements += closed.loop_elements;
        outcome.stats.open_loops_closed += loops;
        outcome.stats.chord_split_elements += closed.split_elements;
        outcome.stats.unmeshed += closed.taken_back;
        if self.opts.trace {
            outcome.trace.push(TraceStep {
                step: outcome.trace.len() + 1,
                edge: [-1, -1],
                angles: Default::default(),
                feature: "stuck".into(),
                action: format!(
                    "{}({}, {}, {})",
                    if closed.paired {
                        "loop_triangle_pairs"
                    } else {
                        "loop_triangle_split"
                    },
                    loops,
                    closed.loop_elements,
                    closed.split_elements
                ),
                by: By::Triangles,
                redesign: vec![reason.to_string()],
                element: vec![],
            });
        }
        match finish_mesh(outcome, &bounds, &self.opts, self.kb_before, kb_after) {
            Ok(mut r) => {
                r.phases.prepare = self.prepare;
                r.phases.recursion = recursion;
                r.stopped_short = Some(stopped_short.clone());
                Ok(Some(r))
            }
            Err(Error::Check(_)) => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// The whole domain meshed by triangles split into quads, the trace
    /// one step saying why.
    pub(super) fn last_resort(
        &mut self,
        reason: String,
        stopped_short: StoppedShort,
    ) -> Result<MeshResult, Error> {
        let mut mesh = mesh_by_triangles(&self.domain, &self.boundary, self.size)?;
        mesh.crack_lines = self.boundary.mesh.crack_lines.clone();
        let mut stats = self.mesher.stats();
        stats.triangle_fallbacks += 1;
        let trace = vec![TraceStep {
            step: 1,
            edge: [-1, -1],
            angles: Default::default(),
            feature: "stuck".into(),
            action: format!("triangle_split({})", mesh.quads.len()),
            by: By::Triangles,
            redesign: vec![reason],
            element: vec![],
        }];
        let kb_stats = self.mesher.kb().stats;
        let area = mesh.boundary_area(1 + self.domain.holes.len() as u32);
        // the rules' attempt and the fallback count as the recursion
        let recursion = self.t0.elapsed().as_secs_f64() - self.prepare;
        let bounds = self.finish_bounds();
        stats.triangle_elements = mesh.quads.len();
        // the rules' attempt is gone: its vetoes with it (still counted)
        let outcome = Outcome {
            mesh,
            trace,
            vetoes: Vec::new(),
            stats,
            area,
            grading: None,
        };
        let mut r = finish_mesh(outcome, &bounds, &self.opts, self.kb_before, kb_stats)?;
        r.phases.prepare = self.prepare;
        r.phases.recursion = recursion;
        r.stopped_short = Some(stopped_short);
        Ok(r)
    }
}
