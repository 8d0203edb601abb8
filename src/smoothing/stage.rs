//! The smoothing stage: guarded Laplace (Eq. 4), then untangling and the
//! evening out of sizes, over the whole mesh or round a few changes.

use crate::mesh::Mesh;
use crate::settings::ElementBounds;
use crate::size_field::SizeField;
use crate::smoothing::laplace::laplace_sweeps;
use crate::smoothing::sizes::even_out_sweeps;
use crate::smoothing::strips::{across, element_neighbours, node_elements, sweep_in_strips, Nodes};
use crate::smoothing::untangle::untangle_sweeps;

/// The smoothing stage: `laplace_passes` sweeps of guarded Laplace, then
/// the angle clean-up and the evening out of sizes, 10 sweeps each; a
/// large mesh strip by strip (see `sweep_in_strips`), all three on a strip
/// before the next. The corners, shapes and sizes aimed for are
/// `bounds`; Laplace weighted by a graded run's field where `weights`
/// (laplace.rs). Returns the moves kept.
pub fn smooth(
    mesh: &mut Mesh,
    laplace_passes: usize,
    bounds: &ElementBounds,
    weights: Option<&SizeField>,
) -> usize {
    let around = node_elements(mesh);
    let neighbours = element_neighbours(mesh, &around);
    sweep_in_strips(mesh, around, |mesh, nodes, dirty| {
        all_sweeps(
            mesh,
            [laplace_passes, 10],
            nodes,
            &neighbours,
            dirty,
            bounds,
            weights,
        )
    })
}

/// The smoothing stage again, on the nodes within a few elements of
/// `near` only: after a change there, the rest is as it was.
pub fn smooth_near(
    mesh: &mut Mesh,
    laplace_passes: usize,
    near: &[u32],
    bounds: &ElementBounds,
    weights: Option<&SizeField>,
) -> usize {
    let around = node_elements(mesh);
    let mut band = vec![false; mesh.nodes.len()];
    let mut visit: Vec<u32> = near.to_vec();
    for &n in near {
        band[n as usize] = true;
    }
    for _ in 0..2 {
        let ring: Vec<u32> = visit
            .iter()
            .flat_map(|&n| {
                around[n as usize]
                    .iter()
                    .flat_map(|&(q, _)| mesh.quads[q as usize])
            })
            .filter(|&m| !band[m as usize])
            .collect();
        for &m in &ring {
            band[m as usize] = true;
        }
        visit.extend(ring);
    }
    visit.sort_unstable();
    visit.dedup();
    // the neighbours of the elements the sweeps look at, and of theirs
    let mut neighbours = vec![[None; 4]; mesh.quads.len()];
    let mut quads: Vec<u32> = visit
        .iter()
        .flat_map(|&n| around[n as usize].iter().map(|&(q, _)| q))
        .collect();
    for _ in 0..2 {
        let mut more = Vec::new();
        for &q in &quads {
            let quad = mesh.quads[q as usize];
            let nb: [Option<u32>; 4] =
                std::array::from_fn(|i| across(mesh, &around, quad[i], quad[(i + 1) % 4]));
            more.extend(nb.iter().flatten());
            neighbours[q as usize] = nb;
        }
        quads = more;
    }
    let nodes = Nodes {
        around: &around,
        visit: &visit,
    };
    let mut dirty = band;
    all_sweeps(
        mesh,
        [laplace_passes, 4],
        &nodes,
        &neighbours,
        &mut dirty,
        bounds,
        weights,
    )
}

/// The three sweeps of the stage in turn over `nodes`, each from the
/// nodes marked dirty at the start: `passes` of Laplace, then of each of
/// the others.
pub(crate) fn all_sweeps(
    mesh: &mut Mesh,
    [laplace_passes, passes]: [usize; 2],
    nodes: &Nodes,
    neighbours: &[[Option<u32>; 4]],
    dirty: &mut [bool],
    bounds: &ElementBounds,
    weights: Option<&SizeField>,
) -> usize {
    let start: Vec<bool> = nodes.visit.iter().map(|&i| dirty[i as usize]).collect();
    let restart = |dirty: &mut [bool]| {
        for (&i, &d) in nodes.visit.iter().zip(&start) {
            dirty[i as usize] = d;
        }
    };
    let mut moved = laplace_sweeps(mesh, laplace_passes, nodes, dirty, bounds, weights);
    restart(dirty);
    moved += untangle_sweeps(mesh, passes, nodes, dirty, bounds);
    restart(dirty);
    moved + even_out_sweeps(mesh, passes, nodes, neighbours, dirty, bounds)
}
