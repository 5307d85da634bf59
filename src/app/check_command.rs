//! `elasto check`: validate a scene and print what would be simulated.

use super::cli::CheckArgs;
use super::{AppError, SceneInput, build_simulation, scene_overrides};
use crate::energy::FrictionSettings;
use crate::scene::{FieldChoice, Scene, SceneConfig, SceneSource};
use crate::solver::{Projection, SolverMethod};
use std::fmt::Write as _;

/// Runs `elasto check`, returning the summary it prints.
pub fn check(args: &CheckArgs) -> Result<String, AppError> {
    let source = SceneSource::resolve(Some(&args.scene))?;
    let overrides = scene_overrides(&args.set)?;
    let scene = Scene::load(&source, &overrides)?;
    let input = SceneInput {
        source: &source,
        overrides: &overrides,
    };
    let setup = match &scene {
        Scene::Two(c) => set_up(c, input)?,
        Scene::Three(c) => set_up(c, input)?,
    };
    Ok(summary(&source, &scene, &setup))
}

/// What building the simulation tells: the barrier stiffness in use and the
/// initial energies, by term.
struct Setup {
    barrier: Option<f64>,
    /// `d_hat`, the stiffness before the first step, and whether it adapts.
    contact: Option<(f64, f64, bool, bool)>,
    friction: Option<FrictionSettings>,
    energies: Vec<(&'static str, f64)>,
}

/// Builds the mesh and the simulation (no stepping) so that every setup error
/// shows here, and reads the barrier stiffness and the initial energies.
fn set_up<const D: usize>(config: &SceneConfig<D>, input: SceneInput) -> Result<Setup, AppError> {
    let sim = build_simulation(config, input)?;
    let energy = sim.energies();
    let mut energies: Vec<(&'static str, f64)> = energy.entries().collect();
    energies.push(("total", energy.total()));
    Ok(Setup {
        barrier: sim.ground().map(|g| g.stiffness()),
        contact: sim.contact().map(|c| {
            (
                c.activation_distance(),
                c.stiffness(),
                c.is_adaptive(),
                config.effects.contact.is_some_and(|c| c.self_contact),
            )
        }),
        friction: sim.friction().map(|f| f.settings()),
        energies,
    })
}

fn summary(source: &SceneSource, scene: &Scene, setup: &Setup) -> String {
    let barrier = setup.barrier;
    let mut s = String::new();
    let time = scene.time();
    let solver = scene.solver();
    let effects = scene.effect_names();
    let render = scene.render();
    let _ = writeln!(s, "scene `{}` ({}) is valid", scene.name(), source.label);
    for warning in scene.warnings() {
        let _ = writeln!(s, "  warning         {warning}");
    }
    let _ = writeln!(s, "  dimension       {}", scene.dimension());
    let _ = writeln!(
        s,
        "  mesh            {} vertices, {} elements",
        scene.vertex_count(),
        scene.element_count()
    );
    if scene.body_count() > 1 {
        let _ = writeln!(
            s,
            "  bodies          {}{}",
            scene.body_count(),
            if setup.contact.is_some() {
                ""
            } else {
                " (they do not collide with each other)"
            }
        );
    }
    for report in scene.import_reports() {
        let _ = writeln!(s, "  mesh file       {report}");
    }
    for material in scene.materials() {
        let constants: Vec<String> = material
            .material
            .parameters()
            .iter()
            .map(|(name, value)| format!("{name} = {value}"))
            .collect();
        let _ = writeln!(
            s,
            "  material        {}, {}, density = {}",
            material.model_name(),
            constants.join(", "),
            material.density
        );
    }
    let _ = writeln!(
        s,
        "  effects         {}",
        if effects.is_empty() {
            "none".into()
        } else {
            effects.join(", ")
        }
    );
    let energies: Vec<String> = setup
        .energies
        .iter()
        .map(|(name, value)| format!("{name} = {value:.6e}"))
        .collect();
    let _ = writeln!(s, "  energy at t = 0 {}", energies.join(", "));
    if let Some(ground) = scene.ground() {
        let _ = writeln!(
            s,
            "  ground          height {}, barrier width a = {}, stiffness kappa = {}",
            ground.height,
            ground.activation_distance,
            barrier.map_or("?".into(), |k| format!("{k}"))
        );
    }
    if let Some((distance, kappa, adaptive, self_contact)) = setup.contact {
        let rule = if adaptive {
            "adaptive (IPC), before the first step"
        } else {
            "fixed"
        };
        let _ = writeln!(
            s,
            "  contact         d_hat = {distance}, stiffness kappa = {kappa:.6e} ({rule}), \
             self-contact {}",
            if self_contact { "on" } else { "off" }
        );
    }
    for (k, line) in scene.obstacle_lines().iter().enumerate() {
        let _ = writeln!(s, "  obstacle {k:<6} {line}");
    }
    if let Some(friction) = setup.friction {
        let _ = writeln!(
            s,
            "  friction        mu = {} against the ground, {} between bodies, \
             velocity threshold eps_v = {} (length/s), {} solve(s) per step",
            friction.ground,
            friction.contact,
            friction.velocity_threshold,
            solver.friction_iterations
        );
    }
    let _ = writeln!(
        s,
        "  time            dt = {:.6e} s, {} substeps per frame, {} frames at {} fps ({} s)",
        time.dt,
        time.substeps,
        time.frames,
        time.fps,
        time.frames as f64 / time.fps
    );
    let method = match (solver.method, solver.projection) {
        (SolverMethod::Newton, Projection::OnDemand) => "newton (projection on demand)".to_owned(),
        (SolverMethod::Newton, Projection::Always) => "newton (projection always)".to_owned(),
        (SolverMethod::GradientDescent { step }, _) => format!("gradient-descent (step {step})"),
    };
    let _ = writeln!(
        s,
        "  solver          {method}, tolerance {} length/s, at most {} iterations per step",
        solver.tolerance, solver.max_iterations
    );
    let field = match scene.field() {
        FieldChoice::Flat => "flat colour".to_owned(),
        f => f.name().to_owned(),
    };
    let _ = writeln!(
        s,
        "  render          {}x{}, {field}",
        render.width, render.height
    );
    s
}
