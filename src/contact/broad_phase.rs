//! Broad phase: the pairs of primitives whose (swept) boxes come within the contact distance.
//!
//! # What it computes
//!
//! A box is `B = [min_0, max_0] x ... x [min_{D-1}, max_{D-1}]`, closed. Two
//! boxes overlap when they share a point:
//!
//! ```text
//! overlaps(A, B)  <=>  for every axis k:
//!     A.min_k <= B.max_k  and  B.min_k <= A.max_k  and  A.min_k <= A.max_k  and  B.min_k <= B.max_k
//! ```
//!
//! (the last two terms make an empty box, `min_k > max_k`, overlap nothing).
//! For an inflation `d` (the activation distance `d_hat`), the broad phase
//! reports the pairs `(i, j)` with `overlaps(A_i + d/2, B_j + d/2)`, where
//! `B + r = [min - r, max + r]`: the boxes whose gap is at most `d` on every
//! axis, so every pair of primitives within distance `d` is reported. Each
//! reported pair also passes the caller's `keep(i, j)` filter (shared
//! vertices, same body), which is called exactly once per overlapping pair.
//! The output is sorted by `(i, j)` and has no duplicates, so it depends on
//! the boxes only: the same whatever the order of the work inside.
//!
//! # How: a sort-based uniform grid
//!
//! 1. Cell size along axis `k`: `h_k` = the 90 % quantile over the boxes of
//!    their extent `max_k - min_k` (for two sets, the larger of the two, so
//!    that vertex boxes of size `d` do not make triangle boxes span many
//!    cells); at least `scene extent_k / 2^B` so that cell indices fit in `B`
//!    bits per axis (`B = min(31, 62 / D)`). Per axis, so that boxes swept
//!    along one direction (a falling body) get cells long in that direction
//!    instead of spanning many cubes. A quantile and not the mean, so that a
//!    few huge boxes do not coarsen the grid; a high one, because boxes above
//!    it may go to the slower large list.
//! 2. The cell of a coordinate is `c_k(x) = clamp(floor((x - o_k) / h_k), 0, 2^B - 1)`
//!    with `o` the lowest corner of all boxes. It is non-decreasing in `x`
//!    (floating-point subtraction, scaling and `floor` are monotone), which is
//!    all the correctness needs: if `A` and `B` overlap, the cell
//!    `max(c(A.min), c(B.min))` (componentwise) lies in both boxes' cell ranges.
//! 3. Every box that spans at most [`MAX_CELLS_PER_BOX`] cells writes one entry
//!    `(cell key, box)` per cell; the entries are sorted by key, and the boxes
//!    of each run of equal keys are tested against each other. A pair that
//!    shares several cells is tested in its *owner cell*
//!    `max(c(A.min), c(B.min))` only, so it is found once without a hash set.
//! 4. The other boxes (those spanning more cells, e.g. the swept boxes of a
//!    fast body, and those with infinite coordinates) form the *large* list,
//!    so memory stays at most [`MAX_CELLS_PER_BOX`] entries per box. Each large
//!    box is swept against the gridded boxes of the other set, sorted by
//!    `min_a` along one axis `a` (the one where the large boxes are thinnest
//!    relative to the scene): a gridded box `S` can overlap a large box `L`
//!    only if `L.min_a - 2 e_a <= S.min_a <= L.max_a`, `e_a` the largest
//!    extent of the gridded boxes along `a` (the factor 2 covers the rounding
//!    of the extents: rounding is monotone, and `fl(max - min) >= (max - min)(1 - 2^-53)`).
//!    Large boxes are tested against each other directly; there are few.
//!
//! The cost is `O(n log n)` for the sorts plus the tests within cells, which
//! for boxes of similar size is `O(n + pairs)`; there is no `O(n^2)` term
//! unless most boxes are large or share a cell (then the output itself is
//! large). The buffers live in [`BroadPhase`] and keep their capacity between
//! calls, so a warm call does not allocate. It runs on one thread.
//!
//! # Degenerate boxes
//!
//! A box with a NaN coordinate, or an empty one (`min_k > max_k` on some axis,
//! as [`Aabb::empty`]), overlaps nothing and pairs with nothing; a NaN
//! position poisons the box of every primitive it belongs to (see
//! [`Aabb::union_point`]). A non-empty box with infinite coordinates is a
//! genuine unbounded box: it goes to the large list and pairs with every box
//! it overlaps. A NaN inflation therefore gives no pairs; a negative one
//! shrinks the boxes. Nothing here loops on or panics over such input; the
//! only panic is for more than `2^31 - 1` boxes (indices are `u32`).
//!
//! # Why not a crate
//!
//! Checked on docs.rs: `bvh` (svenstaro) builds a new `Bvh` from
//! `&mut [Shape]` whose shapes must implement `BHShape` (they store their node
//! index), and its queries take one ray or shape at a time (`traverse` returns
//! a `Vec`, `traverse_iterator` does not allocate); it has no tree-against-tree
//! or self-pair query, and its published manifest depends on nalgebra 0.33,
//! not our 0.35, so its points would be a second nalgebra's types.
//! `parry3d-f64` has a `Bvh` with a self-pair traversal
//! (`traverse_bvtt_single_tree`, a callback per pair of overlapping leaves),
//! but since 0.26 it speaks glam (`DVec3`) instead of nalgebra, and it is 3D
//! only (2D is the separate `parry2d-f64`), so it cannot be generic over
//! `const D`. Either way we would still sort and filter the pairs ourselves;
//! the grid above is short, generic over `D`, allocation-free when warm and
//! exact (every overlapping pair, once).

use crate::math::Vector;

/// A box spanning more grid cells than this goes to the large list.
pub const MAX_CELLS_PER_BOX: u64 = 32;

/// The cell size along each axis is this quantile of the boxes' extents
/// along it.
const CELL_QUANTILE: f64 = 0.9;

/// An axis-aligned box `[min, max]` (closed). Empty when `min_k > max_k` on
/// some axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb<const D: usize> {
    /// Lowest corner.
    pub min: Vector<D>,
    /// Highest corner.
    pub max: Vector<D>,
}

impl<const D: usize> Aabb<D> {
    /// The empty box (`min = +inf`, `max = -inf`): the identity of
    /// [`Aabb::union_point`]; it overlaps nothing.
    pub fn empty() -> Self {
        Self {
            min: Vector::repeat(f64::INFINITY),
            max: Vector::repeat(f64::NEG_INFINITY),
        }
    }

    /// The smallest box holding `self` and `point`. A NaN coordinate of the
    /// point makes that axis NaN for good (NaN is never dropped), so the box
    /// overlaps nothing.
    pub fn union_point(&self, point: &Vector<D>) -> Self {
        let mut out = *self;
        for k in 0..D {
            let p = point[k];
            if p < out.min[k] || p.is_nan() {
                out.min[k] = p;
            }
            if p > out.max[k] || p.is_nan() {
                out.max[k] = p;
            }
        }
        out
    }

    /// The tight box of `points` ([`Aabb::empty`] for none).
    pub fn of_points(points: &[Vector<D>]) -> Self {
        points.iter().fold(Self::empty(), |b, p| b.union_point(p))
    }

    /// The box of the points at both ends of a motion, `start[v] -> end[v]`:
    /// it holds every point of every straight segment between them.
    pub fn swept(start: &[Vector<D>], end: &[Vector<D>]) -> Self {
        start
            .iter()
            .chain(end)
            .fold(Self::empty(), |b, p| b.union_point(p))
    }

    /// The box grown by `by` on every side: `[min - by, max + by]`.
    pub fn inflated(&self, by: f64) -> Self {
        Self {
            min: self.min.add_scalar(-by),
            max: self.max.add_scalar(by),
        }
    }

    /// Whether the two closed boxes share a point (false if either is empty
    /// or has a NaN coordinate).
    pub fn overlaps(&self, other: &Self) -> bool {
        (0..D).all(|k| {
            self.min[k] <= other.max[k]
                && other.min[k] <= self.max[k]
                && self.min[k] <= self.max[k]
                && other.min[k] <= other.max[k]
        })
    }

    /// Non-empty and free of NaN.
    fn is_valid(&self) -> bool {
        (0..D).all(|k| self.min[k] <= self.max[k])
    }

    /// All coordinates finite.
    fn is_finite(&self) -> bool {
        self.min
            .iter()
            .chain(self.max.iter())
            .all(|v| v.is_finite())
    }
}

/// Bits of a cell index per axis: the `D` indices pack into one `u64` key.
const fn axis_bits(d: usize) -> u32 {
    let bits = 62 / d as u32;
    if bits > 31 { 31 } else { bits }
}

/// Tag bit marking an entry of the second set in `pairs_between`.
const SECOND_SET: u32 = 1 << 31;

/// The uniform grid: origin and cell size.
#[derive(Clone, Copy)]
struct Grid<const D: usize> {
    origin: Vector<D>,
    inverse_cell: Vector<D>,
}

impl<const D: usize> Grid<D> {
    const CELLS_PER_AXIS: u32 = 1 << axis_bits(D);

    /// Cell indices of a finite point, clamped to the grid.
    fn cell(&self, p: &Vector<D>) -> [u32; D] {
        let last = f64::from(Self::CELLS_PER_AXIS - 1);
        std::array::from_fn(|k| {
            let c = ((p[k] - self.origin[k]) * self.inverse_cell[k]).floor();
            c.clamp(0.0, last) as u32
        })
    }

    /// The `u64` key of a cell.
    fn key(cell: &[u32; D]) -> u64 {
        cell.iter().enumerate().fold(0, |key, (k, &c)| {
            key | (u64::from(c) << (axis_bits(D) * k as u32))
        })
    }
}

/// One set of boxes, inflated, sorted into grid and large list.
struct BoxSet<const D: usize> {
    /// The inflated boxes, by index.
    boxes: Vec<Aabb<D>>,
    /// Lowest cell of each gridded box (meaningless for the others).
    first_cell: Vec<[u32; D]>,
    /// Indices of the boxes in the grid.
    gridded: Vec<u32>,
    /// Indices of the boxes in the large list.
    large: Vec<u32>,
    /// Largest extent of a gridded box, per axis.
    gridded_extent: Vector<D>,
    /// `gridded`, sorted by `min` along the sweep axis (filled when needed).
    by_min: Vec<u32>,
}

impl<const D: usize> BoxSet<D> {
    fn new() -> Self {
        Self {
            boxes: Vec::new(),
            first_cell: Vec::new(),
            gridded: Vec::new(),
            large: Vec::new(),
            gridded_extent: Vector::zeros(),
            by_min: Vec::new(),
        }
    }

    /// Copies `boxes` grown by `by`.
    fn load(&mut self, boxes: &[Aabb<D>], by: f64) {
        assert!(
            boxes.len() < SECOND_SET as usize,
            "broad phase: at most 2^31 - 1 boxes"
        );
        self.boxes.clear();
        self.boxes.extend(boxes.iter().map(|b| b.inflated(by)));
    }

    /// Per axis `k`, the [`CELL_QUANTILE`] of the extents `max_k - min_k` of
    /// the valid finite boxes (0 for none); `extents` is scratch.
    fn typical_extent(&self, extents: &mut Vec<f64>) -> Vector<D> {
        Vector::from_fn(|k, _| {
            extents.clear();
            extents.extend(
                self.boxes
                    .iter()
                    .filter(|b| b.is_valid() && b.is_finite())
                    .map(|b| b.max[k] - b.min[k]),
            );
            if extents.is_empty() {
                return 0.0;
            }
            let rank = (extents.len() as f64 * CELL_QUANTILE) as usize;
            *extents.select_nth_unstable_by(rank, f64::total_cmp).1
        })
    }

    /// Puts each valid box in the grid (one entry per cell, tagged with
    /// `tag`) or in the large list.
    fn fill_grid(&mut self, grid: &Grid<D>, tag: u32, entries: &mut Vec<(u64, u32)>) {
        self.gridded.clear();
        self.large.clear();
        self.first_cell.clear();
        self.first_cell.resize(self.boxes.len(), [0; D]);
        self.gridded_extent = Vector::zeros();
        for (i, b) in self.boxes.iter().enumerate() {
            if !b.is_valid() {
                continue;
            }
            if !b.is_finite() {
                self.large.push(i as u32);
                continue;
            }
            let (lo, hi) = (grid.cell(&b.min), grid.cell(&b.max));
            let cells = (0..D).fold(1u64, |n, k| n.saturating_mul(u64::from(hi[k] - lo[k]) + 1));
            if cells > MAX_CELLS_PER_BOX {
                self.large.push(i as u32);
                continue;
            }
            self.gridded.push(i as u32);
            self.first_cell[i] = lo;
            self.gridded_extent = self.gridded_extent.sup(&(b.max - b.min));
            let mut cell = lo;
            'cells: loop {
                entries.push((Grid::<D>::key(&cell), i as u32 | tag));
                for k in 0..D {
                    if cell[k] < hi[k] {
                        cell[k] += 1;
                        continue 'cells;
                    }
                    cell[k] = lo[k];
                }
                break;
            }
        }
    }

    /// Fills `by_min`: the gridded boxes sorted by `min` along `axis`.
    fn sort_by_min(&mut self, axis: usize) {
        self.by_min.clear();
        self.by_min.extend_from_slice(&self.gridded);
        let boxes = &self.boxes;
        self.by_min.sort_unstable_by(|&a, &b| {
            boxes[a as usize].min[axis].total_cmp(&boxes[b as usize].min[axis])
        });
    }

    /// Calls `found(s)` for each gridded box `s` that overlaps `large` (by
    /// `sort_by_min(axis)` first).
    fn sweep(&self, large: &Aabb<D>, axis: usize, mut found: impl FnMut(usize)) {
        let lowest = large.min[axis] - 2.0 * self.gridded_extent[axis];
        let min_of = |s: &u32| self.boxes[*s as usize].min[axis];
        let start = self.by_min.partition_point(|s| min_of(s) < lowest);
        let end = self
            .by_min
            .partition_point(|s| min_of(s) <= large.max[axis]);
        for &s in &self.by_min[start..end.max(start)] {
            if self.boxes[s as usize].overlaps(large) {
                found(s as usize);
            }
        }
    }
}

/// Reusable broad phase: holds its scratch buffers, so that calls after the
/// first do not allocate (for inputs no larger than before).
pub struct BroadPhase<const D: usize> {
    first: BoxSet<D>,
    second: BoxSet<D>,
    /// `(cell key, box index | set tag)`, sorted.
    entries: Vec<(u64, u32)>,
    /// Scratch for the extent quantiles.
    extents: Vec<f64>,
}

impl<const D: usize> Default for BroadPhase<D> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const D: usize> BroadPhase<D> {
    /// A broad phase with empty buffers.
    pub fn new() -> Self {
        Self {
            first: BoxSet::new(),
            second: BoxSet::new(),
            entries: Vec::new(),
            extents: Vec::new(),
        }
    }

    /// Every `(i, j)` with `boxes_a[i]` and `boxes_b[j]` overlapping after both
    /// are inflated by `inflation / 2` (their gap is at most `inflation`), for
    /// which `keep(i, j)` is true; written to `pairs` (cleared first) sorted by
    /// `(i, j)`, no duplicates. `keep` is called once per overlapping pair.
    pub fn pairs_between(
        &mut self,
        boxes_a: &[Aabb<D>],
        boxes_b: &[Aabb<D>],
        inflation: f64,
        keep: impl Fn(usize, usize) -> bool,
        pairs: &mut Vec<(u32, u32)>,
    ) {
        pairs.clear();
        let (first, second) = (&mut self.first, &mut self.second);
        first.load(boxes_a, inflation / 2.0);
        second.load(boxes_b, inflation / 2.0);
        let cell = first
            .typical_extent(&mut self.extents)
            .sup(&second.typical_extent(&mut self.extents));
        let (grid, scene) = fit_grid(&[&first.boxes, &second.boxes], cell);
        self.entries.clear();
        first.fill_grid(&grid, 0, &mut self.entries);
        second.fill_grid(&grid, SECOND_SET, &mut self.entries);
        self.entries
            .sort_unstable_by_key(|&(key, tag)| (u128::from(key) << 32) | u128::from(tag));

        for run in self.entries.chunk_by(|x, y| x.0 == y.0) {
            let split = run.partition_point(|e| e.1 & SECOND_SET == 0);
            let (in_first, in_second) = run.split_at(split);
            for &(key, a) in in_first {
                let (a, box_a) = (a as usize, &first.boxes[a as usize]);
                for &(_, b) in in_second {
                    let b = (b & !SECOND_SET) as usize;
                    if owner_key(&first.first_cell[a], &second.first_cell[b]) == key
                        && box_a.overlaps(&second.boxes[b])
                        && keep(a, b)
                    {
                        pairs.push((a as u32, b as u32));
                    }
                }
            }
        }

        if !first.large.is_empty() || !second.large.is_empty() {
            let axis = sweep_axis(&[first, second], &scene);
            let mut push = |a: usize, b: usize| {
                if keep(a, b) {
                    pairs.push((a as u32, b as u32));
                }
            };
            if !first.large.is_empty() {
                second.sort_by_min(axis);
                for &l in &first.large {
                    second.sweep(&first.boxes[l as usize], axis, |s| push(l as usize, s));
                }
            }
            if !second.large.is_empty() {
                first.sort_by_min(axis);
                for &l in &second.large {
                    first.sweep(&second.boxes[l as usize], axis, |s| push(s, l as usize));
                }
            }
            for &a in &first.large {
                for &b in &second.large {
                    if first.boxes[a as usize].overlaps(&second.boxes[b as usize]) {
                        push(a as usize, b as usize);
                    }
                }
            }
        }
        sort_pairs(pairs);
    }

    /// The same within one set: every `(i, j)` with `i < j`, `boxes[i]` and
    /// `boxes[j]` within `inflation` of each other and `keep(i, j)` true,
    /// sorted, no duplicates.
    pub fn pairs_within(
        &mut self,
        boxes: &[Aabb<D>],
        inflation: f64,
        keep: impl Fn(usize, usize) -> bool,
        pairs: &mut Vec<(u32, u32)>,
    ) {
        pairs.clear();
        let set = &mut self.first;
        set.load(boxes, inflation / 2.0);
        let (grid, scene) = fit_grid(&[&set.boxes], set.typical_extent(&mut self.extents));
        self.entries.clear();
        set.fill_grid(&grid, 0, &mut self.entries);
        self.entries
            .sort_unstable_by_key(|&(key, tag)| (u128::from(key) << 32) | u128::from(tag));

        for run in self.entries.chunk_by(|x, y| x.0 == y.0) {
            for (n, &(key, i)) in run.iter().enumerate() {
                let (i, box_i) = (i as usize, &set.boxes[i as usize]);
                for &(_, j) in &run[n + 1..] {
                    let j = j as usize;
                    if owner_key(&set.first_cell[i], &set.first_cell[j]) == key
                        && box_i.overlaps(&set.boxes[j])
                    {
                        let (i, j) = (i.min(j), i.max(j));
                        if keep(i, j) {
                            pairs.push((i as u32, j as u32));
                        }
                    }
                }
            }
        }

        if !set.large.is_empty() {
            let axis = sweep_axis(&[set], &scene);
            set.sort_by_min(axis);
            let mut push = |i: usize, j: usize| {
                let (i, j) = (i.min(j), i.max(j));
                if keep(i, j) {
                    pairs.push((i as u32, j as u32));
                }
            };
            for &l in &set.large {
                set.sweep(&set.boxes[l as usize], axis, |s| push(l as usize, s));
            }
            for (n, &a) in set.large.iter().enumerate() {
                for &b in &set.large[n + 1..] {
                    if set.boxes[a as usize].overlaps(&set.boxes[b as usize]) {
                        push(a as usize, b as usize);
                    }
                }
            }
        }
        sort_pairs(pairs);
    }
}

/// Sorts by `(i, j)` (as one `u64`: a single comparison).
fn sort_pairs(pairs: &mut [(u32, u32)]) {
    pairs.sort_unstable_by_key(|&(i, j)| (u64::from(i) << 32) | u64::from(j));
}

/// The key of the cell where a pair is tested: the componentwise maximum of
/// the two boxes' lowest cells (the cell of the lowest corner of their
/// intersection).
fn owner_key<const D: usize>(a: &[u32; D], b: &[u32; D]) -> u64 {
    Grid::<D>::key(&std::array::from_fn(|k| a[k].max(b[k])))
}

/// The grid for the given (inflated) box sets, and the extent of the scene
/// per axis: origin at the lowest corner of their valid finite boxes, cell
/// sizes `cell`, raised where needed so that the scene fits in the grid's
/// index range; an axis with no positive size takes the largest of the
/// others (or the scene's size, or 1).
fn fit_grid<const D: usize>(sets: &[&[Aabb<D>]], cell: Vector<D>) -> (Grid<D>, Vector<D>) {
    let scene = sets
        .iter()
        .flat_map(|set| set.iter())
        .filter(|b| b.is_valid() && b.is_finite())
        .fold(Aabb::<D>::empty(), |s, b| Aabb {
            min: s.min.inf(&b.min),
            max: s.max.sup(&b.max),
        });
    if !scene.is_valid() {
        // No finite box: nothing goes in the grid.
        let grid = Grid {
            origin: Vector::zeros(),
            inverse_cell: Vector::repeat(1.0),
        };
        return (grid, Vector::zeros());
    }
    let extent = scene.max - scene.min;
    let fallback = [cell.max(), extent.max(), 1.0]
        .into_iter()
        .find(|&h| h > 0.0 && h.is_finite())
        .unwrap_or(1.0);
    let inverse_cell = Vector::from_fn(|k, _| {
        let h = cell[k].max(extent[k] / f64::from(Grid::<D>::CELLS_PER_AXIS));
        let h = if h > 0.0 && h.is_finite() {
            h
        } else {
            fallback
        };
        1.0 / h
    });
    let grid = Grid {
        origin: scene.min,
        inverse_cell,
    };
    (grid, extent)
}

/// The axis along which the large boxes are thinnest relative to the scene
/// (`scene` = its extent per axis): `argmin_k sum_large min(1, extent_k / scene_k)`,
/// so that the sweep window of each large box holds few gridded boxes.
fn sweep_axis<const D: usize>(sets: &[&BoxSet<D>], scene: &Vector<D>) -> usize {
    let score = |k: usize| -> f64 {
        sets.iter()
            .flat_map(|s| s.large.iter().map(|&l| &s.boxes[l as usize]))
            .map(|b| {
                let ratio = (b.max[k] - b.min[k]) / scene[k];
                // NaN (0 / 0, inf - inf) counts as spanning the whole scene.
                if ratio < 1.0 { ratio } else { 1.0 }
            })
            .sum()
    };
    (0..D)
        .map(|k| (k, score(k)))
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .map_or(0, |(k, _)| k)
}

#[cfg(test)]
mod tests;
