//! Tests of additive CCD: random motions against the exact first contact (the
//! first root of the coplanarity determinant where the primitives touch), and
//! constructed cases ([`cases`]).

mod cases;

use super::*;
use crate::math::{Matrix, Polynomial};

/// xorshift64*: deterministic uniform numbers for the random motions.
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
        lo + (hi - lo) * (bits as f64 / (1u64 << 53) as f64)
    }

    fn vector<const D: usize>(&mut self, half_width: f64) -> Vector<D> {
        Vector::<D>::from_fn(|_, _| self.uniform(-half_width, half_width))
    }
}

/// A linear motion of a stencil's corners over `t in [0, 1]`.
#[derive(Clone, Copy)]
struct Motion<const N: usize, const D: usize> {
    x: [Vector<D>; N],
    dx: [Vector<D>; N],
}

impl<const N: usize, const D: usize> Motion<N, D> {
    fn at(&self, t: f64) -> [Vector<D>; N] {
        std::array::from_fn(|i| self.x[i] + self.dx[i] * t)
    }

    /// Build a motion from the positions at time `t_contact` and the displacements.
    fn through(at_contact: [Vector<D>; N], dx: [Vector<D>; N], t_contact: f64) -> Self {
        Self {
            x: std::array::from_fn(|i| at_contact[i] - dx[i] * t_contact),
            dx,
        }
    }
}

type PointEdge = Motion<3, 2>;
type Triangle = Motion<4, 3>;
type EdgeEdge = Motion<4, 3>;

fn pe_distance(x: &[Vector2; 3]) -> f64 {
    point_edge_distance_squared(&x[0], &x[1], &x[2])
}
fn pt_distance(x: &[Vector3; 4]) -> f64 {
    point_triangle_distance_squared(&x[0], &x[1], &x[2], &x[3])
}
fn ee_distance(x: &[Vector3; 4]) -> f64 {
    edge_edge_distance_squared(&x[0], &x[1], &x[2], &x[3])
}

fn pe_ccd(m: &PointEdge, t_max: f64, settings: &CcdSettings) -> CcdOutcome {
    let (x, d) = (&m.x, &m.dx);
    point_edge_ccd(&x[0], &x[1], &x[2], &d[0], &d[1], &d[2], t_max, settings)
}
fn pt_ccd(m: &Triangle, t_max: f64, settings: &CcdSettings) -> CcdOutcome {
    let (x, d) = (&m.x, &m.dx);
    point_triangle_ccd(
        &x[0], &x[1], &x[2], &x[3], &d[0], &d[1], &d[2], &d[3], t_max, settings,
    )
}
fn ee_ccd(m: &EdgeEdge, t_max: f64, settings: &CcdSettings) -> CcdOutcome {
    let (x, d) = (&m.x, &m.dx);
    edge_edge_ccd(
        &x[0], &x[1], &x[2], &x[3], &d[0], &d[1], &d[2], &d[3], t_max, settings,
    )
}

/// The exact first time of impact in `[0, 1]`: the first root of the
/// coplanarity (2D: collinearity) determinant, a polynomial in `t`, at which
/// the primitives actually touch (the distance vanishes there).
fn first_contact<const N: usize, const D: usize>(
    motion: &Motion<N, D>,
    coplanarity: Polynomial,
    distance_squared: impl Fn(&[Vector<D>; N]) -> f64,
) -> Option<f64> {
    let scale = motion
        .x
        .iter()
        .chain(&motion.dx)
        .map(|v| v.norm())
        .fold(1.0, f64::max);
    let touches = |t: f64| distance_squared(&motion.at(t)).sqrt() <= 1e-9 * scale;
    coplanarity
        .sign_changes_in(0.0, 1.0)
        .as_slice()
        .iter()
        .copied()
        .find(|&t| touches(t))
}

fn columns<const D: usize>(c: [Vector<D>; D]) -> Matrix<D> {
    Matrix::<D>::from_columns(&c)
}

fn pe_contact(m: &PointEdge) -> Option<f64> {
    let ([p, e0, e1], [dp, de0, de1]) = (m.x, m.dx);
    let a = columns([e1 - e0, p - e0]);
    let b = columns([de1 - de0, dp - de0]);
    first_contact(m, Polynomial::determinant_of_line(&a, &b), pe_distance)
}
fn pt_contact(m: &Triangle) -> Option<f64> {
    let ([p, t0, t1, t2], [dp, dt0, dt1, dt2]) = (m.x, m.dx);
    let a = columns([t1 - t0, t2 - t0, p - t0]);
    let b = columns([dt1 - dt0, dt2 - dt0, dp - dt0]);
    first_contact(m, Polynomial::determinant_of_line(&a, &b), pt_distance)
}
fn ee_contact(m: &EdgeEdge) -> Option<f64> {
    let ([a0, a1, b0, b1], [da0, da1, db0, db1]) = (m.x, m.dx);
    let a = columns([a1 - a0, b0 - a0, b1 - a0]);
    let b = columns([da1 - da0, db0 - da0, db1 - da0]);
    first_contact(m, Polynomial::determinant_of_line(&a, &b), ee_distance)
}

/// Checks one answer: within `[0, t_max]`, strictly before the exact first
/// contact, and (when it stopped early) keeping `1 - s` of the initial distance.
/// Returns `step / toi` when there is a contact before `t_max`.
fn check<const N: usize, const D: usize>(
    motion: &Motion<N, D>,
    outcome: CcdOutcome,
    toi: Option<f64>,
    distance_squared: impl Fn(&[Vector<D>; N]) -> f64,
    t_max: f64,
) -> Option<f64> {
    let step = outcome.step;
    assert!(!outcome.budget_exhausted);
    assert!((0.0..=t_max).contains(&step), "step {step}");
    if let Some(toi) = toi {
        assert!(step < toi, "step {step} reaches the contact at {toi}");
    }
    if step < t_max {
        let start = distance_squared(&motion.x).sqrt();
        let end = distance_squared(&motion.at(step)).sqrt();
        assert!(end >= 0.1 * start * (1.0 - 1e-6), "kept {end} of {start}");
    }
    toi.filter(|&toi| toi <= t_max).map(|toi| step / toi)
}

/// The answers are not only safe but useful: every one moves (`step / toi`
/// above 0.1), nine in ten reach half the time of impact, the median 0.75
/// (measured: minimum 0.12, tenth percentile 0.69, median 0.82 to 0.87).
fn assert_useful(name: &str, mut ratios: Vec<f64>) {
    ratios.sort_by(f64::total_cmp);
    let quantile = |f: f64| ratios[((ratios.len() - 1) as f64 * f) as usize];
    assert!(
        ratios.len() > RANDOM_CASES * 9 / 10,
        "{name}: {}",
        ratios.len()
    );
    assert!(quantile(0.0) > 0.1, "{name}: min {}", quantile(0.0));
    assert!(quantile(0.1) >= 0.5, "{name}: q10 {}", quantile(0.1));
    assert!(quantile(0.5) >= 0.75, "{name}: median {}", quantile(0.5));
}

/// Random contacts by construction: the primitives at a random time `T`
/// with the point on the edge (`rigid`: the corners of each primitive share
/// one displacement), moved back to `t = 0` (the first contact may be earlier).
fn random_point_edge(rng: &mut Rng, rigid: bool) -> PointEdge {
    let t_contact = rng.uniform(0.05, 0.95);
    let (e0, e1) = (rng.vector(1.0), rng.vector(1.0));
    let p = e0 + (e1 - e0) * rng.uniform(0.0, 1.0);
    let de0 = rng.vector(2.0);
    let (dp, de1) = if rigid {
        (rng.vector(2.0), de0)
    } else {
        (rng.vector(2.0), rng.vector(2.0))
    };
    Motion::through([p, e0, e1], [dp, de0, de1], t_contact)
}

fn random_point_triangle(rng: &mut Rng, rigid: bool) -> Triangle {
    let t_contact = rng.uniform(0.05, 0.95);
    let (t0, t1, t2) = (rng.vector(1.0), rng.vector(1.0), rng.vector(1.0));
    let (u, v) = (rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
    let (u, v) = if u + v > 1.0 {
        (1.0 - u, 1.0 - v)
    } else {
        (u, v)
    };
    let p = t0 + (t1 - t0) * u + (t2 - t0) * v;
    let dt0 = rng.vector(2.0);
    let dp = rng.vector(2.0);
    let (dt1, dt2) = if rigid {
        (dt0, dt0)
    } else {
        (rng.vector(2.0), rng.vector(2.0))
    };
    Motion::through([p, t0, t1, t2], [dp, dt0, dt1, dt2], t_contact)
}

fn random_edge_edge(rng: &mut Rng, rigid: bool) -> EdgeEdge {
    let t_contact = rng.uniform(0.05, 0.95);
    let (a0, a1, b0) = (rng.vector(1.0), rng.vector(1.0), rng.vector(1.0));
    let crossing = a0 + (a1 - a0) * rng.uniform(0.0, 1.0);
    let b1 = b0 + (crossing - b0) / rng.uniform(0.05, 1.0);
    let (da0, db0) = (rng.vector(2.0), rng.vector(2.0));
    let (da1, db1) = if rigid {
        (da0, db0)
    } else {
        (rng.vector(2.0), rng.vector(2.0))
    };
    Motion::through([a0, a1, b0, b1], [da0, da1, db0, db1], t_contact)
}

const RANDOM_CASES: usize = 2000;

#[test]
fn random_point_edge_contacts_are_never_reached() {
    let settings = CcdSettings::default();
    for rigid in [true, false] {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let mut ratios = Vec::new();
        for _ in 0..RANDOM_CASES {
            let motion = random_point_edge(&mut rng, rigid);
            if pe_distance(&motion.x) < 1e-6 {
                continue;
            }
            let toi = pe_contact(&motion);
            assert!(toi.is_some(), "the constructed contact was not found");
            let outcome = pe_ccd(&motion, 1.0, &settings);
            ratios.extend(check(&motion, outcome, toi, pe_distance, 1.0));
        }
        assert_useful(&format!("point-edge rigid {rigid}"), ratios);
    }
}

#[test]
fn random_point_triangle_contacts_are_never_reached() {
    let settings = CcdSettings::default();
    for rigid in [true, false] {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let mut ratios = Vec::new();
        for _ in 0..RANDOM_CASES {
            let motion = random_point_triangle(&mut rng, rigid);
            if pt_distance(&motion.x) < 1e-6 {
                continue;
            }
            let toi = pt_contact(&motion);
            assert!(toi.is_some(), "the constructed contact was not found");
            let outcome = pt_ccd(&motion, 1.0, &settings);
            ratios.extend(check(&motion, outcome, toi, pt_distance, 1.0));
        }
        assert_useful(&format!("point-triangle rigid {rigid}"), ratios);
    }
}

#[test]
fn random_edge_edge_contacts_are_never_reached() {
    let settings = CcdSettings::default();
    for rigid in [true, false] {
        let mut rng = Rng(0xd1b5_4a32_d192_ed03);
        let mut ratios = Vec::new();
        for _ in 0..RANDOM_CASES {
            let motion = random_edge_edge(&mut rng, rigid);
            if ee_distance(&motion.x) < 1e-6 {
                continue;
            }
            let toi = ee_contact(&motion);
            assert!(toi.is_some(), "the constructed contact was not found");
            let outcome = ee_ccd(&motion, 1.0, &settings);
            ratios.extend(check(&motion, outcome, toi, ee_distance, 1.0));
        }
        assert_useful(&format!("edge-edge rigid {rigid}"), ratios);
    }
}

/// Free random motions (most miss) against a random `t_max`.
#[test]
fn random_free_motions_respect_t_max_and_contacts() {
    let settings = CcdSettings::default();
    let mut rng = Rng(0x0123_4567_89ab_cdef);
    let mut contacts = 0;
    for _ in 0..RANDOM_CASES {
        let t_max = rng.uniform(0.05, 1.0);
        let pe = Motion {
            x: [(); 3].map(|_| rng.vector(1.0)),
            dx: [(); 3].map(|_| rng.vector(3.0)),
        };
        let pt = Motion {
            x: [(); 4].map(|_| rng.vector(1.0)),
            dx: [(); 4].map(|_| rng.vector(3.0)),
        };
        let ee = Motion {
            x: [(); 4].map(|_| rng.vector(1.0)),
            dx: [(); 4].map(|_| rng.vector(3.0)),
        };
        let (toi_pe, toi_pt, toi_ee) = (pe_contact(&pe), pt_contact(&pt), ee_contact(&ee));
        contacts += [toi_pe, toi_pt, toi_ee]
            .iter()
            .filter(|t| t.is_some())
            .count();
        check(
            &pe,
            pe_ccd(&pe, t_max, &settings),
            toi_pe,
            pe_distance,
            t_max,
        );
        check(
            &pt,
            pt_ccd(&pt, t_max, &settings),
            toi_pt,
            pt_distance,
            t_max,
        );
        check(
            &ee,
            ee_ccd(&ee, t_max, &settings),
            toi_ee,
            ee_distance,
            t_max,
        );
    }
    assert!(contacts > RANDOM_CASES / 4, "only {contacts} contacts");
}
