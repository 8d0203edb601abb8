//! Final patterns: a loop of four segments is one element; a loop of six
//! is closed by the first of the KB's patterns 1-3 (kb/patterns.pl) whose
//! elements are convex and clear of the front. Patterns 1 and 2 add a node
//! (Eq. 5 and 6). Where no rule applies, a small loop is closed whole by
//! the ways of the KB's `closing_way/2` (closing.rs).

pub mod closing;

use glam::DVec2;

use crate::features::deg_round;
use crate::geometry::{orient2d, quad_angles};
use crate::kb::{KbError, KnowledgeBase, PatternKind};
use crate::partial_mesh::{Closing, PartialMesh};
use crate::report::trace::{Angles, By};
use crate::validity::{convex_ok, distinct, quad_clear};

/// Closes loop `l` if it has four or six segments and a pattern fits;
/// false otherwise.
pub fn try_close_loop(
    pm: &mut PartialMesh,
    kb: &mut KnowledgeBase,
    l: u32,
) -> Result<bool, KbError> {
    let n = pm.front.loop_len(l);
    if n != 4 && n != 6 {
        return Ok(false);
    }
    let fvs = pm.front.loop_fvs(l);
    let ids: Vec<u32> = fvs.iter().map(|&f| pm.front.node(f)).collect();
    let p: Vec<DVec2> = ids.iter().map(|&i| pm.mesh.nodes[i as usize]).collect();
    let angles: Vec<f64> = fvs
        .iter()
        .map(|&f| deg_round(pm.front.angle(f, &pm.mesh.nodes)))
        .collect();
    let names = ["a1", "a2", "a3", "a4", "a5", "a6"];
    let angle_map = Angles::new(names.into_iter().zip(angles.iter().copied()).collect());
    if n == 4 {
        let q = [p[0], p[1], p[2], p[3]];
        if convex_ok(&q)
            && no_sliver_edge(&q)
            && distinct(&ids)
            && quad_clear(
                pm,
                q,
                &ids.iter().map(|&x| Some(x)).collect::<Vec<_>>(),
                0.0,
            )
        {
            let quad = [ids[0], ids[1], ids[2], ids[3]];
            pm.close_with(
                l,
                vec![quad],
                &[],
                Closing {
                    feature: "final4",
                    action: "quad".into(),
                    angles: angle_map,
                    by: By::Pattern,
                },
            );
            return Ok(true);
        }
        return Ok(false);
    }
    if !distinct(&ids) {
        return Ok(false);
    }
    let mut best = None;
    for pat in kb.final_patterns(&angles)? {
        let k = pat.start;
        let at = |i: usize| (k + i) % 6; // the paper's N_{i+1}
        let (quads, new_pts): (Vec<[usize; 4]>, Vec<DVec2>) = match pat.kind {
            PatternKind::Three => (
                vec![[at(2), at(3), at(4), at(5)], [at(5), at(0), at(1), at(2)]],
                vec![],
            ),
            PatternKind::One | PatternKind::Two => {
                let c = if pat.kind == PatternKind::One {
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
                let c = best_centre(&p, &quads, c, pm.host.centre_search_below);
                (quads, vec![c])
            }
        };
        let pt = |i: usize| if i < 6 { p[i] } else { new_pts[i - 6] };
        let clear = quads.iter().all(|qd| {
            let q = qd.map(pt);
            convex_ok(&q) && no_sliver_edge(&q)
        }) && quads.iter().all(|qd| {
            let qids: Vec<Option<u32>> = qd
                .iter()
                .map(|&i| if i < 6 { Some(ids[i]) } else { None })
                .collect();
            quad_clear(pm, qd.map(pt), &qids, 0.0)
        });
        if !clear {
            continue;
        }
        // the first pattern with every corner in the window; else the
        // valid one whose worst corner is nearest it
        let excess = quads
            .iter()
            .map(|qd| crate::element_quality::worst_excess(qd.map(pt), &pm.bounds))
            .fold(0.0, f64::max);
        if best.as_ref().is_none_or(|b: &(f64, _, _, _)| excess < b.0) {
            best = Some((excess, quads, new_pts, pat.text));
        }
        if excess == 0.0 {
            break;
        }
    }
    if let Some((_, quads, new_pts, text)) = best {
        let base = pm.mesh.nodes.len() as u32;
        let quads_ids: Vec<[u32; 4]> = quads
            .iter()
            .map(|qd| qd.map(|i| if i < 6 { ids[i] } else { base + (i - 6) as u32 }))
            .collect();
        pm.close_with(
            l,
            quads_ids,
            &new_pts,
            Closing {
                feature: "final6",
                action: text,
                angles: angle_map,
                by: By::Pattern,
            },
        );
        return Ok(true);
    }
    Ok(false)
}

/// Closes loop `l`, one the rules are stuck on, whole by the best of the
/// ways the KB's `closing_way/2` allows, if it has at most
/// `bound(closing_loop_segments, _)` segments. With `strict`, only where
/// every element has its corners inside the window; else where every
/// element is convex. The elements must be clear of the rest of the front.
pub fn try_close_stuck_loop(
    pm: &mut PartialMesh,
    kb: &mut KnowledgeBase,
    memo: &mut closing::Memo,
    l: u32,
    strict: bool,
) -> Result<bool, KbError> {
    let n = pm.front.loop_len(l);
    if n < 4 || n % 2 == 1 || n as f64 > pm.host.closing_loop_segments {
        return Ok(false);
    }
    let fvs = pm.front.loop_fvs(l);
    let ids: Vec<u32> = fvs.iter().map(|&f| pm.front.node(f)).collect();
    if !distinct(&ids) {
        return Ok(false);
    }
    let mut ways = vec![closing::Ways::default(); n + 1];
    for (k, w) in ways.iter_mut().enumerate().skip(4).step_by(2) {
        for name in kb.closing_ways(k)? {
            match name.as_str() {
                "quad" => w.quad = true,
                "inset" => w.inset = true,
                "hub" => w.hub = true,
                "chord" => w.chord = true,
                "path" => w.path = true,
                _ => {}
            }
        }
    }
    let p: Vec<DVec2> = ids.iter().map(|&i| pm.mesh.nodes[i as usize]).collect();
    // strict: a split whose part has a corner further from a right angle
    // than the window allows is not followed (with the KB's margin for
    // the last placement of the new nodes)
    let cap = if strict {
        (90.0 - pm.bounds.lower_corner).max(pm.bounds.upper_corner - 90.0)
            + pm.host.closing_strict_margin
    } else {
        closing::NOT_CONVEX
    };
    let Some(closed) = memo.close_loop(&p, &ways, cap) else {
        return Ok(false);
    };
    let pt = |i: usize| {
        if i < n {
            p[i]
        } else {
            closed.new_points[i - n]
        }
    };
    // strict: corners in the window, and an element on the loop about
    // the size of the loop's edges it takes (the elements across them are)
    let fits = |qd: &[usize; 4]| {
        let q = qd.map(pt);
        if !convex_ok(&q) {
            return false;
        }
        if !strict {
            return true;
        }
        let (mut sum, mut k) = (0.0, 0);
        for i in 0..4 {
            let (a, b) = (qd[i], qd[(i + 1) % 4]);
            if a < n && b < n && (b == (a + 1) % n || a == (b + 1) % n) {
                sum += (p[a] - p[b]).length();
                k += 1;
            }
        }
        let side = ((q[2] - q[0]).perp_dot(q[3] - q[1]).abs() * 0.5).sqrt();
        let size_fits = k == 0 || {
            let r = side * k as f64 / sum;
            let most = pm.host.closing_strict_size;
            (1.0 / most..=most).contains(&r)
        };
        size_fits && crate::element_quality::worst_excess(q, &pm.bounds) == 0.0
    };
    if !closed.quads.iter().all(fits) {
        return Ok(false);
    }
    let clear = closed.quads.iter().all(|qd| {
        let qids: Vec<Option<u32>> = qd
            .iter()
            .map(|&i| if i < n { Some(ids[i]) } else { None })
            .collect();
        quad_clear(pm, qd.map(pt), &qids, 0.0)
    });
    if !clear {
        return Ok(false);
    }
    let angles: Vec<(&'static str, f64)> = fvs
        .iter()
        .zip(ANGLE_NAMES)
        .map(|(&f, name)| (name, deg_round(pm.front.angle(f, &pm.mesh.nodes))))
        .collect();
    let base = pm.mesh.nodes.len() as u32;
    let quads_ids: Vec<[u32; 4]> = closed
        .quads
        .iter()
        .map(|qd| qd.map(|i| if i < n { ids[i] } else { base + (i - n) as u32 }))
        .collect();
    let feature = format!("final{n}");
    pm.close_with(
        l,
        quads_ids,
        &closed.new_points,
        Closing {
            feature: &feature,
            action: closed.text,
            angles: Angles::new(angles),
            by: By::Pattern,
        },
    );
    Ok(true)
}

/// The trace's names of a closed loop's angles, in loop order (the bound
/// `closing_loop_segments` is below 41).
const ANGLE_NAMES: [&str; 40] = [
    "a1", "a2", "a3", "a4", "a5", "a6", "a7", "a8", "a9", "a10", "a11", "a12", "a13", "a14", "a15",
    "a16", "a17", "a18", "a19", "a20", "a21", "a22", "a23", "a24", "a25", "a26", "a27", "a28",
    "a29", "a30", "a31", "a32", "a33", "a34", "a35", "a36", "a37", "a38", "a39", "a40",
];

/// Whether every edge of a closing element is at least a hundredth of its
/// longest: two loop nodes at one place, or a centre put on a loop node,
/// make an edge of nothing between two corners of 90, convex and in the
/// window (the sides across a sharp tip taken whole are shorter than the
/// others, but not a hundred times).
fn no_sliver_edge(q: &[DVec2; 4]) -> bool {
    let e: [f64; 4] = std::array::from_fn(|i| (q[(i + 1) % 4] - q[i]).length());
    let longest = e.iter().copied().fold(0.0, f64::max);
    e.iter().all(|&l| l * SLIVER_EDGE > longest)
}

/// How many times shorter than an element's longest edge its shortest
/// may be in a closing pattern.
const SLIVER_EDGE: f64 = 100.0;

/// The position of an inner node (index 6 in `quads`) that makes the
/// elements convex with the largest smallest angle: `first` if it is good,
/// else the best of a grid over the loop's bounding box.
fn best_centre(p: &[DVec2], quads: &[[usize; 4]], first: DVec2, search_below: f64) -> DVec2 {
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
    if best.0 >= search_below {
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
