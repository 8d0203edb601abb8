//! Evening out sizes and shapes where they break the KB's bounds (size
//! jump between neighbours, aspect ratio and taper: 2, 10 and 10 unless
//! `bound/2` says otherwise).

use glam::DVec2;

use crate::element_quality::{corners_outside, quad_area, size_shape_excess, worst_around};
use crate::mesh::{Mesh, NodeKind};
use crate::settings::ElementBounds;
use crate::smoothing::compass::compass_search_together;
use crate::smoothing::strips::{mark_nodes, take_free_dirty, Nodes};

pub(crate) fn even_out_sweeps(
    mesh: &mut Mesh,
    passes: usize,
    nodes: &Nodes,
    neighbours: &[[Option<u32>; 4]],
    dirty: &mut [bool],
    bounds: &ElementBounds,
) -> usize {
    let around = nodes.around;
    let mut area: Vec<f64> = (0..mesh.quads.len() as u32)
        .map(|q| quad_area(mesh, q))
        .collect();
    let mut moved = 0;
    for _ in 0..passes {
        let mut any = false;
        for &n in nodes.visit {
            let n = n as usize;
            if !take_free_dirty(mesh, nodes, dirty, n) {
                continue;
            }
            let own = excess_round(mesh, &area, neighbours, &around[n], bounds);
            if own <= 0.95 {
                continue; // moving n could only make its elements worse
            }
            let mut moved_nodes = Vec::new();
            let left = match even_out_move(mesh, &[n], &around[n], &area, neighbours, bounds) {
                Some(left) => {
                    moved_nodes.push(n);
                    left
                }
                None => own,
            };
            if left > 1.0 {
                // still past a bound: n is held by a corner at the edge
                // of the window; try it with a neighbour, both moving
                // together (an edge of the element shifted)
                if let Some(m) = even_out_pair(mesh, n, nodes, &area, neighbours, bounds) {
                    moved_nodes.extend([n, m]);
                }
            }
            for k in moved_nodes {
                moved += 1;
                any = true;
                // the neighbours' size ratios changed with these
                for &(q, _) in &around[k] {
                    area[q as usize] = quad_area(mesh, q);
                    let touched =
                        std::iter::once(q).chain(neighbours[q as usize].iter().flatten().copied());
                    mark_nodes(mesh, touched, dirty);
                }
            }
        }
        if !any {
            break;
        }
    }
    moved
}

/// The size and shape excess of the elements of `region` (measured
/// afresh), against their neighbours too: all that moving the nodes the
/// region is round changes. `area` holds every other element's area.
pub(crate) fn excess_round(
    mesh: &Mesh,
    area: &[f64],
    neighbours: &[[Option<u32>; 4]],
    region: &[(u32, u8)],
    bounds: &ElementBounds,
) -> f64 {
    excess_round_under(mesh, area, neighbours, region, f64::INFINITY, bounds)
        .unwrap_or(f64::INFINITY)
}

/// The region's areas measured once an evaluation (a region is rarely
/// larger; past this its areas are measured as they are asked for).
pub(crate) const REGION_AREAS: usize = 24;

/// `excess_round` if it is below `bound`, else None: the elements are
/// judged one by one and the first at or past the bound ends it (most
/// places a search tries are no better, and one element shows it).
pub(crate) fn excess_round_under(
    mesh: &Mesh,
    area: &[f64],
    neighbours: &[[Option<u32>; 4]],
    region: &[(u32, u8)],
    bound: f64,
    bounds: &ElementBounds,
) -> Option<f64> {
    let mut fresh = [0.0; REGION_AREAS];
    for (slot, &(q, _)) in fresh.iter_mut().zip(region) {
        *slot = quad_area(mesh, q);
    }
    let area_of = |q: u32| match region.iter().position(|x| x.0 == q) {
        Some(i) if i < REGION_AREAS => fresh[i],
        Some(_) => quad_area(mesh, q),
        None => area[q as usize],
    };
    let mut worst = 0.0;
    for &(q, _) in region {
        let e = size_shape_excess(mesh, q, &neighbours[q as usize], &area_of, bounds);
        if e >= bound {
            return None;
        }
        worst = f64::max(worst, e);
    }
    (worst < bound).then_some(worst)
}

/// Moves the nodes `ns` together to where the size and shape excess of
/// their elements (`region`) is least, without a corner there leaving
/// the corner window further or getting much sharper than it was.
/// Returns the excess left if they moved.
pub(crate) fn even_out_move(
    mesh: &mut Mesh,
    ns: &[usize],
    region: &[(u32, u8)],
    area: &[f64],
    neighbours: &[[Option<u32>; 4]],
    bounds: &ElementBounds,
) -> Option<f64> {
    let inside = |f: &u32| region.iter().any(|&(q, _)| q == *f);
    // what moving them cannot change: the shapes of the elements next to
    // the region, and their sizes against elements outside it
    let fixed = region
        .iter()
        .flat_map(|&(q, _)| neighbours[q as usize].iter().flatten().copied())
        .filter(|f| !inside(f))
        .map(|f| {
            let others = neighbours[f as usize].map(|g| g.filter(|g| !inside(g)));
            size_shape_excess(mesh, f, &others, &|q| area[q as usize], bounds)
        })
        .fold(0.0, f64::max);
    let start_excess = excess_round(mesh, area, neighbours, region, bounds).max(fixed);
    if fixed >= start_excess - 1e-6 {
        return None; // the worst is out of reach: no place does better
    }
    let start = worst_around(mesh, region, bounds);
    let start_outside = corners_outside(mesh, region, bounds);
    let min_sin = (-start.1).min(0.6);
    let olds: Vec<DVec2> = ns.iter().map(|&n| mesh.nodes[n]).collect();
    let best = compass_search_together(
        mesh,
        ns,
        region,
        start_excess,
        |m, best| {
            // the excess first: most places are no better, and the
            // corners need not be looked at there
            let e =
                excess_round_under(m, area, neighbours, region, best - 1e-6, bounds)?.max(fixed);
            if e >= best - 1e-6 {
                return None;
            }
            let w = worst_around(m, region, bounds);
            let allowed = w.0 <= start.0 + 1e-9
                && -w.1 >= min_sin
                && corners_outside(m, region, bounds) <= start_outside;
            allowed.then_some(e)
        },
        |e, best| e < best - 1e-6,
        6,
    );
    if best == olds[0] {
        return None;
    }
    for (&n, &o) in ns.iter().zip(&olds) {
        mesh.nodes[n] = o + (best - olds[0]);
    }
    Some(excess_round(mesh, area, neighbours, region, bounds))
}

/// Makes the best joint move of node `n` with one of the free nodes it
/// shares an edge with (one the sweep may move), if one does better. The
/// first partner wins a tie. Returns the partner.
pub(crate) fn even_out_pair(
    mesh: &mut Mesh,
    n: usize,
    nodes: &Nodes,
    area: &[f64],
    neighbours: &[[Option<u32>; 4]],
    bounds: &ElementBounds,
) -> Option<usize> {
    let around = nodes.around;
    let mut partners: Vec<usize> = around[n]
        .iter()
        .map(|&(q, c)| mesh.quads[q as usize][(c as usize + 1) % 4] as usize)
        .filter(|&m| {
            mesh.kinds[m] == NodeKind::Interior && nodes.visit.binary_search(&(m as u32)).is_ok()
        })
        .collect();
    partners.sort_unstable();
    partners.dedup();
    let at_n = mesh.nodes[n];
    // (partner, excess left, where the two went)
    let mut best: Option<(usize, f64, [DVec2; 2])> = None;
    for m in partners {
        let at_m = mesh.nodes[m];
        let mut region = around[n].clone();
        region.extend(
            around[m]
                .iter()
                .filter(|x| !around[n].iter().any(|y| y.0 == x.0)),
        );
        if let Some(left) = even_out_move(mesh, &[n, m], &region, area, neighbours, bounds) {
            if best.is_none_or(|b| left < b.1 - 1e-6) {
                best = Some((m, left, [mesh.nodes[n], mesh.nodes[m]]));
            }
            mesh.nodes[n] = at_n;
            mesh.nodes[m] = at_m;
        }
    }
    let (m, _, [pn, pm]) = best?;
    mesh.nodes[n] = pn;
    mesh.nodes[m] = pm;
    Some(m)
}
