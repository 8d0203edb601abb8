//! Unmeshing: a stuck loop gets room by taking back the elements along
//! it, so that the enlarged loop can be split better.

use crate::fallback::slits::zip_slits;
use crate::front::Fv;
use crate::partial_mesh::PartialMesh;
use crate::report::trace::{Angles, By, TraceStep};

/// Takes back every element that shares an edge with loop `l`; the
/// loop grows round them. False if there is none.
pub fn unmesh_layer(pm: &mut PartialMesh, l: u32) -> Option<Vec<Fv>> {
    let edges: Vec<(u32, u32)> = pm
        .front
        .loop_fvs(l)
        .iter()
        .map(|&fv| (pm.front.node(pm.front.next(fv)), pm.front.node(fv)))
        .collect();
    let owner = pm.edge_owners();
    let mut victims: Vec<usize> = edges
        .iter()
        .filter_map(|e| owner.get(e).map(|&q| q as usize))
        .collect();
    victims.sort_unstable();
    victims.dedup();
    if victims.is_empty() {
        return None;
    }
    let mut removed = Vec::new();
    for &qi in &victims {
        let q = pm.mesh.quads[qi];
        // a front edge a->b that the element runs b->a
        let mut found = None;
        for i in 0..4 {
            let (b, a) = (q[i], q[(i + 1) % 4]);
            if let Some(fa) = pm
                .front
                .occurrences(a)
                .find(|&fa| pm.front.node(pm.front.next(fa)) == b)
            {
                found = Some((i, fa));
                break;
            }
        }
        let Some((i, fa)) = found else { continue };
        let fb = pm.front.next(fa);
        let x = q[(i + 2) % 4];
        let y = q[(i + 3) % 4];
        pm.front.begin();
        let layer = pm.front.layer(fa);
        let made = pm.front.replace_path(fa, fb, &[x, y], layer);
        for m in made {
            let node = pm.front.node(m);
            let others: Vec<Fv> = pm.front.occurrences(node).filter(|&o| o != m).collect();
            for o in others {
                if !pm.front.alive(o) || !pm.front.alive(m) {
                    continue;
                }
                if pm.front.loop_of(o) == pm.front.loop_of(m) {
                    // not along an inner line: the loop is left passing
                    // the node twice there
                    if pm.parts_a_line_seam(m, o) {
                        continue;
                    }
                    pm.front.split_pinch(m, o);
                } else {
                    pm.front.join_pinch(m, o);
                }
            }
        }
        if pm.front.touched_loops().iter().any(|&t| {
            pm.front.loop_len(t) % 2 == 1 || (pm.guard_loop_areas && pm.loop_area(t) <= 0.0)
        }) {
            pm.front.rollback();
            continue;
        }
        pm.front.commit(&pm.mesh.nodes);
        removed.push(qi);
    }
    if removed.is_empty() {
        return None;
    }
    removed.sort_unstable();
    for &qi in removed.iter().rev() {
        let q = pm.remove_quad(qi);
        pm.stats.unmeshed += 1;
        pm.note_step(|step| TraceStep {
            step,
            edge: [q[0] as i64, q[1] as i64],
            angles: Angles::default(),
            feature: "stuck".into(),
            action: "unmesh".into(),
            by: By::Unmesh,
            redesign: vec![],
            element: q.iter().map(|&x| x as i64).collect(),
        });
    }
    // edges between two elements taken back bound nothing now
    for t in pm.front.touched_loops() {
        zip_slits(pm, t, false);
    }
    let touched = pm.front.take_touched();
    for &t in &touched {
        if pm.front.alive(t) {
            pm.fallback_only.insert(pm.front.loop_of(t));
        }
    }
    Some(touched)
}
