//! Rings: a small loop no chord splits well gets a ring of elements round
//! a new convex loop inside it, which the final patterns or a chord close.

use glam::DVec2;

use crate::geometry::orient2d;
use crate::mesh::NodeKind;
use crate::partial_mesh::{Closing, PartialMesh};
use crate::report::trace::{Angles, By};
use crate::validity::{convex_angles, distinct, quad_clear};

/// The last resort for a loop the rules and chords cannot mesh: a
/// ring of n elements round a new convex loop of n nodes on a circle
/// about a centre that sees every node of the loop. The inner loop is
/// convex whatever the loop's shape, so the final patterns or a chord
/// close it.
pub fn close_ring(pm: &mut PartialMesh, l: u32) -> Option<u32> {
    let fvs = pm.front.loop_fvs(l);
    let n = fvs.len();
    let ids: Vec<u32> = fvs.iter().map(|&f| pm.front.node(f)).collect();
    if !distinct(&ids) || n > 12 {
        return None;
    }
    let p: Vec<DVec2> = ids.iter().map(|&i| pm.mesh.nodes[i as usize]).collect();
    // The centre and radius: the best of a grid over the loop's box,
    // judged by the smallest angle of the ring's elements.
    // a quarter of the rules' minimum: a ring may be finer than the
    // elements round it, but rings in rings cannot shrink for ever
    // (a loop of four gets a ring round a convex four, closed at once:
    // no nesting, so its ring may go finer)
    let min_edge = pm.min_edge / if n == 4 { 32.0 } else { 4.0 };
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
    let floor = |best: &Option<(f64, Vec<DVec2>)>| best.as_ref().map_or(f64::NEG_INFINITY, |b| b.0);
    let steps = 48;
    for ix in 1..steps {
        for iy in 1..steps {
            let c = lo + (hi - lo) * DVec2::new(ix as f64 / steps as f64, iy as f64 / steps as f64);
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
            if !quad_clear(
                pm,
                q,
                &[Some(ids[i]), Some(ids[(i + 1) % n]), None, None],
                0.0,
            ) {
                return None;
            }
        }
        let base = pm.mesh.nodes.len() as u32;
        for &x in &inner {
            pm.mesh.add_node(x, NodeKind::Interior);
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
        pm.stats.fallback_splits += 1;
        pm.stats.rings += 1;
        let layer = pm.front.layer(fvs[0]) + 1;
        pm.close_with(
            l,
            qs,
            &[],
            Closing {
                feature: "stuck",
                action: "ring".into(),
                angles: Angles::default(),
                by: By::Ring,
            },
        );
        pm.front.begin();
        let nl = pm.front.add_loop(&inner_ids, &vec![layer; n]);
        pm.front.commit(&pm.mesh.nodes);
        return Some(nl);
    }
    None
}
