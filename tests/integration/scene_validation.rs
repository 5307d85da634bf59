//! Scene files: parsing, defaults, overrides and every validation error, through the library API.

use elasto::energy::ElementField;
use elasto::material::Material;
use elasto::render::{Camera, Colouring, RenderSettings};
use elasto::scene::{
    BUILTIN_SCENES, BoxMesh, Diagnostic, FieldChoice, MaterialConfig, Origin, Scene, SceneConfig,
    SceneError, SceneOverride, SceneSource, TimeConfig,
};
use elasto::solver::{SolverMethod, SolverSettings};

const MINIMAL: &str = r#"dimension = 2

[mesh]
size = [1.0, 1.0]
cells = [5, 5]
offset = [0.0, 10.0]

[material]
model = "stvk"
young = 300.0
poisson = 0.3
"#;

fn source(text: &str) -> SceneSource {
    SceneSource {
        label: "test.toml".into(),
        default_name: "test".into(),
        path: None,
        text: text.into(),
    }
}

fn load(text: &str) -> Result<Scene, SceneError> {
    Scene::load(&source(text), &[])
}

fn load_with(text: &str, sets: &[&str]) -> Result<Scene, SceneError> {
    let overrides: Vec<SceneOverride> = sets.iter().map(|s| s.parse().unwrap()).collect();
    Scene::load(&source(text), &overrides)
}

fn diagnostic(result: Result<Scene, SceneError>) -> Diagnostic {
    match result {
        Ok(_) => panic!("expected an error"),
        Err(SceneError::Invalid(d)) => *d,
        Err(e) => panic!("expected a scene diagnostic, got {e}"),
    }
}

/// Replaces the first line starting with `key =` (or appends under `[table]`).
fn edit(text: &str, old: &str, new: &str) -> String {
    assert!(text.contains(old), "{old} not in scene");
    text.replacen(old, new, 1)
}

fn line_of(d: &Diagnostic) -> usize {
    match d.origin {
        Origin::File { line, .. } => line,
        ref o => panic!("expected a file position, got {o:?}"),
    }
}

#[test]
fn minimal_scene_gets_documented_defaults() {
    let Scene::Two(c) = load(MINIMAL).unwrap() else {
        panic!("2D")
    };
    assert_eq!(c.name, "test");
    assert_eq!(c.bodies[0].mesh.as_box().unwrap().cells, [5, 5]);
    assert_eq!(
        c.bodies[0].mesh.as_box().unwrap().offset.as_slice(),
        &[0.0, 10.0]
    );
    assert_eq!(c.bodies[0].initial_velocity.as_slice(), &[0.0, 0.0]);
    assert_eq!(c.bodies[0].material.density, 1.0);
    let Material::StVenantKirchhoff(m) = c.bodies[0].material.material else {
        panic!("stvk")
    };
    // E = 300, nu = 0.3: mu = 300 / 2.6, lambda = 90 / (1.3 * 0.4).
    assert!((m.lame.mu - 115.38461538461539).abs() < 1e-9);
    assert!((m.lame.lambda - 173.07692307692307).abs() < 1e-9);
    assert_eq!(
        (c.time.fps, c.time.substeps, c.time.frames),
        (30.0, 10, 300)
    );
    assert!((c.time.dt - 1.0 / 300.0).abs() < 1e-15);
    assert_eq!(c.solver.method, SolverMethod::Newton);
    // The tolerance scales with the scene: 1e-3 of the 1 x 1 box's
    // diagonal, per second.
    assert!((c.solver.tolerance - 1e-3 * 2f64.sqrt()).abs() < 1e-15);
    assert_eq!(c.solver.max_iterations, 50);
    // Absent effects do not exist.
    assert_eq!(
        (c.effects.gravity, c.effects.ground, c.effects.pinned.len()),
        (None, None, 0)
    );
    assert_eq!([c.render.width, c.render.height], [1280, 720]);
    assert_eq!(c.field, FieldChoice::Scalar(ElementField::EnergyDensity));
    assert_eq!(c.render.camera, Camera::Auto);
    assert!(c.render.draw_edges && c.render.draw_legend);
}

#[test]
fn the_settings_types_default_to_the_scene_file_defaults() {
    let Scene::Two(c) = load(MINIMAL).unwrap() else {
        panic!("2D")
    };
    assert_eq!(c.time, TimeConfig::default());
    // All but the tolerance, which a scene scales with its size (1e-3 of
    // the 1 x 1 box's diagonal per second) and the library cannot know.
    assert_eq!(
        c.solver,
        SolverSettings {
            tolerance: 1e-3 * 2f64.sqrt(),
            ..SolverSettings::default()
        }
    );
    assert_eq!(c.field, FieldChoice::default());
    assert_eq!(
        c.bodies[0].material.density,
        MaterialConfig::default().density
    );
    assert_eq!(
        c.bodies[0].initial_velocity,
        SceneConfig::<2>::default().bodies[0].initial_velocity
    );
    // MINIMAL sets the offset; without it the box starts at the default corner.
    let Scene::Two(m) = load(&edit(MINIMAL, "offset = [0.0, 10.0]\n", "")).unwrap() else {
        panic!("2D")
    };
    assert_eq!(
        m.bodies[0].mesh.as_box().unwrap().offset,
        BoxMesh::<2>::default().offset
    );
    // The render settings are the renderer's type, with the renderer's defaults
    // except for what the scene names: the legend title of its field.
    assert_eq!(
        c.render,
        RenderSettings {
            colouring: Colouring::Scalar {
                range: None,
                label: "strain energy density"
            },
            ..RenderSettings::default()
        }
    );
    // With a ground, the renderer draws it where the scene puts it.
    let Scene::Two(c) = load(&format!("{MINIMAL}[effects.ground]\nheight = -0.5\n")).unwrap()
    else {
        panic!("2D")
    };
    assert_eq!(c.render.ground_height, Some(-0.5));
}

#[test]
fn every_builtin_scene_is_valid_and_matches_its_name() {
    assert_eq!(BUILTIN_SCENES.len(), 6);
    for b in BUILTIN_SCENES {
        let scene = Scene::load(&SceneSource::from_builtin(b), &[])
            .unwrap_or_else(|e| panic!("{}: {e}", b.name));
        assert_eq!(scene.name(), b.name);
        // The embedded text is the shipped file.
        let shipped = std::fs::read_to_string(format!(
            "{}/scenes/{}.toml",
            env!("CARGO_MANIFEST_DIR"),
            b.name
        ))
        .unwrap();
        assert_eq!(shipped, b.toml);
    }
    let drop = Scene::load(&SceneSource::resolve(None).unwrap(), &[]).unwrap();
    assert_eq!(drop.name(), "report-drop-2d");
    let Scene::Two(c) = drop else { panic!("2D") };
    assert_eq!(c.bodies[0].mesh.as_box().unwrap().cells, [5, 5]);
    assert_eq!(c.bodies[0].mesh.as_box().unwrap().offset[1], 10.0);
    assert_eq!(c.effects.gravity.unwrap().as_slice(), &[0.0, -1.0]);
    let ground = c.effects.ground.unwrap();
    assert_eq!((ground.height, ground.activation_distance), (0.0, 0.1));
}

#[test]
fn three_d_scene_with_lame_parameters_and_camera() {
    let text = r#"dimension = 3
[mesh]
size = [1, 2, 3]
cells = [1, 2, 3]
[material]
model = "neo-hookean"
mu = 10.0
lambda = 20.0
[time]
dt = 0.01
fps = 25
duration = 2.0
[render.camera]
eye = [3, 3, 3]
target = [0, 0, 0]
"#;
    let Scene::Three(c) = load(text).unwrap() else {
        panic!("3D")
    };
    assert_eq!(
        c.bodies[0].mesh.as_box().unwrap().size.as_slice(),
        &[1.0, 2.0, 3.0]
    );
    let Material::NeoHookean(m) = c.bodies[0].material.material else {
        panic!("neo-hookean")
    };
    assert_eq!((m.lame.mu, m.lame.lambda), (10.0, 20.0));
    // dt = 0.01 at 25 fps is 4 substeps; 2 s at 25 fps is 50 frames.
    assert_eq!((c.time.substeps, c.time.frames), (4, 50));
    assert_eq!(
        c.render.camera,
        Camera::Perspective {
            eye: [3.0; 3],
            target: [0.0; 3],
            fov_degrees: 35.0
        }
    );
    let scene = Scene::Three(c);
    assert_eq!(scene.vertex_count(), 2 * 3 * 4);
    assert_eq!(scene.element_count(), 6 * 6);
}

#[test]
fn errors_name_the_file_the_key_and_the_line() {
    // (edit of the minimal scene, expected key, expected line, words in the reason)
    let cases: &[(&str, &str, &str, usize, &str)] = &[
        ("young = 300.0", "young = -3.0", "material.young", 10, "> 0"),
        ("young = 300.0", "young = 0.0", "material.young", 10, "> 0"),
        (
            "poisson = 0.3",
            "poisson = 0.5",
            "material.poisson",
            11,
            "(-1, 0.5)",
        ),
        (
            "poisson = 0.3",
            "poisson = -1.0",
            "material.poisson",
            11,
            "(-1, 0.5)",
        ),
        (
            "young = 300.0",
            "young = \"stiff\"",
            "material.young",
            10,
            "invalid type",
        ),
        (
            "young = 300.0",
            "youngs = 300.0",
            "material.youngs",
            10,
            "unknown field",
        ),
        (
            "cells = [5, 5]",
            "cells = [5, 0]",
            "mesh.cells",
            5,
            "at least 1",
        ),
        (
            "cells = [5, 5]",
            "cells = [5, 5, 5]",
            "mesh.cells",
            5,
            "2 components",
        ),
        (
            "size = [1.0, 1.0]",
            "size = [1.0, -1.0]",
            "mesh.size",
            4,
            "> 0",
        ),
        ("dimension = 2", "dimension = 4", "dimension", 1, "2 or 3"),
        (
            "model = \"stvk\"",
            "model = \"rubber\"",
            "material.model",
            9,
            "unknown variant",
        ),
    ];
    for (old, new, key, line, words) in cases {
        let d = diagnostic(load(&edit(MINIMAL, old, new)));
        assert_eq!(d.source, "test.toml");
        assert_eq!(d.key.as_deref(), Some(*key), "{new}: {d}");
        assert_eq!(line_of(&d), *line, "{new}: {d}");
        assert!(d.reason.contains(words), "{new}: {d}");
        let text = d.to_string();
        assert!(
            text.starts_with(&format!("test.toml:{line}:")) && text.contains(key),
            "{text}"
        );
    }
}

#[test]
fn errors_in_optional_tables() {
    let with = |extra: &str| format!("{MINIMAL}{extra}");
    let cases: &[(&str, &str, &str)] = &[
        ("[time]\nframes = 0\n", "time.frames", "at least 1"),
        ("[time]\ndt = 0.0\n", "time.dt", "> 0"),
        ("[time]\ndt = -0.1\n", "time.dt", "> 0"),
        ("[time]\ndt = nan\n", "time.dt", "> 0"),
        ("[time]\ndt = 0.004\n", "time.dt", "whole steps"),
        (
            "[time]\ndt = 0.00166667\nsubsteps = 10\n",
            "time.dt",
            "substeps = 10",
        ),
        (
            "[time]\nframes = 3\nduration = 1.0\n",
            "time.duration",
            "not both",
        ),
        ("[time]\nfps = 0\n", "time.fps", "> 0"),
        ("[solver]\ntolerance = 0.0\n", "solver.tolerance", "> 0"),
        ("[solver]\nstep = 1e-6\n", "solver.step", "gradient-descent"),
        (
            "[solver]\nmethod = \"gradient-descent\"\nprojection = \"on-demand\"\n",
            "solver.projection",
            "only used with method = \"newton\"",
        ),
        (
            "[solver]\nprojection = \"sometimes\"\n",
            "solver.projection",
            "`always` or `on-demand`",
        ),
        (
            "[solver]\nmethod = \"gradient-descent\"\nstep = -1.0\n",
            "solver.step",
            "> 0",
        ),
        (
            "[solver]\nmax_iterations = 0\n",
            "solver.max_iterations",
            "at least 1",
        ),
        ("[effects.ground]\na = -0.1\n", "effects.ground.a", "> 0"),
        (
            "[effects.ground]\nkappa = 0\n",
            "effects.ground.kappa",
            "> 0",
        ),
        ("[effects.ground]\nheight = 10.0\n", "mesh.offset", "ground"),
        ("[effects.ground]\nheight = 10.5\n", "mesh.offset", "ground"),
        (
            "[effects.gravity]\nacceleration = [0.0, -1.0, 0.0]\n",
            "effects.gravity.acceleration",
            "2 components",
        ),
        (
            "[effects.gravity]\n",
            "effects.gravity",
            "missing field `acceleration`",
        ),
        (
            "[effects.wind]\nspeed = 1\n",
            "effects.wind",
            "unknown field",
        ),
        (
            "[effects.pinned]\nmin = [2, 2]\nmax = [3, 3]\n",
            "effects.pinned",
            "no mesh vertex",
        ),
        (
            "[effects.pinned]\nmin = [0.5, 10.1]\nmax = [0.55, 10.9]\n",
            "effects.pinned",
            "no mesh vertex",
        ),
        (
            "[effects.pinned]\nmin = [1, 1]\nmax = [0, 0]\n",
            "effects.pinned.max",
            "below",
        ),
        (
            "[render]\nresolution = [0, 10]\n",
            "render.resolution",
            "pixels",
        ),
        (
            "[render]\nfield = \"pressure\"\n",
            "render.field",
            "unknown variant",
        ),
        (
            "[render]\nrange = [1.0, 0.0]\n",
            "render.range",
            "low < high",
        ),
        (
            "[render]\ncolour = [1.5, 0.0, 0.0]\n",
            "render.colour",
            "[0, 1]",
        ),
        (
            "[render.camera]\ncenter = [0, 0]\n",
            "render.camera.height",
            "required",
        ),
        (
            "[render.camera]\neye = [1, 1, 1]\n",
            "render.camera.eye",
            "3D camera key",
        ),
    ];
    for (extra, key, words) in cases {
        let d = diagnostic(load(&with(extra)));
        assert_eq!(d.key.as_deref(), Some(*key), "{extra}: {d}");
        assert!(d.reason.contains(words), "{extra}: {d}");
        // Every one of these keys (or its table) sits after the minimal scene's 11 lines.
        assert!(line_of(&d) >= 12 || *key == "mesh.offset", "{extra}: {d}");
    }
}

#[test]
fn material_stiffness_needs_exactly_one_pair() {
    let both = edit(
        MINIMAL,
        "poisson = 0.3",
        "poisson = 0.3\nmu = 1.0\nlambda = 1.0",
    );
    let d = diagnostic(load(&both));
    assert_eq!(d.key.as_deref(), Some("material.mu"));
    assert!(d.reason.contains("not both"), "{d}");
    let half = edit(MINIMAL, "poisson = 0.3\n", "");
    let d = diagnostic(load(&half));
    assert_eq!(d.key.as_deref(), Some("material.poisson"));
    assert!(d.reason.contains("together with `young`"), "{d}");
    // Reported at the [material] table, since the key itself is absent.
    assert_eq!(line_of(&d), 8);
    let none = edit(
        edit(MINIMAL, "poisson = 0.3\n", "").as_str(),
        "young = 300.0\n",
        "",
    );
    let d = diagnostic(load(&none));
    assert_eq!(d.key.as_deref(), Some("material"));
}

#[test]
fn malformed_toml_gives_the_line_and_column() {
    let d = diagnostic(load(&edit(MINIMAL, "young = 300.0", "young = = 300.0")));
    assert_eq!(d.key, None);
    assert_eq!(line_of(&d), 10);
    assert!(d.reason.starts_with("invalid TOML"), "{d}");
    let d = diagnostic(load(&edit(MINIMAL, "[material]", "[material")));
    assert_eq!(line_of(&d), 8);
    // A duplicate key is a TOML error too.
    let d = diagnostic(load(&edit(
        MINIMAL,
        "poisson = 0.3",
        "poisson = 0.3\npoisson = 0.2",
    )));
    assert_eq!(line_of(&d), 12);
}

#[test]
fn missing_required_keys_are_named() {
    let d = diagnostic(load(&edit(MINIMAL, "dimension = 2\n", "")));
    assert!(d.reason.contains("missing field `dimension`"), "{d}");
    let d = diagnostic(load(&edit(MINIMAL, "cells = [5, 5]\n", "")));
    assert!(
        d.reason.contains("is required with generator = \"box\""),
        "{d}"
    );
    assert_eq!(d.key.as_deref(), Some("mesh.cells"), "{d}");
}

#[test]
fn overrides_apply_before_validation_and_are_named_in_errors() {
    let Scene::Two(c) = load_with(
        MINIMAL,
        &[
            "material.young=1e3",
            "time.frames=2",
            "material.model=neo-hookean",
            "effects.gravity.acceleration=[0, -9.81]",
            "name=\"renamed\"",
        ],
    )
    .unwrap() else {
        panic!("2D")
    };
    assert_eq!(c.name, "renamed");
    assert_eq!(c.time.frames, 2);
    assert!(matches!(
        c.bodies[0].material.material,
        Material::NeoHookean(_)
    ));
    assert!((c.bodies[0].material.material.parameter("mu").unwrap() - 1e3 / 2.6).abs() < 1e-9);
    // The override created the effect: it exists only because it was asked for.
    assert_eq!(c.effects.gravity.unwrap().as_slice(), &[0.0, -9.81]);

    let cases: &[(&str, &str, &str)] = &[
        ("material.young=-5", "material.young", "> 0"),
        ("material.youngs=5", "material.youngs", "unknown field"),
        ("materials.young=5", "materials", "unknown field"),
        ("time.frames=0", "time.frames", "at least 1"),
        ("time.frames=abc", "time.frames", "invalid type"),
        ("mesh.size.x=1", "mesh.size.x", "not a table"),
    ];
    for (set, key, words) in cases {
        let d = diagnostic(load_with(MINIMAL, &[set]));
        assert_eq!(d.origin, Origin::Flag(format!("--set {set}")), "{set}: {d}");
        assert_eq!(d.key.as_deref(), Some(*key), "{set}: {d}");
        assert!(d.reason.contains(words), "{set}: {d}");
        assert!(d.to_string().starts_with(&format!("--set {set}")), "{d}");
    }
    // An error in the file is still reported at its line when overrides exist.
    let d = diagnostic(load_with(
        &edit(MINIMAL, "poisson = 0.3", "poisson = 0.7"),
        &["time.frames=2"],
    ));
    assert_eq!(
        (d.key.as_deref(), line_of(&d)),
        (Some("material.poisson"), 11)
    );
}

#[test]
fn the_resolved_scene_reproduces_the_scene() {
    let text = format!(
        "{MINIMAL}[time]\ndt = 0.00166667\nduration = 1.0\n[solver]\nmethod = \"gradient-descent\"\n"
    );
    let (scene, resolved) =
        Scene::load_resolved(&source(&text), &["material.density=2.5".parse().unwrap()]).unwrap();
    // Defaults are written out explicitly.
    for line in [
        "substeps = 20",
        "frames = 30",
        "density = 2.5",
        "max_iterations = 10000",
        "step = 0.000001",
    ] {
        assert!(resolved.contains(line), "{line} missing from\n{resolved}");
    }
    assert!(!resolved.contains("dt ="), "{resolved}");
    let again = Scene::load(&source(&resolved), &[]).unwrap();
    assert_eq!(again, scene);
    // Built-ins round-trip too.
    for b in BUILTIN_SCENES {
        let (scene, resolved) = Scene::load_resolved(&SceneSource::from_builtin(b), &[]).unwrap();
        assert_eq!(
            Scene::load(&source(&resolved), &[]).unwrap(),
            scene,
            "{}",
            b.name
        );
    }
}

#[test]
fn unknown_scene_names_list_the_builtins() {
    let err = SceneSource::resolve(Some("no-such-scene")).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("no-such-scene")
            && text.contains("report-drop-2d")
            && text.contains("hanging-bar-3d")
    );
}
