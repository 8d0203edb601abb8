//! The loop subdivision (the classic outer-to-inner work the paper cites,
//! refs. 11, 23, 27): a loop the rules are stuck on is split by a chord
//! between two of its nodes, subdivided so that both parts stay even.

use glam::DVec2;

use crate::features::deg_round;
use crate::geometry::{interior_angle, segments_intersect, SegmentRelation};
use crate::mesh::NodeKind;
use crate::partial_mesh::PartialMesh;
use crate::report::trace::{Angles, By, TraceStep};
use crate::validity::convex_ok;

/// Splits loop `l` by the best chord between two of its nodes whose
/// clearance from the front is at least `clearance` times the local size,
/// subdivided so that both parts are even; `strict` asks for a chord
/// that splits both corners well and leaves no part of four segments
/// that is not one convex element. False when there is none.
pub fn chord_split(pm: &mut PartialMesh, l: u32, clearance: f64, strict: bool) -> bool {
    let n = pm.front.loop_len(l);
    if n == 4 {
        return false;
    }
    let fvs = pm.front.loop_fvs(l);
    let ids: Vec<u32> = fvs.iter().map(|&f| pm.front.node(f)).collect();
    let p: Vec<DVec2> = ids.iter().map(|&i| pm.mesh.nodes[i as usize]).collect();
    let theta: Vec<f64> = fvs
        .iter()
        .map(|&f| pm.front.angle(f, &pm.mesh.nodes))
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
            if len / (k as f64) < pm.min_edge / 4.0 {
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
    let near = FrontNear::round(pm, &p, &cands, clearance);
    for &(score, i, j, k, h) in &cands {
        if near.chord_clear(p[i], p[j], ids[i], ids[j], h * clearance) {
            best = Some((score, i, j, k));
            break;
        }
    }
    let Some((_, i, j, k)) = best else {
        return false;
    };
    let (pi, pj) = (p[i], p[j]);
    let inner: Vec<u32> = (1..k)
        .map(|s| {
            pm.mesh
                .add_node(pi + (pj - pi) * (s as f64 / k as f64), NodeKind::Interior)
        })
        .collect();
    let mut path: Vec<u32> = inner.clone();
    path.push(ids[j]);
    path.extend(inner.iter().rev());
    path.push(ids[i]);
    pm.front.begin();
    let layer = pm.front.layer(fvs[i]).max(pm.front.layer(fvs[j]));
    let made = pm
        .front
        .replace_path(fvs[i], pm.front.next(fvs[i]), &path, layer);
    let parts = pm.front.split_pinch(made[k - 1], fvs[j]);
    if pm.fallback_only.contains(&l) {
        pm.fallback_only.extend(parts);
    }
    pm.front.commit(&pm.mesh.nodes);
    pm.stats.fallback_splits += 1;
    let angles = Angles::new(vec![
        ("theta1", deg_round(theta[i])),
        ("theta2", deg_round(theta[j])),
    ]);
    pm.note_step(|step| TraceStep {
        step,
        edge: [ids[i] as i64, ids[j] as i64],
        angles,
        feature: "stuck".into(),
        action: format!("split({k})"),
        by: By::Chord,
        redesign: vec![],
        element: vec![],
    });
    true
}

/// The front edges round a loop, gathered once for all its candidate
/// chords (a stuck loop of a few hundred nodes has thousands of them):
/// each edge's end nodes and their places.
struct FrontNear {
    edges: Vec<(u32, u32, DVec2, DVec2)>,
}

impl FrontNear {
    /// The front edges within reach of any of `cands` (chords between
    /// points of `p`): the grid's cells over the loop's box, padded as
    /// each chord's own query is.
    fn round(
        pm: &mut PartialMesh,
        p: &[DVec2],
        cands: &[(f64, usize, usize, usize, f64)],
        clearance: f64,
    ) -> FrontNear {
        let Some(h) = cands.iter().map(|c| c.4).reduce(f64::max) else {
            return FrontNear { edges: vec![] };
        };
        let pad = DVec2::splat(h * clearance * 0.25);
        let lo = p.iter().copied().reduce(DVec2::min).unwrap_or_default() - pad;
        let hi = p.iter().copied().reduce(DVec2::max).unwrap_or_default() + pad;
        let mut near = std::mem::take(&mut pm.scratch);
        pm.front.edges_near(lo, hi, &mut near);
        let edges = near
            .iter()
            .map(|&e| {
                let (x, y) = (pm.front.node(e), pm.front.node(pm.front.next(e)));
                (x, y, pm.mesh.nodes[x as usize], pm.mesh.nodes[y as usize])
            })
            .collect();
        pm.scratch = near;
        FrontNear { edges }
    }

    /// True iff the chord crosses no front edge and passes no front node
    /// closer than a fifth of the local size. Edges whose box misses the
    /// chord's padded box can do neither.
    fn chord_clear(&self, a: DVec2, b: DVec2, na: u32, nb: u32, h: f64) -> bool {
        let pad = DVec2::splat(h * 0.25);
        let (lo, hi) = (a.min(b) - pad, a.max(b) + pad);
        for &(x, y, px, py) in &self.edges {
            if px.max(py).cmplt(lo).any() || px.min(py).cmpgt(hi).any() {
                continue;
            }
            if x != na && x != nb && crate::geometry::point_segment_distance(px, a, b) < 0.2 * h {
                return false;
            }
            let rel = segments_intersect(a, b, px, py);
            if x == na || x == nb || y == na || y == nb {
                // sharing an end is fine; lying along the chord is not
                if rel == SegmentRelation::Overlap || (x == na && y == nb) || (x == nb && y == na) {
                    return false;
                }
                continue;
            }
            if rel != SegmentRelation::Disjoint {
                return false;
            }
        }
        true
    }
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
