//! A large mesh swept on several threads, strip by strip, the same
//! result on any machine; and the adjacency the sweeps work on.

use glam::DVec2;

use crate::mesh::{Mesh, NodeKind};

/// For each node, the elements that use it and the node's corner index.
pub fn node_elements(mesh: &Mesh) -> Vec<Vec<(u32, u8)>> {
    let mut out = vec![Vec::new(); mesh.nodes.len()];
    for (qi, q) in mesh.quads.iter().enumerate() {
        for (c, &n) in q.iter().enumerate() {
            out[n as usize].push((qi as u32, c as u8));
        }
    }
    out
}

/// For each element, the elements across its four edges.
pub(crate) fn element_neighbours(mesh: &Mesh, around: &[Vec<(u32, u8)>]) -> Vec<[Option<u32>; 4]> {
    mesh.quads
        .iter()
        .map(|q| std::array::from_fn(|i| across(mesh, around, q[i], q[(i + 1) % 4])))
        .collect()
}

/// The element with the edge b -> a (the other side of the edge a -> b).
pub(crate) fn across(mesh: &Mesh, around: &[Vec<(u32, u8)>], a: u32, b: u32) -> Option<u32> {
    around[b as usize]
        .iter()
        .find(|&&(o, c)| mesh.quads[o as usize][(c as usize + 1) % 4] == a)
        .map(|&(o, _)| o)
}

/// Whether a sweep looks at node `n`: a free node of some element, marked
/// dirty since it was last looked at (the mark is taken). A node none of
/// whose elements changed since then would come out the same.
pub(crate) fn take_free_dirty(mesh: &Mesh, nodes: &Nodes, dirty: &mut [bool], n: usize) -> bool {
    std::mem::take(&mut dirty[n])
        && mesh.kinds[n] == NodeKind::Interior
        && !nodes.around[n].is_empty()
}

/// What a sweep works on: each node's elements, and the nodes it visits
/// (in ascending order; it moves no other).
pub(crate) struct Nodes<'a> {
    pub(crate) around: &'a [Vec<(u32, u8)>],
    pub(crate) visit: &'a [u32],
}

/// Meshes with fewer nodes are smoothed on one thread.
pub(crate) const SPLIT_FROM_NODES: usize = 20_000;

/// A large mesh is cut into this many strips across x.
pub(crate) const STRIPS: usize = 8;

/// How many rings of elements either side of a seam its sweep may move.
pub(crate) const SEAM_BAND: usize = 3;

/// Runs a sweep over every free node; a large mesh on several threads.
///
/// The nodes are cut into strips by x. A strip is swept without its nodes
/// at a seam (those sharing an element with another strip), so no strip
/// moves a node another one reads; the threads take strips in turn, each
/// on its own copy of the mesh, every strip from the mesh as it was. Then
/// the seams are swept, within a band of a few elements, the bands far
/// enough apart that neither reads the other's moves side by side. The
/// strips and bands depend on the mesh alone, and each comes out the same
/// whichever thread sweeps it, so the result is the same on any machine.
/// Returns the moves kept.
pub(crate) fn sweep_in_strips(
    mesh: &mut Mesh,
    around: Vec<Vec<(u32, u8)>>,
    sweep: impl Fn(&mut Mesh, &Nodes, &mut [bool]) -> usize + Sync,
) -> usize {
    let threads = std::thread::available_parallelism()
        .map_or(1, |c| c.get())
        .clamp(1, 4);
    sweep_in_strips_on(mesh, around, threads, sweep)
}

/// `sweep_in_strips` on this many threads.
pub(crate) fn sweep_in_strips_on(
    mesh: &mut Mesh,
    around: Vec<Vec<(u32, u8)>>,
    threads: usize,
    sweep: impl Fn(&mut Mesh, &Nodes, &mut [bool]) -> usize + Sync,
) -> usize {
    let n = mesh.nodes.len();
    if n < SPLIT_FROM_NODES {
        let all: Vec<u32> = (0..n as u32).collect();
        let mut dirty = vec![true; n];
        let nodes = Nodes {
            around: &around,
            visit: &all,
        };
        return sweep(mesh, &nodes, &mut dirty);
    }
    let mut by_x: Vec<u32> = (0..n as u32).collect();
    by_x.sort_by(|&a, &b| {
        mesh.nodes[a as usize]
            .x
            .total_cmp(&mesh.nodes[b as usize].x)
            .then(a.cmp(&b))
    });
    let mut strip = vec![0usize; n];
    for (rank, &i) in by_x.iter().enumerate() {
        strip[i as usize] = rank * STRIPS / n;
    }
    let at_seam = |i: usize| {
        around[i].iter().any(|&(q, _)| {
            mesh.quads[q as usize]
                .iter()
                .any(|&m| strip[m as usize] != strip[i])
        })
    };
    let seam: Vec<bool> = (0..n).map(at_seam).collect();
    let mut inner: Vec<Vec<u32>> = vec![Vec::new(); STRIPS];
    for i in (0..n).filter(|&i| !seam[i]) {
        inner[strip[i]].push(i as u32);
    }
    let all_dirty = vec![true; n];
    let moved = sweep_groups(mesh, &around, &inner, &all_dirty, threads, &sweep);
    // the seams are left, swept within a band of a few elements either
    // side (a settling move there need not ripple across the mesh)
    let mut band = seam.clone();
    for _ in 0..SEAM_BAND {
        band = (0..n)
            .map(|i| {
                band[i]
                    || around[i]
                        .iter()
                        .any(|&(q, _)| mesh.quads[q as usize].iter().any(|&m| band[m as usize]))
            })
            .collect();
    }
    // bands far apart cannot read each other's moves: swept side by side,
    // they come out as swept together
    let bands = apart_groups(mesh, &around, &band, BANDS_APART);
    moved + sweep_groups(mesh, &around, &bands, &seam, threads, &sweep)
}

/// How many node steps from a band a sweep there may read or mark (the
/// size evening reads areas two elements out, three steps): bands more
/// than twice this apart are swept apart.
pub(crate) const BANDS_APART: usize = 4;

/// The nodes marked in `marked`, in ascending order, grouped so that two
/// nodes at most `2 * reach` steps apart (a step: to a corner of an
/// element at the node) are in one group; the groups ordered by their
/// first node.
pub(crate) fn apart_groups(
    mesh: &Mesh,
    around: &[Vec<(u32, u8)>],
    marked: &[bool],
    reach: usize,
) -> Vec<Vec<u32>> {
    let n = marked.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn root(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    }
    // every node reached within `reach` steps of a marked one takes the
    // group of the first to reach it; two groups meeting are joined
    let mut owner: Vec<u32> = (0..n as u32)
        .map(|i| if marked[i as usize] { i } else { u32::MAX })
        .collect();
    let mut frontier: Vec<u32> = (0..n as u32).filter(|&i| marked[i as usize]).collect();
    for _ in 0..reach {
        let mut next = Vec::new();
        for &u in &frontier {
            for &(q, _) in &around[u as usize] {
                for v in mesh.quads[q as usize] {
                    let o = owner[v as usize];
                    if o == u32::MAX {
                        owner[v as usize] = owner[u as usize];
                        next.push(v);
                    } else {
                        let (a, b) = (root(&mut parent, o), root(&mut parent, owner[u as usize]));
                        parent[a.max(b) as usize] = a.min(b);
                    }
                }
            }
        }
        frontier = next;
    }
    let mut groups: Vec<Vec<u32>> = Vec::new();
    let mut index: rustc_hash::FxHashMap<u32, usize> = Default::default();
    for i in (0..n as u32).filter(|&i| marked[i as usize]) {
        let r = root(&mut parent, i);
        let g = *index.entry(r).or_insert_with(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[g].push(i);
    }
    groups
}

/// Sweeps each group of nodes, the threads taking groups in turn, each
/// group from the mesh as it was and from the dirty marks of
/// `dirty_at_start`; the groups' nodes are then written back. Returns
/// the moves kept.
pub(crate) fn sweep_groups(
    mesh: &mut Mesh,
    around: &[Vec<(u32, u8)>],
    groups: &[Vec<u32>],
    dirty_at_start: &[bool],
    threads: usize,
    sweep: &(impl Fn(&mut Mesh, &Nodes, &mut [bool]) -> usize + Sync),
) -> usize {
    let n = mesh.nodes.len();
    if groups.is_empty() {
        return 0;
    }
    if groups.len() == 1 {
        let mut dirty = dirty_at_start.to_vec();
        let nodes = Nodes {
            around,
            visit: &groups[0],
        };
        return sweep(mesh, &nodes, &mut dirty);
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    // sweeps groups as they come, each from the mesh as it was (so that
    // what a group reads outside it is the same whichever groups the
    // thread swept before); the places its nodes went, and the moves kept
    let original = &*mesh;
    let work = || {
        let mut m = original.clone();
        let mut dirty = vec![false; n];
        let mut placed: Vec<(u32, DVec2)> = Vec::new();
        let mut moved = 0;
        loop {
            let s = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            let Some(visit) = groups.get(s) else {
                return (placed, moved);
            };
            for &i in visit {
                dirty[i as usize] = dirty_at_start[i as usize];
            }
            moved += sweep(&mut m, &Nodes { around, visit }, &mut dirty);
            for &i in visit {
                placed.push((i, m.nodes[i as usize]));
                m.nodes[i as usize] = original.nodes[i as usize];
            }
        }
    };
    let results: Vec<(Vec<(u32, DVec2)>, usize)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (1..threads.min(groups.len()))
            .map(|_| scope.spawn(work))
            .collect();
        let mine = work();
        // a sweep that panicked is a defect: let it surface as one
        std::iter::once(mine)
            .chain(
                handles
                    .into_iter()
                    .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e))),
            )
            .collect()
    });
    let mut moved = 0;
    for (placed, m) in results {
        moved += m;
        for (i, p) in placed {
            mesh.nodes[i as usize] = p;
        }
    }
    moved
}

/// Marks every node of these elements dirty: a sweep looks at them again.
pub(crate) fn mark_nodes(mesh: &Mesh, quads: impl Iterator<Item = u32>, dirty: &mut [bool]) {
    for q in quads {
        for m in mesh.quads[q as usize] {
            dirty[m as usize] = true;
        }
    }
}
