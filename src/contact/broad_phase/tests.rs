//! Tests of `broad_phase`.

use super::*;
use std::cell::Cell;

/// splitmix64, uniform in [0, 1).
struct Rng(u64);
impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// A multiple of 1/64 in [0, n/64).
    fn lattice(&mut self, n: f64) -> f64 {
        (self.uniform() * n).floor() / 64.0
    }
}

const INFLATION: f64 = 1.0 / 64.0;

/// Corners on the 1/64 lattice (exact arithmetic, so many pairs touch at
/// exactly the inflation distance): 15 % zero-size, 80 % up to 3/64 wide,
/// 5 % huge (up to 8 wide, in a unit scene).
fn random_boxes<const D: usize>(rng: &mut Rng, n: usize) -> Vec<Aabb<D>> {
    (0..n)
        .map(|_| {
            let kind = rng.uniform();
            let min = Vector::<D>::from_fn(|_, _| rng.lattice(64.0));
            let size = Vector::<D>::from_fn(|_, _| match kind {
                k if k < 0.15 => 0.0,
                k if k < 0.95 => rng.lattice(4.0),
                _ => rng.lattice(512.0),
            });
            Aabb {
                min,
                max: min + size,
            }
        })
        .collect()
}

fn brute_between<const D: usize>(
    a: &[Aabb<D>],
    b: &[Aabb<D>],
    inflation: f64,
    keep: impl Fn(usize, usize) -> bool,
) -> Vec<(u32, u32)> {
    let h = inflation / 2.0;
    let mut out = Vec::new();
    for (i, bi) in a.iter().enumerate() {
        for (j, bj) in b.iter().enumerate() {
            if bi.inflated(h).overlaps(&bj.inflated(h)) && keep(i, j) {
                out.push((i as u32, j as u32));
            }
        }
    }
    out
}

fn brute_within<const D: usize>(
    boxes: &[Aabb<D>],
    inflation: f64,
    keep: impl Fn(usize, usize) -> bool,
) -> Vec<(u32, u32)> {
    let all = brute_between(boxes, boxes, inflation, keep);
    all.into_iter().filter(|&(i, j)| i < j).collect()
}

/// Pairs of the reference whose inflated boxes touch (a shared face, edge
/// or corner of zero width).
fn touching<const D: usize>(a: &[Aabb<D>], b: &[Aabb<D>], pairs: &[(u32, u32)]) -> usize {
    let h = INFLATION / 2.0;
    let touch = |x: &Aabb<D>, y: &Aabb<D>| {
        (0..D).any(|k| x.max[k] + h == y.min[k] - h || y.max[k] + h == x.min[k] - h)
    };
    pairs
        .iter()
        .filter(|&&(i, j)| touch(&a[i as usize], &b[j as usize]))
        .count()
}

fn check_random<const D: usize>(seeds: u64, sizes: (usize, usize)) {
    let keep = |i: usize, j: usize| !(7 * i + 3 * j).is_multiple_of(5);
    let (mut touching_pairs, mut large_boxes, mut multi_cell) = (0, 0, 0);
    let (mut phase, mut pairs) = (BroadPhase::<D>::new(), Vec::new());
    for seed in 0..seeds {
        let mut rng = Rng(seed);
        let a = random_boxes::<D>(&mut rng, sizes.0);
        let b = random_boxes::<D>(&mut rng, sizes.1);

        let calls = Cell::new(0);
        let counting = |i: usize, j: usize| {
            calls.set(calls.get() + 1);
            keep(i, j)
        };
        phase.pairs_between(&a, &b, INFLATION, counting, &mut pairs);
        let overlapping = brute_between(&a, &b, INFLATION, |_, _| true);
        assert_eq!(pairs, brute_between(&a, &b, INFLATION, keep), "seed {seed}");
        assert_eq!(calls.get(), overlapping.len(), "keep once per pair");
        assert!(pairs.len() < overlapping.len() && !pairs.is_empty());
        touching_pairs += touching(&a, &b, &overlapping);
        large_boxes += phase.first.large.len() + phase.second.large.len();
        multi_cell += phase.entries.len() - phase.first.gridded.len() - phase.second.gridded.len();

        phase.pairs_within(&a, INFLATION, keep, &mut pairs);
        assert_eq!(pairs, brute_within(&a, INFLATION, keep), "seed {seed}");
        assert!(
            pairs.windows(2).all(|w| w[0] < w[1]),
            "sorted, no duplicates"
        );
    }
    assert!(touching_pairs > 0 && large_boxes > 0 && multi_cell > 0);
}

#[test]
fn matches_brute_force_in_2d() {
    check_random::<2>(40, (300, 200));
}

#[test]
fn matches_brute_force_in_3d() {
    check_random::<3>(40, (400, 250));
}

#[test]
fn touching_at_the_inflation_distance_counts() {
    let unit = |x: f64| Aabb::<2> {
        min: Vector::from([x, 0.0]),
        max: Vector::from([x + 1.0, 1.0]),
    };
    let (a, b) = ([unit(0.0)], [unit(1.5)]);
    let mut phase = BroadPhase::new();
    let mut pairs = Vec::new();
    phase.pairs_between(&a, &b, 0.5, |_, _| true, &mut pairs);
    assert_eq!(pairs, [(0, 0)]);
    phase.pairs_between(&a, &b, 0.5 - 1e-12, |_, _| true, &mut pairs);
    assert!(pairs.is_empty());
    phase.pairs_within(&[a[0], b[0]], 0.5, |_, _| true, &mut pairs);
    assert_eq!(pairs, [(0, 1)]);
}

#[test]
fn reused_buffers_give_the_same_list_without_reallocating() {
    let mut rng = Rng(7);
    let a = random_boxes::<3>(&mut rng, 500);
    let b = random_boxes::<3>(&mut rng, 300);
    let (mut warm, mut first, mut again) = (BroadPhase::new(), Vec::new(), Vec::new());
    warm.pairs_between(&a, &b, INFLATION, |_, _| true, &mut first);
    let buffers = |p: &BroadPhase<3>| {
        (
            p.entries.as_ptr(),
            p.first.boxes.as_ptr(),
            p.second.by_min.as_ptr(),
        )
    };
    let before = buffers(&warm);
    warm.pairs_between(&a, &b, INFLATION, |_, _| true, &mut again);
    assert_eq!(buffers(&warm), before, "no reallocation when warm");
    assert_eq!(again, first);
    warm.pairs_within(&b, INFLATION, |_, _| true, &mut again);
    warm.pairs_between(&a, &b, INFLATION, |_, _| true, &mut again);
    assert_eq!(again, first);
    BroadPhase::default().pairs_between(&a, &b, INFLATION, |_, _| true, &mut again);
    assert_eq!(again, first);
    assert!(first.len() > 100);
}

#[test]
fn far_outliers_clamp_to_the_grid_border() {
    let mut rng = Rng(3);
    let mut a = random_boxes::<3>(&mut rng, 200);
    for (n, b) in a.iter_mut().take(8).enumerate() {
        let shift = Vector::<3>::repeat(1e12 * (n % 2) as f64 - 1e9 * n as f64);
        (b.min, b.max) = (b.min + shift, b.max + shift);
    }
    let mut pairs = Vec::new();
    BroadPhase::new().pairs_within(&a, INFLATION, |_, _| true, &mut pairs);
    assert_eq!(pairs, brute_within(&a, INFLATION, |_, _| true));
}

#[test]
fn nan_and_empty_boxes_pair_with_nothing_infinite_ones_with_everything() {
    let mut rng = Rng(11);
    let mut a = random_boxes::<3>(&mut rng, 300);
    let b = random_boxes::<3>(&mut rng, 200);
    let nan = Vector::<3>::from([0.5, f64::NAN, 0.5]);
    a[0] = Aabb::of_points(&[Vector::repeat(0.5), nan]);
    a[1].max[2] = f64::NAN;
    a[2] = Aabb::empty();
    a[3] = Aabb {
        min: Vector::repeat(f64::NEG_INFINITY),
        max: Vector::repeat(f64::INFINITY),
    };
    a[4] = Aabb {
        min: Vector::from([f64::NEG_INFINITY, -1.0, -1.0]),
        max: Vector::from([0.5, 2.0, 2.0]),
    };
    let mut phase = BroadPhase::new();
    let mut pairs = Vec::new();
    phase.pairs_between(&a, &b, INFLATION, |_, _| true, &mut pairs);
    assert_eq!(pairs, brute_between(&a, &b, INFLATION, |_, _| true));
    let with = |i: u32| pairs.iter().filter(|p| p.0 == i).count();
    assert_eq!((with(0), with(1), with(2)), (0, 0, 0));
    assert_eq!(with(3), b.len());
    let left = b.iter().filter(|x| x.min[0] <= 0.5 + INFLATION).count();
    assert!(with(4) == left && left > 50 && left < 150);

    phase.pairs_within(&a, INFLATION, |_, _| true, &mut pairs);
    assert_eq!(pairs, brute_within(&a, INFLATION, |_, _| true));
    assert!(pairs.iter().all(|&(i, j)| i > 2 && j > 2));
    phase.pairs_between(&a, &b, f64::NAN, |_, _| true, &mut pairs);
    assert!(pairs.is_empty());
    let nan_only = [a[0], a[1], a[2]];
    phase.pairs_within(&nan_only, INFLATION, |_, _| true, &mut pairs);
    assert!(pairs.is_empty());
}

#[test]
fn boxes_of_points() {
    let p = |x: f64, y: f64| Vector::<2>::from([x, y]);
    let tight = Aabb::of_points(&[p(1.0, -2.0), p(-3.0, 4.0), p(0.5, 0.5)]);
    assert_eq!((tight.min, tight.max), (p(-3.0, -2.0), p(1.0, 4.0)));
    let swept = Aabb::swept(&[p(0.0, 0.0)], &[p(2.0, -1.0)]);
    assert_eq!((swept.min, swept.max), (p(0.0, -1.0), p(2.0, 0.0)));
    let grown = swept.inflated(0.25);
    assert_eq!((grown.min, grown.max), (p(-0.25, -1.25), p(2.25, 0.25)));
    assert_eq!(Aabb::<2>::of_points(&[]), Aabb::empty());
    assert!(!Aabb::<2>::empty().overlaps(&Aabb::empty()));
    assert!(!Aabb::<2>::empty().inflated(1.0).overlaps(&grown));
    let touching = Aabb::of_points(&[p(2.25, 0.25), p(3.0, 3.0)]);
    assert!(grown.overlaps(&touching) && touching.overlaps(&grown));
    assert!(!grown.overlaps(&touching.inflated(-1e-9)));
    let poisoned = tight
        .union_point(&p(f64::NAN, 0.0))
        .union_point(&p(9.0, 0.0));
    assert!(poisoned.min[0].is_nan() && poisoned.max[0].is_nan());
    assert!(!poisoned.overlaps(&tight) && !tight.overlaps(&poisoned));
}
