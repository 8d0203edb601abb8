//! Element quality, measured as the outside judge measures it: corner
//! angles, scaled Jacobian, aspect ratio (ratio of the distances between
//! midpoints of opposite edges), taper (larger ratio of opposite edge
//! lengths), and the size jump between neighbours.

use rustc_hash::FxHashMap;

use crate::element_quality::{aspect_taper, scaled_jacobian};
use crate::geometry::quad_angles;
use crate::mesh::Mesh;
use crate::settings::ElementBounds;

/// Quality figures of a quad mesh.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Quality {
    /// Number of quads.
    pub quads: usize,
    /// Smallest corner angle (deg).
    pub min_angle: f64,
    /// Largest corner angle (deg).
    pub max_angle: f64,
    /// The corner window the share below counts (degrees): the KB's
    /// `bound(lower_corner, _)` and `bound(upper_corner, _)`, [45, 135]
    /// built in.
    pub corner_window: [f64; 2],
    /// Share of quads with every angle in `corner_window`, in percent
    /// (named for the built-in window).
    pub pct_45_135: f64,
    /// Number of quads with a corner outside [45, 135].
    pub outside_45_135: usize,
    /// Smallest scaled Jacobian.
    pub min_scaled_jacobian: f64,
    /// Largest aspect ratio.
    pub max_aspect: f64,
    /// Largest taper.
    pub max_taper: f64,
    /// Largest size jump between neighbours: sqrt of their area ratio.
    pub max_size_jump: f64,
}

/// The quality figures of a mesh, its corners counted against the
/// built-in window [45, 135].
pub fn measure(mesh: &Mesh) -> Quality {
    measure_within(mesh, &ElementBounds::default())
}

/// The quality figures of a mesh, its corners counted against the window
/// of `bounds` (the KB's, for a run).
pub(crate) fn measure_within(mesh: &Mesh, bounds: &ElementBounds) -> Quality {
    let mut q = Quality {
        quads: mesh.quads.len(),
        min_angle: 180.0,
        max_angle: 0.0,
        corner_window: [bounds.lower_corner, bounds.upper_corner],
        pct_45_135: 0.0,
        outside_45_135: 0,
        min_scaled_jacobian: 1.0,
        max_aspect: 1.0,
        max_taper: 1.0,
        max_size_jump: 1.0,
    };
    let mut good = 0usize;
    let mut areas = Vec::with_capacity(mesh.quads.len());
    for i in 0..mesh.quads.len() {
        let p = mesh.quad_points(i);
        let a = quad_angles(p);
        let (lo, hi) = a
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
        q.min_angle = q.min_angle.min(lo);
        q.max_angle = q.max_angle.max(hi);
        if lo >= bounds.lower_corner && hi <= bounds.upper_corner {
            good += 1;
        }
        q.min_scaled_jacobian = q.min_scaled_jacobian.min(scaled_jacobian(p));
        let (asp, tap) = aspect_taper(p);
        q.max_aspect = q.max_aspect.max(asp);
        q.max_taper = q.max_taper.max(tap);
        areas.push(crate::geometry::polygon_area(&p).abs());
    }
    if !mesh.quads.is_empty() {
        q.pct_45_135 = 100.0 * good as f64 / mesh.quads.len() as f64;
    }
    q.outside_45_135 = mesh.quads.len() - good;
    let mut owner: FxHashMap<(u32, u32), u32> =
        FxHashMap::with_capacity_and_hasher(2 * mesh.quads.len(), Default::default());
    for (qi, quad) in mesh.quads.iter().enumerate() {
        for i in 0..4 {
            let (a, b) = (quad[i], quad[(i + 1) % 4]);
            let k = (a.min(b), a.max(b));
            if let Some(&o) = owner.get(&k) {
                let (x, y) = (areas[o as usize], areas[qi]);
                if x > 0.0 && y > 0.0 {
                    q.max_size_jump = q.max_size_jump.max((x.max(y) / x.min(y)).sqrt());
                }
            } else {
                owner.insert(k, qi as u32);
            }
        }
    }
    q
}

/// How many corners fall in each 10-degree bin, 0-10 to 170-180.
pub fn angle_bins(mesh: &Mesh) -> [usize; 18] {
    let mut bins = [0usize; 18];
    for i in 0..mesh.quads.len() {
        for a in quad_angles(mesh.quad_points(i)) {
            bins[((a / 10.0) as usize).min(17)] += 1;
        }
    }
    bins
}

/// A text histogram of corner angles in 10-degree bins.
pub fn angle_histogram(mesh: &Mesh) -> String {
    let bins = angle_bins(mesh);
    let max = *bins.iter().max().unwrap_or(&1).max(&1);
    let mut s = String::new();
    for (i, &b) in bins.iter().enumerate() {
        if b == 0 && (i < 3 || i > 15) {
            continue;
        }
        let bar = "#".repeat((b * 50).div_ceil(max));
        s.push_str(&format!(
            "{:>3}-{:<3} {:>8} {}\n",
            i * 10,
            i * 10 + 10,
            b,
            bar
        ));
    }
    s
}
