//! Building a simulation: checking the settings, eliminating pinned vertices, and making the list of energy terms the scene's effects ask for.
//!
//! Elasticity is always a term; gravity and the ground barrier exist only
//! when the scene asks for them (an absent effect has no term, so it costs
//! nothing). Pinned vertices are eliminated from the unknowns here, once.
//! The integrator gets the initial acceleration `a_0 = -M^{-1} grad U(x_0)`
//! here (Newmark needs it; the other schemes ignore it).

use super::{Body, Effects, SimError, Simulation, SimulationSettings};
use crate::assembly::SparseHessian;
use crate::energy::{BodyElasticity, EnergyTerm, Gravity, GroundBarrier, Inertia};
use crate::material::Material;
use crate::math::{UP_AXIS, Vector};
use crate::mesh::Mesh;
use crate::solver::SolverMethod;
use std::sync::Arc;

fn invalid(key: &'static str, reason: impl Into<String>) -> SimError {
    SimError::InvalidSetting {
        key,
        reason: reason.into(),
    }
}

/// `a_0 = -M^{-1} grad U(x_0)` on free vertices, zero on pinned ones: the
/// acceleration of the initial state under every potential term.
fn initial_acceleration<const D: usize>(
    elasticity: &dyn EnergyTerm<D>,
    effect_terms: &[Box<dyn EnergyTerm<D>>],
    masses: &[f64],
    free_index: &[Option<usize>],
    positions: &[Vector<D>],
) -> Vec<Vector<D>> {
    let mut gradient = vec![Vector::<D>::zeros(); positions.len()];
    elasticity.add_gradient(positions, 1.0, &mut gradient);
    for term in effect_terms {
        term.add_gradient(positions, 1.0, &mut gradient);
    }
    gradient
        .iter()
        .zip(masses)
        .zip(free_index)
        .map(|((g, m), free)| match free {
            Some(_) if *m > 0.0 => -g / *m,
            _ => Vector::<D>::zeros(),
        })
        .collect()
}

impl<const D: usize> Simulation<D> {
    /// Builds a simulation of `mesh` made of `material` with `density` (mass per
    /// unit rest volume), starting at rest positions with `initial_velocity`.
    pub fn new(
        mesh: Mesh<D>,
        material: Material,
        density: f64,
        effects: Effects<D>,
        settings: SimulationSettings,
        initial_velocity: Vector<D>,
    ) -> Result<Self, SimError> {
        let body = Body {
            mesh,
            material,
            density,
            velocity: initial_velocity,
            pinned: None,
        };
        Self::with_bodies(vec![body], effects, settings)
    }

    /// Builds a simulation of several bodies: their meshes are concatenated
    /// (vertices and elements in body order) into the simulation's mesh;
    /// each has its material, density, initial velocity and pinned region,
    /// and all share the effects (which pin vertices of any body).
    pub fn with_bodies(
        bodies: Vec<Body<D>>,
        effects: Effects<D>,
        settings: SimulationSettings,
    ) -> Result<Self, SimError> {
        if bodies.is_empty() {
            return Err(invalid("bodies", "a simulation needs at least one body"));
        }
        for body in &bodies {
            let density = body.density;
            if !(density > 0.0 && density.is_finite()) {
                return Err(invalid(
                    "density",
                    format!("must be positive and finite, got {density}"),
                ));
            }
        }
        if !(settings.dt > 0.0 && settings.dt.is_finite()) {
            return Err(invalid(
                "dt",
                format!("must be positive and finite, got {}", settings.dt),
            ));
        }
        if !(settings.solver.tolerance > 0.0) {
            return Err(invalid(
                "tolerance",
                format!("must be positive, got {}", settings.solver.tolerance),
            ));
        }
        if settings.solver.max_iterations == 0 {
            return Err(invalid("max_iterations", "must be at least 1"));
        }
        if let SolverMethod::GradientDescent { step } = settings.solver.method
            && !(step > 0.0 && step.is_finite())
        {
            return Err(invalid(
                "step",
                format!("must be positive and finite, got {step}"),
            ));
        }
        let inside = |r: &super::PinRegion<D>, x: &Vector<D>| {
            (0..D).all(|k| x[k] >= r.min[k] && x[k] <= r.max[k])
        };
        // Per vertex: its body's index; masses and rest positions in body order.
        let mut owner = Vec::new();
        let mut masses = Vec::new();
        let mut positions = Vec::new();
        let mut simplices = Vec::new();
        for (b, body) in bodies.iter().enumerate() {
            let offset = positions.len();
            if let Some(region) = &body.pinned
                && !body.mesh.rest_positions().iter().any(|x| inside(region, x))
            {
                return Err(invalid(
                    "pinned",
                    format!("the pinned region of body {b} holds no vertex of it"),
                ));
            }
            owner.extend(std::iter::repeat_n(b, body.mesh.vertex_count()));
            masses.extend(body.mesh.lumped_masses(body.density));
            positions.extend_from_slice(body.mesh.rest_positions());
            simplices.extend(
                body.mesh
                    .simplices()
                    .map(|s| s.iter().map(|v| v + offset).collect::<Vec<_>>()),
            );
        }
        let pins: Vec<Option<super::PinRegion<D>>> = bodies.iter().map(|b| b.pinned).collect();
        let body_velocities: Vec<Vector<D>> = bodies.iter().map(|b| b.velocity).collect();
        let (mesh, elasticity) = if bodies.len() == 1 {
            let body = bodies.into_iter().next().expect("one body");
            let mesh = Arc::new(body.mesh);
            let elasticity = BodyElasticity::single(mesh.clone(), body.material);
            (mesh, elasticity)
        } else {
            let mesh = Arc::new(Mesh::new(positions.clone(), simplices).map_err(|e| {
                SimError::SetupFailure {
                    reason: e.to_string(),
                }
            })?);
            let parts = bodies
                .iter()
                .map(|b| (Arc::new(b.mesh.clone()), b.material))
                .collect();
            let elasticity = BodyElasticity::bodies(parts).map_err(|e| SimError::SetupFailure {
                reason: e.to_string(),
            })?;
            (mesh, elasticity)
        };
        let pinned = |v: usize, x: &Vector<D>| {
            effects.pinned.is_some_and(|r| inside(&r, x))
                || pins[owner[v]].is_some_and(|r| inside(&r, x))
        };
        let mut free_count = 0;
        let free_index: Vec<Option<usize>> = positions
            .iter()
            .enumerate()
            .map(|(v, x)| {
                (!pinned(v, x)).then(|| {
                    free_count += 1;
                    free_count - 1
                })
            })
            .collect();
        if effects.pinned.is_some() && free_count == positions.len() {
            return Err(invalid("pinned", "the pinned region holds no vertex"));
        }
        if free_count == 0 {
            return Err(invalid(
                "pinned",
                "every vertex is pinned: nothing can move",
            ));
        }
        let velocities: Vec<Vector<D>> = free_index
            .iter()
            .enumerate()
            .map(|(v, f)| {
                if f.is_some() {
                    body_velocities[owner[v]]
                } else {
                    Vector::<D>::zeros()
                }
            })
            .collect();
        let mut effect_terms: Vec<Box<dyn EnergyTerm<D>>> = Vec::new();
        if let Some(g) = effects.gravity {
            effect_terms.push(Box::new(Gravity::new(masses.clone(), g)));
        }
        let mut barrier_stiffness = None;
        if let Some(ground) = effects.ground {
            if !(ground.activation_distance > 0.0 && ground.activation_distance.is_finite()) {
                return Err(invalid(
                    "a",
                    format!(
                        "the barrier width must be positive, got {}",
                        ground.activation_distance
                    ),
                ));
            }
            if let Some((vertex, x)) = positions
                .iter()
                .enumerate()
                .find(|(_, x)| !(x[UP_AXIS] > ground.height))
            {
                return Err(SimError::BelowGround {
                    vertex,
                    height: x[UP_AXIS],
                    ground: ground.height,
                });
            }
            let stiffness = match ground.stiffness {
                Some(kappa) if kappa > 0.0 && kappa.is_finite() => kappa,
                Some(kappa) => {
                    return Err(invalid(
                        "kappa",
                        format!("must be positive and finite, got {kappa}"),
                    ));
                }
                None => GroundBarrier::default_stiffness(
                    ground.height,
                    ground.activation_distance,
                    &masses,
                    &positions,
                    &velocities,
                    effects.gravity,
                ),
            };
            effect_terms.push(Box::new(GroundBarrier::new(
                ground.height,
                ground.activation_distance,
                stiffness,
            )));
            barrier_stiffness = Some(stiffness);
        }
        let hessian =
            SparseHessian::new(&mesh, free_index).map_err(|e| SimError::SetupFailure {
                reason: e.to_string(),
            })?;
        let mut integrator = settings.integrator.build(positions.len());
        integrator.set_initial_acceleration(&initial_acceleration(
            &elasticity,
            &effect_terms,
            &masses,
            hessian.free_index(),
            &positions,
        ));
        Ok(Self {
            inertia: Inertia::new(masses.clone()),
            elasticity,
            effect_terms,
            integrator,
            barrier_stiffness,
            ground_height: effects.ground.map(|g| g.height),
            mesh,
            masses,
            positions,
            velocities,
            time: 0.0,
            steps: 0,
            settings,
            hessian,
        })
    }
}
