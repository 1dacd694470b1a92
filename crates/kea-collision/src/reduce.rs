//! Contact reduction: from a manifold's points keep at most `max_points`. The deepest point
//! comes first (one point is enough to bounce); each next one is the point farthest from those
//! already kept, so three or four span the support area and a box rests on its corners.

use kea::{Real, Vec3};

/// Writes into `keep` the indices of the points to keep, at most `max_points`.
pub(crate) fn reduce(points: &[(Vec3, Real)], max_points: usize, keep: &mut Vec<usize>) {
    keep.clear();
    if points.len() <= max_points {
        keep.extend(0..points.len());
        return;
    }
    let deepest = (0..points.len())
        .max_by(|&a, &b| points[a].1.total_cmp(&points[b].1))
        .unwrap_or(0);
    keep.push(deepest);
    while keep.len() < max_points {
        let mut best = None;
        let mut best_distance = -1.0;
        for (i, (p, _)) in points.iter().enumerate() {
            if keep.contains(&i) {
                continue;
            }
            let nearest = keep
                .iter()
                .map(|&k| (points[k].0 - *p).length_squared())
                .fold(Real::INFINITY, Real::min);
            if nearest > best_distance {
                best_distance = nearest;
                best = Some(i);
            }
        }
        match best {
            Some(i) => keep.push(i),
            None => break,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_the_deepest_then_the_corners() {
        // A face of 8 points: 4 corners and 4 edge midpoints; the deepest is a midpoint.
        let pts = [
            (Vec3::new(-1.0, 0.0, -1.0), 0.01),
            (Vec3::new(1.0, 0.0, -1.0), 0.01),
            (Vec3::new(1.0, 0.0, 1.0), 0.01),
            (Vec3::new(-1.0, 0.0, 1.0), 0.01),
            (Vec3::new(0.0, 0.0, -1.0), 0.02),
            (Vec3::new(1.0, 0.0, 0.0), 0.01),
            (Vec3::new(0.0, 0.0, 1.0), 0.01),
            (Vec3::new(-1.0, 0.0, 0.0), 0.01),
        ];
        let mut keep = Vec::new();
        reduce(&pts, 1, &mut keep);
        assert_eq!(keep, vec![4]);
        reduce(&pts, 4, &mut keep);
        // Deepest, then the two far corners, then a near corner: they span the face.
        assert_eq!(keep, vec![4, 2, 3, 0]);
    }
}
