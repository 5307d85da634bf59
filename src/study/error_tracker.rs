//! The reference trajectory, and the running errors of a run against it
//! (the definitions are in the module doc of [`crate::study`]).

use crate::math::Vector;

/// The reference run, frame by frame: every vertex position (when kept),
/// the centre of mass and the total energy.
#[derive(Debug, Clone, Default)]
pub struct Reference {
    /// Rest positions of the reference mesh, flattened: a run whose mesh has
    /// exactly these rest positions is compared vertex by vertex.
    rest: Vec<f64>,
    /// Positions of every output frame, flattened, one `Vec` per frame.
    positions: Vec<Vec<f64>>,
    /// Centre of mass of every output frame.
    centres: Vec<Vec<f64>>,
    /// Total energy of every output frame.
    energies: Vec<f64>,
}

impl Reference {
    /// An empty reference for a mesh with these rest positions.
    pub fn new<const D: usize>(rest: &[Vector<D>]) -> Self {
        Self {
            rest: flatten(rest),
            ..Self::default()
        }
    }

    /// Records the next output frame.
    pub fn push<const D: usize>(
        &mut self,
        positions: &[Vector<D>],
        centre: &Vector<D>,
        energy: f64,
    ) {
        self.positions.push(flatten(positions));
        self.centres.push(centre.as_slice().to_vec());
        self.energies.push(energy);
    }

    /// The number of frames recorded.
    pub fn frames(&self) -> usize {
        self.energies.len()
    }

    /// The scale energy errors are relative to: `|Ê^0|`, or `max_k |Ê^k|`
    /// when the initial energy is zero (1 if every energy is zero).
    fn energy_scale(&self) -> f64 {
        let initial = self.energies.first().copied().unwrap_or(0.0).abs();
        if initial > 0.0 {
            return initial;
        }
        let largest = self.energies.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        if largest > 0.0 { largest } else { 1.0 }
    }

    /// Starts comparing a run whose mesh has rest positions `rest`.
    pub fn tracker<const D: usize>(&self, rest: &[Vector<D>]) -> ErrorTracker<'_> {
        let same_mesh = self.rest.len() == rest.len() * D
            && self
                .rest
                .iter()
                .zip(rest.iter().flat_map(|p| p.iter()))
                .all(|(a, b)| a == b);
        ErrorTracker {
            reference: self,
            kind: if same_mesh {
                ErrorKind::Vertices
            } else {
                ErrorKind::CentreOfMass
            },
            energy_scale: self.energy_scale(),
            trajectory: 0.0,
            energy: 0.0,
            frames: 0,
        }
    }
}

/// What the trajectory error measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The largest vertex distance (the run has the reference's mesh).
    Vertices,
    /// The largest centre-of-mass distance (the meshes differ).
    CentreOfMass,
}

impl ErrorKind {
    /// The name written in `study.csv`: `vertices` or `centre_of_mass`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Vertices => "vertices",
            Self::CentreOfMass => "centre_of_mass",
        }
    }
}

/// The running maxima of one run's errors against the reference.
#[derive(Debug)]
pub struct ErrorTracker<'r> {
    reference: &'r Reference,
    kind: ErrorKind,
    /// [`Reference::energy_scale`], computed once.
    energy_scale: f64,
    trajectory: f64,
    energy: f64,
    frames: usize,
}

impl ErrorTracker<'_> {
    /// Compares the run's next output frame with the reference's frame of
    /// the same index. A NaN anywhere makes the error NaN (never hidden by
    /// `max`).
    pub fn observe<const D: usize>(
        &mut self,
        positions: &[Vector<D>],
        centre: &Vector<D>,
        energy: f64,
    ) {
        let k = self.frames;
        self.frames += 1;
        let Some(&reference_energy) = self.reference.energies.get(k) else {
            return;
        };
        let distance = match self.kind {
            ErrorKind::Vertices => {
                let reference = &self.reference.positions[k];
                positions
                    .iter()
                    .enumerate()
                    .map(|(i, p)| distance(p.as_slice(), &reference[i * D..(i + 1) * D]))
                    .fold(0.0, nan_max)
            }
            ErrorKind::CentreOfMass => distance(centre.as_slice(), &self.reference.centres[k]),
        };
        self.trajectory = nan_max(self.trajectory, distance);
        let energy_error = (energy - reference_energy).abs() / self.energy_scale;
        self.energy = nan_max(self.energy, energy_error);
    }

    /// The errors over the frames observed; `None` when the run wrote a
    /// different number of frames than the reference.
    pub fn finish(self) -> Option<RunErrors> {
        (self.frames == self.reference.frames()).then_some(RunErrors {
            kind: self.kind,
            trajectory: self.trajectory,
            energy: self.energy,
        })
    }
}

/// One run's errors against the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunErrors {
    /// What `trajectory` measures.
    pub kind: ErrorKind,
    /// The largest vertex (or centre-of-mass) distance over all frames.
    pub trajectory: f64,
    /// The largest energy difference relative to the reference's initial energy.
    pub energy: f64,
}

fn flatten<const D: usize>(points: &[Vector<D>]) -> Vec<f64> {
    points.iter().flat_map(|p| p.iter().copied()).collect()
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// `max` that keeps a NaN.
fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector<2> {
        Vector::<2>::new(x, y)
    }

    fn reference() -> Reference {
        let rest = [v(0.0, 0.0), v(1.0, 0.0)];
        let mut reference = Reference::new(&rest);
        reference.push(&rest, &v(0.5, 0.0), 10.0);
        reference.push(&[v(0.0, -1.0), v(1.0, -1.0)], &v(0.5, -1.0), 8.0);
        reference
    }

    #[test]
    fn same_mesh_errors_are_the_largest_vertex_distance_and_relative_energy() {
        let reference = reference();
        let rest = [v(0.0, 0.0), v(1.0, 0.0)];
        let mut tracker = reference.tracker(&rest);
        tracker.observe(&rest, &v(0.5, 0.0), 10.0);
        // One vertex 0.3 off, the other 0.4 (a 3-4-5 triangle: 0.5).
        tracker.observe(&[v(0.0, -1.3), v(1.3, -1.4)], &v(0.65, -1.35), 9.0);
        let errors = tracker.finish().unwrap();
        assert_eq!(errors.kind, ErrorKind::Vertices);
        assert!((errors.trajectory - 0.5).abs() < 1e-15);
        assert!((errors.energy - 0.1).abs() < 1e-15);
    }

    #[test]
    fn another_mesh_is_compared_by_centre_of_mass() {
        let reference = reference();
        let rest = [v(0.0, 0.0), v(0.5, 0.0), v(1.0, 0.0)];
        let mut tracker = reference.tracker(&rest);
        tracker.observe(&rest, &v(0.5, 0.0), 10.0);
        tracker.observe(&rest, &v(0.5, -0.75), 8.0);
        let errors = tracker.finish().unwrap();
        assert_eq!(errors.kind, ErrorKind::CentreOfMass);
        assert!((errors.trajectory - 0.25).abs() < 1e-15);
        assert_eq!(errors.energy, 0.0);
    }

    #[test]
    fn nan_is_kept_and_a_short_run_has_no_errors() {
        let reference = reference();
        let rest = [v(0.0, 0.0), v(1.0, 0.0)];
        let mut tracker = reference.tracker(&rest);
        tracker.observe(&[v(f64::NAN, 0.0), v(1.0, 0.0)], &v(0.5, 0.0), 10.0);
        tracker.observe(&rest, &v(0.5, 0.0), 10.0);
        assert!(tracker.finish().unwrap().trajectory.is_nan());
        let mut short = reference.tracker(&rest);
        short.observe(&rest, &v(0.5, 0.0), 10.0);
        assert!(short.finish().is_none());
    }
}
