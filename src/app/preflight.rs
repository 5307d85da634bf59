//! Checks made after the scene is validated and before any work or file,
//! of what the scene validator cannot know: what the run will allocate
//! against this machine's memory (before any mesh is built), the image size
//! against the graphics adapter, and the starting energy of the built
//! simulation. Each failure is a scene error at its key (exit code 2).

use super::AppError;
use crate::render::RenderSettings;
use crate::scene::{Scene, SceneConfig, SceneOverride, SceneSource, approx, image_bytes};
use crate::sim::Simulation;

/// A scene's source and overrides, to report a problem at its key.
#[derive(Clone, Copy)]
pub(crate) struct SceneInput<'a> {
    /// The scene file or built-in scene.
    pub source: &'a SceneSource,
    /// The `--set` (and shortcut flag) overrides.
    pub overrides: &'a [SceneOverride],
}

impl SceneInput<'_> {
    /// A scene error at `key`, located like the validator's.
    pub fn error(&self, key: &str, reason: impl Into<String>) -> AppError {
        AppError::Scene(Scene::key_error(self.source, self.overrides, key, reason))
    }
}

/// Memory a simulation certainly takes per element, in bytes (index: the
/// dimension): an estimate from below. Measured peaks are 1.6-2.1 KB per
/// triangle and 4-7 KB per tetrahedron (the sparse factorisation grows
/// faster than the mesh in 3D).
const SIMULATION_BYTES_PER_ELEMENT: [u64; 4] = [0, 0, 1024, 2048];

/// Bytes the simulation of `config` takes at least.
fn simulation_bytes<const D: usize>(config: &SceneConfig<D>) -> u64 {
    config.element_count() as u64 * SIMULATION_BYTES_PER_ELEMENT[D]
}

/// Bytes one frame kept for rendering after the run takes: positions as
/// three 32-bit floats per vertex and one per element.
fn kept_frame_bytes<const D: usize>(config: &SceneConfig<D>) -> u64 {
    12 * config.vertex_count() as u64 + 4 * config.element_count() as u64 + 48
}

/// This machine's memory in bytes: the physical memory, or a smaller
/// control-group limit; `None` when unknown (not Linux).
fn machine_memory() -> Option<u64> {
    let physical = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
            let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kib * 1024)
        })?;
    let limit = std::fs::read_to_string("/sys/fs/cgroup/memory.max")
        .ok()
        .and_then(|t| t.trim().parse::<u64>().ok());
    Some(limit.map_or(physical, |l| l.min(physical)))
}

/// A byte count for messages, e.g. `3.4 GB`.
fn bytes(n: u64) -> String {
    let n = n as f64;
    match n {
        _ if n >= 1e12 => format!("{:.1} TB", n / 1e12),
        _ if n >= 1e9 => format!("{:.1} GB", n / 1e9),
        _ => format!("{:.0} MB", n / 1e6),
    }
}

/// The simulation of `config` must fit in this machine's memory.
pub(crate) fn check_simulation_memory<const D: usize>(
    config: &SceneConfig<D>,
    input: SceneInput,
) -> Result<(), AppError> {
    let Some(memory) = machine_memory() else {
        return Ok(());
    };
    let needed = simulation_bytes(config);
    if needed > memory {
        let key = match (&config.bodies[..], &config.bodies[0].mesh) {
            ([_, _, ..], _) => "bodies",
            (_, crate::scene::MeshConfig::Box(_)) => "mesh.cells",
            (_, crate::scene::MeshConfig::File(_)) => "mesh.path",
        };
        return Err(input.error(
            key,
            format!(
                "the simulation of {} elements needs at least {}, more than this machine's {}",
                config.element_count(),
                bytes(needed),
                bytes(memory)
            ),
        ));
    }
    Ok(())
}

/// The frames a run keeps for the automatic camera and colour range, with
/// the simulation, must fit in this machine's memory.
pub(crate) fn check_kept_frames<const D: usize>(
    config: &SceneConfig<D>,
    input: SceneInput,
) -> Result<(), AppError> {
    let Some(memory) = machine_memory() else {
        return Ok(());
    };
    let frames = config.time.frames as u64;
    let kept = frames.saturating_mul(kept_frame_bytes(config));
    let needed = kept.saturating_add(simulation_bytes(config));
    if needed > memory {
        return Err(input.error(
            "time.frames",
            format!(
                "{frames} frames of {} vertices and {} elements need {} kept in memory for \
                 the automatic camera and colour range, more than this machine's {}; fix \
                 `render.camera` and `render.range` (frames are then rendered as they are \
                 simulated), render fewer frames, or pass --no-render",
                config.vertex_count(),
                config.element_count(),
                bytes(kept),
                bytes(memory)
            ),
        ));
    }
    Ok(())
}

/// Why an image of `width` x `height` does not fit a device with textures
/// of at most `max_side` pixels per side and buffers of `max_bytes`.
pub(crate) fn image_problem(
    width: u32,
    height: u32,
    max_side: u32,
    max_bytes: u64,
) -> Option<String> {
    if width > max_side || height > max_side {
        return Some(format!(
            "{width}x{height} exceeds this graphics adapter's limit of {max_side} pixels per side"
        ));
    }
    let needed = image_bytes(width, height);
    if needed > max_bytes {
        return Some(format!(
            "{width}x{height} needs a read-back buffer of {needed} bytes, more than this \
             graphics adapter's limit of {max_bytes}"
        ));
    }
    None
}

/// The image size must fit the graphics adapter, whose largest image
/// (`adapter_limits`, from [`crate::render::max_image_size`]) is asked for
/// only when rendering.
pub(crate) fn check_image_size(
    settings: &RenderSettings,
    input: SceneInput,
    adapter_limits: Result<(u32, u64), crate::render::RenderError>,
) -> Result<(), AppError> {
    let (max_side, max_bytes) = adapter_limits.map_err(AppError::Render)?;
    match image_problem(settings.width, settings.height, max_side, max_bytes) {
        Some(reason) => Err(input.error("render.resolution", reason)),
        None => Ok(()),
    }
}

/// Every term of the incremental potential must be finite at the start,
/// weighted by dt² as the first step weighs it, and so must the first
/// step's prediction `x + dt v`.
pub(crate) fn check_starting_energy<const D: usize>(
    config: &SceneConfig<D>,
    sim: &Simulation<D>,
    input: SceneInput,
) -> Result<(), AppError> {
    let dt = config.time.dt;
    let energy = sim.energies();
    let total_mass: f64 = sim.masses().iter().sum();
    let gravity_scale = config
        .effects
        .gravity
        .map_or(0.0, |g| g.norm() * total_mass);
    // Each energy entry (kinetic, then one per term of the scene) with the
    // scene key that sets it.
    let mut terms: Vec<(&str, String, f64)> = energy
        .entries()
        .map(|(name, value)| {
            let key = match name {
                "kinetic" if config.bodies.len() > 1 => "bodies",
                "elastic" if config.bodies.len() > 1 => "bodies",
                "kinetic" => "mesh.velocity",
                "elastic" => "material",
                "gravity" => "effects.gravity.acceleration",
                "barrier" => "effects.ground",
                _ => "effects",
            };
            let what = match name {
                "gravity" => "gravitational energy".to_owned(),
                other => format!("{other} energy"),
            };
            (key, what, value)
        })
        .collect();
    terms.push((
        "effects.gravity.acceleration",
        "weight (|g| times the mass)".to_owned(),
        gravity_scale,
    ));
    for (key, what, value) in terms {
        let weighted = value * dt * dt;
        if !value.is_finite() || !weighted.is_finite() {
            return Err(input.error(
                key,
                format!(
                    "the starting {what} is {} (weighted by dt² = {} in the first step: {}); \
                     the first step cannot be solved in double precision",
                    approx(value),
                    approx(dt * dt),
                    approx(weighted)
                ),
            ));
        }
    }
    let prediction_finite = sim
        .positions()
        .iter()
        .zip(sim.velocities())
        .all(|(x, v)| (x + v * dt).iter().all(|c| c.is_finite()));
    if !prediction_finite {
        let key = if config.bodies.len() > 1 {
            "bodies"
        } else {
            "mesh.velocity"
        };
        return Err(input.error(
            key,
            format!(
                "moves the body out of double precision in the first step (dt = {} s)",
                approx(dt)
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn images_are_checked_against_the_adapters_limits() {
        let max = 256 << 20;
        assert_eq!(image_problem(1280, 720, 8192, max), None);
        assert_eq!(image_problem(8192, 8192, 8192, max), None);
        let side = image_problem(8193, 10, 8192, max).unwrap();
        assert!(side.contains("8192 pixels per side"), "{side}");
        // 8000 x 8500 fits the side but needs 272 000 000 bytes.
        let buffer = image_problem(8000, 8500, 16384, max).unwrap();
        assert!(buffer.contains("272000000 bytes"), "{buffer}");
        assert_eq!(image_problem(4096, 4096, 16384, 64 << 20), None);
        assert!(image_problem(4096, 4097, 16384, 64 << 20).is_some());
    }

    #[test]
    fn byte_counts_read_short() {
        assert_eq!(bytes(20_000_000_000_000), "20.0 TB");
        assert_eq!(bytes(3_400_000_000), "3.4 GB");
        assert_eq!(bytes(350_000_000), "350 MB");
    }
}
