//! `[time]` and `[solver]`: frames, steps and their limits; the method,
//! tolerance (scaled with the scene when not given), projection and the
//! friction passes.

use super::{
    MAX_FRICTION_ITERATIONS, MAX_SUBDIVISIONS, SceneValidator, VResult, bounding_box_diagonal,
};
use crate::scene::raw_scene::{Method, ProjectionName, RawSolver, RawTime};
use crate::scene::scene_config::{
    BodyConfig, DEFAULT_FPS, DEFAULT_FRAMES, DEFAULT_GRADIENT_DESCENT_ITERATIONS,
    DEFAULT_GRADIENT_DESCENT_STEP, DEFAULT_NEWTON_ITERATIONS, DEFAULT_RELATIVE_TOLERANCE,
    DEFAULT_SUBSTEPS, MAX_FRAMES, MAX_STEPS, MAX_SUBSTEPS, TimeConfig,
};
use crate::scene::scene_error::{approx, num};
use crate::sim::{DEFAULT_FRICTION_VELOCITY, Effects};
use crate::solver::{Projection, SolverMethod, SolverSettings};

impl SceneValidator<'_, '_> {
    /// `[time]`: frames, frame rate, substeps and the integrator, within their limits.
    pub(super) fn time(&self, raw: &RawTime) -> VResult<(TimeConfig, RawTime)> {
        let fps = self.positive("time.fps", raw.fps.unwrap_or(DEFAULT_FPS))?;
        let substeps = match (raw.substeps, raw.dt) {
            (None, None) => DEFAULT_SUBSTEPS,
            (Some(n), None) => self.count("time.substeps", n, MAX_SUBSTEPS)?,
            (substeps, Some(dt)) => {
                let dt = self.positive("time.dt", dt)?;
                let exact = 1.0 / (fps * dt);
                let nearest = exact.round().max(1.0);
                if !(nearest <= MAX_SUBSTEPS as f64) {
                    return Err(self.err(
                        "time.dt",
                        format!(
                            "{} s makes {} steps per frame of 1/{} s, more than the \
                             {MAX_SUBSTEPS} allowed",
                            num(dt),
                            approx(exact),
                            num(fps)
                        ),
                    ));
                }
                if (exact - nearest).abs() > 1e-3 * nearest {
                    return Err(self.err(
                        "time.dt",
                        format!(
                            "{} s does not split a frame of 1/{} s into whole steps ({exact:.4} steps); \
                             use e.g. dt = {:.6e} ({nearest} steps) or give `substeps`",
                            num(dt),
                            num(fps),
                            1.0 / (fps * nearest)
                        ),
                    ));
                }
                let from_dt = nearest as usize;
                if let Some(n) = substeps.filter(|&n| n != from_dt as i64) {
                    return Err(self.err(
                        "time.dt",
                        format!(
                            "dt = {} s means {from_dt} steps per frame at {} fps, but substeps = {n}",
                            num(dt),
                            num(fps)
                        ),
                    ));
                }
                from_dt
            }
        };
        let frames = match (raw.frames, raw.duration) {
            (Some(_), Some(_)) => {
                return Err(self.err("time.duration", "give `frames` or `duration`, not both"));
            }
            (Some(n), None) => self.count("time.frames", n, MAX_FRAMES)?,
            (None, Some(d)) => {
                let d = self.positive("time.duration", d)?;
                let n = (d * fps).round();
                if n < 1.0 {
                    return Err(self.err(
                        "time.duration",
                        format!("{} s is less than one frame at {} fps", num(d), num(fps)),
                    ));
                }
                if !(n <= MAX_FRAMES as f64) {
                    return Err(self.err(
                        "time.duration",
                        format!(
                            "{} s at {} fps is {} frames, more than the {MAX_FRAMES} allowed",
                            num(d),
                            num(fps),
                            approx(n)
                        ),
                    ));
                }
                n as usize
            }
            (None, None) => DEFAULT_FRAMES,
        };
        let time_key = match (raw.dt, raw.frames, raw.duration) {
            (Some(_), _, _) => "time.dt",
            (None, Some(_), _) => "time.frames",
            (None, None, Some(_)) => "time.duration",
            _ => "time.substeps",
        };
        let steps = (frames - 1) as u64 * substeps as u64;
        if steps > MAX_STEPS {
            return Err(self.err(
                time_key,
                format!(
                    "{frames} frames of {substeps} steps make {steps} time steps, more than the \
                     {MAX_STEPS} allowed"
                ),
            ));
        }
        let dt = 1.0 / (fps * substeps as f64);
        // The solver weighs the potential by dt²: it must be a normal double.
        if !((dt * dt).is_finite() && dt * dt >= f64::MIN_POSITIVE) {
            let key = if raw.dt.is_some() {
                "time.dt"
            } else {
                "time.fps"
            };
            return Err(self.err(
                key,
                format!(
                    "gives a time step dt = 1 / (fps × substeps) = {} s whose square is outside \
                     double precision (the solver weighs forces by dt²)",
                    approx(dt)
                ),
            ));
        }
        let integrator = raw.integrator.unwrap_or_default();
        let resolved = RawTime {
            fps: Some(fps),
            substeps: Some(substeps as i64),
            dt: None,
            frames: Some(frames as i64),
            duration: None,
            integrator: Some(integrator),
        };
        Ok((
            TimeConfig {
                fps,
                substeps,
                dt,
                frames,
                integrator,
            },
            resolved,
        ))
    }

    /// `[solver]`, for bodies whose bounding box at rest has the diagonal
    /// `scene_size` (the default tolerance scales with it).
    pub(super) fn solver(
        &self,
        raw: &RawSolver,
        scene_size: f64,
    ) -> VResult<(SolverSettings, RawSolver)> {
        let method = raw.method.unwrap_or_default();
        let tolerance = self.positive(
            "solver.tolerance",
            raw.tolerance
                .unwrap_or(DEFAULT_RELATIVE_TOLERANCE * scene_size),
        )?;
        let (method_settings, default_iterations, step) = match method {
            Method::Newton => {
                if raw.step.is_some() {
                    return Err(self.err(
                        "solver.step",
                        "is only used with method = \"gradient-descent\"",
                    ));
                }
                (SolverMethod::Newton, DEFAULT_NEWTON_ITERATIONS, None)
            }
            Method::GradientDescent => {
                let step = self.positive(
                    "solver.step",
                    raw.step.unwrap_or(DEFAULT_GRADIENT_DESCENT_STEP),
                )?;
                (
                    SolverMethod::GradientDescent { step },
                    DEFAULT_GRADIENT_DESCENT_ITERATIONS,
                    Some(step),
                )
            }
        };
        let projection = match (method, raw.projection) {
            (Method::GradientDescent, Some(_)) => {
                return Err(self.err("solver.projection", "is only used with method = \"newton\""));
            }
            (Method::GradientDescent, None) => None,
            (Method::Newton, given) => {
                Some(given.map_or(SolverSettings::default().projection, Projection::from))
            }
        };
        let max_iterations = match raw.max_iterations {
            Some(n) => self.count("solver.max_iterations", n, usize::MAX)?,
            None => default_iterations,
        };
        let max_subdivisions = match raw.max_subdivisions {
            Some(n) if (0..=MAX_SUBDIVISIONS as i64).contains(&n) => n as usize,
            Some(n) => {
                return Err(self.err(
                    "solver.max_subdivisions",
                    format!("must be a whole number from 0 to {MAX_SUBDIVISIONS}, got {n}"),
                ));
            }
            None => SolverSettings::default().max_subdivisions,
        };
        let resolved = RawSolver {
            method: Some(method),
            tolerance: Some(tolerance),
            max_iterations: Some(max_iterations as i64),
            projection: projection.map(ProjectionName::from),
            max_subdivisions: Some(max_subdivisions as i64),
            step,
            friction_velocity: None,
            friction_iterations: None,
        };
        Ok((
            SolverSettings {
                method: method_settings,
                tolerance,
                max_iterations,
                projection: projection.unwrap_or_default(),
                max_subdivisions,
                ..SolverSettings::default()
            },
            resolved,
        ))
    }

    /// `solver.friction_velocity` and `solver.friction_iterations`, in a
    /// scene with friction (a `friction` above 0 in `[effects.ground]`,
    /// `[effects.contact]` or an obstacle); refused without it, where they
    /// would do nothing.
    pub(super) fn friction_solver<const D: usize>(
        &self,
        mut solver: SolverSettings,
        mut resolved: RawSolver,
        raw: &RawSolver,
        effects: &Effects<D>,
        bodies: &[BodyConfig<D>],
    ) -> VResult<(SolverSettings, RawSolver)> {
        let has_friction = effects.ground.is_some_and(|g| g.friction > 0.0)
            || effects.contact.is_some_and(|c| c.friction > 0.0)
            || effects
                .obstacles
                .iter()
                .any(|o| o.friction.is_some_and(|mu| mu > 0.0));
        if !has_friction {
            for (key, given) in [
                ("solver.friction_velocity", raw.friction_velocity.is_some()),
                (
                    "solver.friction_iterations",
                    raw.friction_iterations.is_some(),
                ),
            ] {
                if given {
                    return Err(self.err(
                        key,
                        "is only used with friction: give effects.ground.friction, \
                         effects.contact.friction or an obstacle's friction above 0",
                    ));
                }
            }
            return Ok((solver, resolved));
        }
        let velocity = match raw.friction_velocity {
            Some(v) => self.positive("solver.friction_velocity", v)?,
            None => DEFAULT_FRICTION_VELOCITY * bounding_box_diagonal(bodies),
        };
        let iterations = match raw.friction_iterations {
            Some(n) => self.count("solver.friction_iterations", n, MAX_FRICTION_ITERATIONS)?,
            None => 1,
        };
        solver.friction_velocity = Some(velocity);
        solver.friction_iterations = iterations;
        resolved.friction_velocity = Some(velocity);
        resolved.friction_iterations = Some(iterations as i64);
        Ok((solver, resolved))
    }
}
