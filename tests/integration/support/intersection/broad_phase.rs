//! The broad phase: a uniform grid of bounding boxes, so that only facets
//! whose boxes overlap are compared (near-linear for surfaces of even size).

use std::collections::HashMap;

/// An axis-aligned bounding box.
#[derive(Debug, Clone, Copy)]
pub(super) struct Aabb {
    min: [f64; 3],
    max: [f64; 3],
}

impl Aabb {
    pub(super) fn of<const N: usize>(points: [[f64; 3]; N]) -> Self {
        let pick =
            |k: usize, f: fn(f64, f64) -> f64| points.iter().map(|p| p[k]).fold(points[0][k], f);
        Aabb {
            min: std::array::from_fn(|k| pick(k, f64::min)),
            max: std::array::from_fn(|k| pick(k, f64::max)),
        }
    }
    fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: std::array::from_fn(|k| self.min[k].min(o.min[k])),
            max: std::array::from_fn(|k| self.max[k].max(o.max[k])),
        }
    }
    fn grown(self, margin: f64) -> Aabb {
        Aabb {
            min: self.min.map(|x| x - margin),
            max: self.max.map(|x| x + margin),
        }
    }
    fn extent(&self) -> f64 {
        (0..3)
            .map(|k| self.max[k] - self.min[k])
            .fold(0.0, f64::max)
    }
    fn overlaps(&self, o: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] <= o.max[k] && o.min[k] <= self.max[k])
    }
}

/// The cells of an inclusive range of cell indices per axis.
fn cells_in([x, y, z]: [(i64, i64); 3]) -> impl Iterator<Item = [i64; 3]> {
    (x.0..=x.1)
        .flat_map(move |cx| (y.0..=y.1).flat_map(move |cy| (z.0..=z.1).map(move |cz| [cx, cy, cz])))
}

/// Every `(query, item)` whose boxes are within `margin`, sorted. The items
/// go into a uniform grid of cells about their mean size (doubled while they
/// would fill more than 16 cells each on average); each query looks only at
/// the cells its box covers.
pub(super) fn overlapping_pairs(
    queries: &[Aabb],
    items: &[Aabb],
    margin: f64,
) -> Vec<(usize, usize)> {
    let grown: Vec<Aabb> = items.iter().map(|b| b.grown(margin)).collect();
    let Some(whole) = grown.iter().copied().reduce(Aabb::union) else {
        return Vec::new();
    };
    let mean = grown.iter().map(Aabb::extent).sum::<f64>() / grown.len() as f64;
    // At most ~1e6 cells per axis, so that indices stay small whatever the sizes.
    let mut cell = mean.max(whole.extent() * 1e-6);
    if !(cell > 0.0 && cell.is_finite()) {
        cell = 1.0;
    }
    // Cell indices of a box clipped to the items' box (so queries far out visit none).
    let range = |b: &Aabb, cell: f64| -> [(i64, i64); 3] {
        std::array::from_fn(|k| {
            let index = |x: f64| ((x - whole.min[k]) / cell).floor() as i64;
            (
                index(b.min[k].max(whole.min[k])),
                index(b.max[k].min(whole.max[k])),
            )
        })
    };
    let volume = |r: [(i64, i64); 3]| {
        r.iter()
            .map(|&(lo, hi)| (hi - lo + 1).max(0) as f64)
            .product::<f64>()
    };
    while grown.iter().map(|b| volume(range(b, cell))).sum::<f64>()
        > 16.0 * grown.len() as f64 + 1024.0
    {
        cell *= 2.0;
    }
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, b) in grown.iter().enumerate() {
        for key in cells_in(range(b, cell)) {
            grid.entry(key).or_default().push(i);
        }
    }
    let (mut pairs, mut candidates) = (Vec::new(), Vec::new());
    for (q, query) in queries.iter().enumerate() {
        candidates.clear();
        candidates.extend(
            cells_in(range(query, cell))
                .filter_map(|key| grid.get(&key))
                .flatten(),
        );
        candidates.sort_unstable();
        candidates.dedup();
        pairs.extend(
            candidates
                .iter()
                .filter(|&&i| query.overlaps(&grown[i]))
                .map(|&i| (q, i)),
        );
    }
    pairs
}
