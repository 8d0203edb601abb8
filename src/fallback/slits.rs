//! Slits and pinches: where fronts met, a loop can run along an edge and
//! back (a slit bounding nothing) or pass a node twice (two loops
//! touching); zipping the slit or parting the loop there gives loops the
//! rules and the chords can close.

use glam::DVec2;
use rustc_hash::FxHashMap as HashMap;

use crate::front::Fv;
use crate::geometry::polygon_area;
use crate::mesh::{Mesh, NodeKind};
use crate::partial_mesh::PartialMesh;

/// Whether the front edge a-b, met both ways, bounds nothing: elements
/// on both sides (fronts that met), or none on either side and not an
/// input line (left where elements were taken back). An inner line of
/// the input, with no element yet, bounds the domain on both sides.
fn slit_is_inside(mesh: &Mesh, owner: &HashMap<(u32, u32), u32>, a: u32, b: u32) -> bool {
    let owned = (owner.contains_key(&(a, b)), owner.contains_key(&(b, a)));
    let input = |n: u32| mesh.kinds[n as usize] == NodeKind::Boundary;
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
pub fn zip_slits(pm: &mut PartialMesh, l: u32, pinches: bool) -> (bool, Vec<u32>) {
    let mut zipped = false;
    let mut open = vec![l];
    let mut done = Vec::new();
    pm.edge_owners();
    while let Some(l) = open.pop() {
        // a slit (an edge there and back bounding nothing), or else a
        // node the loop passes twice
        let slit = pm.edge_owners_if_kept().and_then(|owner| {
            pm.front.loop_fvs(l).into_iter().find_map(|fv| {
                let (p, n) = (pm.front.prev(fv), pm.front.next(fv));
                let (a, b) = (pm.front.node(p), pm.front.node(fv));
                (p != n && pm.front.node(n) == a && slit_is_inside(&pm.mesh, owner, a, b))
                    .then_some((p, n))
            })
        });
        match slit.or_else(|| pinches.then(|| pinch_to_split(pm, l)).flatten()) {
            Some((u, v)) => {
                pm.front.begin();
                let rest = pm.front.split_pinch(u, v);
                pm.front.commit(&pm.mesh.nodes);
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
fn pinch_to_split(pm: &PartialMesh, l: u32) -> Option<(Fv, Fv)> {
    let fvs = pm.front.loop_fvs(l);
    let at = |i: usize| pm.mesh.nodes[pm.front.node(fvs[i % fvs.len()]) as usize];
    let index: HashMap<Fv, usize> = fvs.iter().enumerate().map(|(i, &f)| (f, i)).collect();
    for (i, &u) in fvs.iter().enumerate() {
        for v in pm.front.occurrences(pm.front.node(u)) {
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
