//! The size field of a graded run: the element size aimed for at any
//! point, fine at the boundary and coarser inside (the paper's third
//! requirement). At a point p it is
//!
//! ```text
//! min(max_size, min over boundary segments s of (|s| + growth * dist(p, s)))
//! ```
//!
//! so it starts at each segment's own length (fixed segment counts
//! included) and grows linearly away from the boundary, never above
//! `max_size`. The front asks it at every edge it classifies, so the
//! segments sit in a grid of buckets and a query looks only at the rings
//! of buckets that can still hold a smaller value.

use glam::DVec2;

/// The target element size at any point of the domain.
#[derive(Debug, Clone)]
pub struct SizeField {
    segments: Vec<(DVec2, DVec2, f64)>,
    /// Segment indices by bucket, row-major.
    buckets: Vec<Vec<u32>>,
    origin: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    shortest: f64,
    growth: f64,
    max_size: f64,
}

fn dist_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared().max(1e-300)).clamp(0.0, 1.0);
    (a + ab * t - p).length()
}

impl SizeField {
    /// The field of the boundary `segments` (pairs of end points), growing
    /// by `growth` (size gained per unit of distance) up to `max_size`.
    /// None when there is nothing to grade (no segment, no growth, or no
    /// finite limit).
    pub fn new(segments: Vec<(DVec2, DVec2)>, growth: f64, max_size: f64) -> Option<SizeField> {
        if segments.is_empty() || !(growth > 0.0) || !max_size.is_finite() {
            return None;
        }
        let segments: Vec<(DVec2, DVec2, f64)> = segments
            .into_iter()
            .map(|(a, b)| (a, b, (b - a).length()))
            .collect();
        let shortest = segments.iter().map(|s| s.2).fold(f64::INFINITY, f64::min);
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for &(a, b, _) in &segments {
            lo = lo.min(a.min(b));
            hi = hi.max(a.max(b));
        }
        let extent = (hi - lo).max_element().max(1e-300);
        // about 64 buckets across the longer side, none smaller than a
        // typical segment
        let mean = segments.iter().map(|s| s.2).sum::<f64>() / segments.len() as f64;
        let cell = (extent / 64.0).max(mean);
        let nx = ((hi.x - lo.x) / cell).floor() as usize + 1;
        let ny = ((hi.y - lo.y) / cell).floor() as usize + 1;
        let mut buckets = vec![Vec::new(); nx * ny];
        for (i, &(a, b, _)) in segments.iter().enumerate() {
            let (s0, s1) = (a.min(b), a.max(b));
            let (x0, y0) = (
                ((s0.x - lo.x) / cell) as usize,
                ((s0.y - lo.y) / cell) as usize,
            );
            let (x1, y1) = (
                (((s1.x - lo.x) / cell) as usize).min(nx - 1),
                (((s1.y - lo.y) / cell) as usize).min(ny - 1),
            );
            for y in y0..=y1 {
                for x in x0..=x1 {
                    buckets[y * nx + x].push(i as u32);
                }
            }
        }
        Some(SizeField {
            segments,
            buckets,
            origin: lo,
            cell,
            nx,
            ny,
            shortest,
            growth,
            max_size,
        })
    }

    /// The largest size it aims for (the run's `max_size`).
    pub fn max_size(&self) -> f64 {
        self.max_size
    }

    /// The target size at `p`.
    pub fn at(&self, p: DVec2) -> f64 {
        let mut best = self.max_size;
        let q = (p - self.origin) / self.cell;
        let (cx, cy) = (q.x.floor() as i64, q.y.floor() as i64);
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        // distance from p to the outside of ring k's inner square is at
        // least (k - 1) cells; stop once no segment there can beat `best`
        let outside = |v: i64, n: i64| v < 0 || v >= n;
        let far = (nx.max(ny) + cx.abs().max(cy.abs())) + 1;
        for k in 0..=far {
            let reach = (k - 1).max(0) as f64 * self.cell;
            if self.shortest + self.growth * reach >= best {
                break;
            }
            for y in cy - k..=cy + k {
                if outside(y, ny) {
                    continue;
                }
                let step = if y == cy - k || y == cy + k {
                    1
                } else {
                    (2 * k).max(1)
                };
                let mut x = cx - k;
                while x <= cx + k {
                    if !outside(x, nx) {
                        for &i in &self.buckets[(y * nx + x) as usize] {
                            let (a, b, l) = self.segments[i as usize];
                            let v = l + self.growth * dist_to_segment(p, a, b);
                            best = best.min(v);
                        }
                    }
                    x += step;
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(n: usize, side: f64) -> Vec<(DVec2, DVec2)> {
        let c = [
            DVec2::ZERO,
            DVec2::new(side, 0.0),
            DVec2::new(side, side),
            DVec2::new(0.0, side),
        ];
        let mut out = Vec::new();
        for k in 0..4 {
            for i in 0..n {
                let (a, b) = (c[k], c[(k + 1) % 4]);
                out.push((
                    a.lerp(b, i as f64 / n as f64),
                    a.lerp(b, (i + 1) as f64 / n as f64),
                ));
            }
        }
        out
    }

    #[test]
    fn the_field_grows_from_the_boundary_up_to_the_limit() {
        let segs = square(10, 10.0);
        let f = SizeField::new(segs.clone(), 0.5, 3.0).unwrap();
        // on the boundary: the segment's own length
        assert!((f.at(DVec2::new(5.0, 0.0)) - 1.0).abs() < 1e-12);
        // two units in: 1 + 0.5 * 2
        assert!((f.at(DVec2::new(5.0, 2.0)) - 2.0).abs() < 1e-12);
        // the centre: capped
        assert_eq!(f.at(DVec2::new(5.0, 5.0)), 3.0);
        // the same as the brute force everywhere on a grid
        for i in 0..=20 {
            for j in 0..=20 {
                let p = DVec2::new(i as f64 * 0.5, j as f64 * 0.5);
                let brute = segs
                    .iter()
                    .map(|&(a, b)| (b - a).length() + 0.5 * dist_to_segment(p, a, b))
                    .fold(3.0f64, f64::min);
                assert!(
                    (f.at(p) - brute).abs() < 1e-12,
                    "at {p}: {} vs {brute}",
                    f.at(p)
                );
            }
        }
    }

    #[test]
    fn a_field_with_no_growth_is_none() {
        assert!(SizeField::new(square(4, 1.0), 0.0, 3.0).is_none());
        assert!(SizeField::new(Vec::new(), 0.5, 3.0).is_none());
    }
}
