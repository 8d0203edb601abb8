//! Blocks whose opposite sides cannot agree (the paper's Fig. 18: "the
//! mesh generation in mapping element when two opposite sides do not
//! share a subdivision number"): the free blocks that touch each other
//! make one region, whose loop of fine nodes the rules mesh as a domain
//! of its own, every node kept; its elements join the mapped blocks'.

use glam::DVec2;
use rustc_hash::FxHashMap as HashMap;

use super::intervals::Chords;
use crate::kb::KnowledgeBase;
use crate::mesh::{Mesh, NodeKind};
use crate::pipeline::{mesh_domain, Options};
use crate::report::trace::{By, TraceStep};

/// Meshes the free blocks of `layout` into `fine` (whose mapped blocks
/// and every layout edge's nodes, `edge_nodes`, are there already), a
/// region of touching free blocks at a time; the regions' steps, their
/// node ids those of `fine`, come back for the trace. Err says why not
/// (a region round a hole of mapped blocks, an odd loop, a region the
/// rules cannot mesh). `opts`: the regions' runs (uniform, at the
/// element size).
pub fn mesh_free_regions(
    fine: &mut Mesh,
    layout: &Mesh,
    chords: &Chords,
    edge_nodes: &[Vec<u32>],
    free: &[bool],
    kb: &mut KnowledgeBase,
    opts: &Options,
) -> Result<Vec<TraceStep>, String> {
    let size = opts.size.expect("the regions' runs have the element size");
    let mut steps = Vec::new();
    for region in regions(chords, free) {
        let ring = region_loop(layout, chords, edge_nodes, &region)?;
        if ring.len() % 2 == 1 {
            return Err(format!(
                "free blocks with an odd loop of {} segments",
                ring.len()
            ));
        }
        let points: Vec<[f64; 2]> = ring
            .iter()
            .map(|&n| [fine.nodes[n as usize].x, fine.nodes[n as usize].y])
            .collect();
        let domain = crate::input::domain::Domain::from_json(&serde_json::json!({
            "name": "free blocks", "size": size,
            "outer": { "points": points, "segments": vec![1; points.len()] }
        }))
        .map_err(|e| format!("free blocks: {e}"))?;
        let r =
            mesh_domain(&domain, kb, opts, &mut |_| {}).map_err(|e| format!("free blocks: {e}"))?;
        if r.stats.triangle_fallbacks > 0 {
            return Err("free blocks meshed whole by the triangle fallback".into());
        }
        // the region's loop nodes are the fine mesh's, at the same
        // coordinates exactly; the others are new
        let at: HashMap<(u64, u64), u32> = ring
            .iter()
            .map(|&n| (key(fine.nodes[n as usize]), n))
            .collect();
        let ids: Vec<u32> = r
            .mesh
            .nodes
            .iter()
            .zip(&r.mesh.kinds)
            .map(|(&p, &kind)| match (kind, at.get(&key(p))) {
                (NodeKind::Boundary, Some(&n)) => Ok(n),
                (NodeKind::Boundary, None) => Err("free blocks: a loop node moved".to_string()),
                _ => Ok(fine.add_node(p, NodeKind::Interior)),
            })
            .collect::<Result<_, _>>()?;
        let block = region[0] as u32;
        for q in &r.mesh.quads {
            fine.quads.push(q.map(|n| ids[n as usize]));
            fine.blocks.push(block);
        }
        let q = layout.quads[region[0]];
        steps.push(TraceStep {
            step: 0,
            edge: [q[0] as i64, q[1] as i64],
            angles: Default::default(),
            feature: "block".into(),
            action: format!("free({}, {})", region.len(), ring.len()),
            by: By::Block,
            redesign: vec![],
            element: q.iter().map(|&x| x as i64).collect(),
        });
        let id = |x: i64| if x < 0 { x } else { ids[x as usize] as i64 };
        steps.extend(r.trace.into_iter().map(|mut t| {
            t.edge = t.edge.map(id);
            t.element = t.element.into_iter().map(id).collect();
            t
        }));
    }
    Ok(steps)
}

/// Grows the free blocks until every region of them has an even loop (a
/// region's loop may be odd where there are several: only their sum is
/// even): an odd region takes in the blocks next to it, until it meets
/// another odd one.
pub fn even_regions(chords: &Chords, counts: &[usize], free: &mut [bool]) {
    for _ in 0..free.len() {
        let odd = regions(chords, free).into_iter().find(|region| {
            let mut uses: HashMap<usize, usize> = HashMap::default();
            for &b in region {
                for &e in &chords.sides[b] {
                    *uses.entry(e).or_default() += 1;
                }
            }
            let segments: usize = uses
                .iter()
                .filter(|(_, &n)| n == 1)
                .map(|(&e, _)| counts[e])
                .sum();
            segments % 2 == 1
        });
        let Some(region) = odd else { return };
        let edges: Vec<usize> = region.iter().flat_map(|&b| chords.sides[b]).collect();
        for (b, s) in chords.sides.iter().enumerate() {
            if s.iter().any(|e| edges.contains(e)) {
                free[b] = true;
            }
        }
    }
}

fn key(p: DVec2) -> (u64, u64) {
    (p.x.to_bits(), p.y.to_bits())
}

/// The free blocks grouped by touching (a shared layout edge), each
/// group in block order.
fn regions(chords: &Chords, free: &[bool]) -> Vec<Vec<usize>> {
    let mut by_edge: HashMap<usize, Vec<usize>> = HashMap::default();
    for (b, s) in chords.sides.iter().enumerate() {
        if free[b] {
            for &e in s {
                by_edge.entry(e).or_default().push(b);
            }
        }
    }
    let mut seen = vec![false; free.len()];
    let mut out = Vec::new();
    for start in 0..free.len() {
        if !free[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        let (mut region, mut stack) = (vec![], vec![start]);
        while let Some(b) = stack.pop() {
            region.push(b);
            for e in chords.sides[b] {
                for &o in &by_edge[&e] {
                    if !seen[o] {
                        seen[o] = true;
                        stack.push(o);
                    }
                }
            }
        }
        region.sort_unstable();
        out.push(region);
    }
    out
}

/// The loop of fine nodes round a region, counter-clockwise: the sides
/// of its blocks no other block of it shares, joined end to end.
fn region_loop(
    layout: &Mesh,
    chords: &Chords,
    edge_nodes: &[Vec<u32>],
    region: &[usize],
) -> Result<Vec<u32>, String> {
    let mut uses: HashMap<usize, usize> = HashMap::default();
    for &b in region {
        for &e in &chords.sides[b] {
            *uses.entry(e).or_default() += 1;
        }
    }
    // each outer side from its block's corner k to k + 1
    let mut next: HashMap<u32, Vec<u32>> = HashMap::default();
    let mut sides = 0;
    for &b in region {
        let q = layout.quads[b];
        for (k, &e) in chords.sides[b].iter().enumerate() {
            if uses[&e] > 1 {
                continue;
            }
            let mut nodes = edge_nodes[e].clone();
            if nodes[0] != q[k] {
                nodes.reverse();
            }
            next.insert(q[k], nodes);
            sides += 1;
        }
    }
    let start = layout.quads[region[0]]
        .iter()
        .copied()
        .find(|n| next.contains_key(n))
        .ok_or("free blocks: a region with no outer side")?;
    let (mut ring, mut at, mut walked) = (Vec::new(), start, 0);
    loop {
        let nodes = next
            .get(&at)
            .ok_or("free blocks: a region's sides do not close")?;
        ring.extend_from_slice(&nodes[..nodes.len() - 1]);
        at = *nodes.last().expect("a side has two ends");
        walked += 1;
        if at == start {
            break;
        }
        if walked > sides {
            return Err("free blocks: a region's sides do not close".into());
        }
    }
    if walked != sides {
        return Err("free blocks round mapped ones (a region with a hole)".into());
    }
    Ok(ring)
}
