//! Issue 12, item 3: moving pinned regions (`[[effects.pinned]]`), what is
//! refused and how the scene reads them: a region driven into the ground
//! stops the run with a message, a motion with bad numbers is bad input
//! naming `effects.pinned[i]`, and the scene keys are read into the effects
//! or refused with messages naming `effects.pinned[i].key`. The regions'
//! paths and forces: `moving_boundaries`.

use crate::moving_boundaries::material;
use elasto::material::MaterialModel;
use elasto::math::{Vector, Vector3};
use elasto::mesh::Mesh;
use elasto::scene::{Scene, SceneError, SceneSource};
use elasto::sim::{Effects, Ground, PinMotion, PinRegion, Simulation, SimulationSettings};

/// A region driven into the ground is refused before the solve.
#[test]
fn a_move_into_the_ground_is_refused() {
    let mesh = Mesh::axis_aligned_box(
        Vector::<2>::new(0.0, 0.5),
        Vector::<2>::new(1.0, 1.5),
        [2, 2],
    )
    .unwrap();
    let plate =
        PinRegion::new(Vector::<2>::new(-1.0, 0.4), Vector::<2>::new(2.0, 0.6)).moving(PinMotion {
            velocity: Vector::<2>::new(0.0, -1.0),
            ..PinMotion::default()
        });
    let effects = Effects {
        gravity: None,
        ground: Some(Ground {
            height: 0.0,
            activation_distance: 0.1,
            stiffness: None,
            friction: 0.0,
        }),
        contact: None,
        pinned: vec![plate],
        obstacles: Vec::new(),
    };
    let settings = SimulationSettings {
        dt: 0.1,
        ..Default::default()
    };
    let mut sim = Simulation::new(
        mesh,
        material(MaterialModel::NeoHookean, 100.0, 0.3),
        1.0,
        effects,
        settings,
        Vector::<2>::zeros(),
    )
    .unwrap();
    let mut outcome = Ok(());
    for _ in 0..10 {
        if let Err(e) = sim.step() {
            outcome = Err(e);
            break;
        }
        assert!(sim.frame_stats().min_height.unwrap() > 0.0);
    }
    let text = outcome.unwrap_err().to_string();
    assert!(text.contains("on or below the ground"), "{text}");
    // Steps 0..4 reach heights 0.4 .. 0.1; the 5th would reach 0.
    assert_eq!(sim.step_count(), 4);
}

fn load(text: &str) -> Result<Scene, SceneError> {
    let source = SceneSource {
        label: "test.toml".into(),
        default_name: "test".into(),
        path: None,
        text: text.into(),
    };
    Scene::load(&source, &[])
}

const BAR_2D: &str = "dimension = 2\n\n[mesh]\nsize = [4.0, 1.0]\ncells = [4, 1]\n\n\
                      [material]\nmodel = \"neo-hookean\"\nyoung = 100.0\npoisson = 0.3\n";
const BAR_3D: &str = "dimension = 3\n\n[mesh]\nsize = [4.0, 1.0, 1.0]\ncells = [4, 1, 1]\n\n\
                      [material]\nmodel = \"neo-hookean\"\nyoung = 100.0\npoisson = 0.3\n";

/// `[[effects.pinned]]` regions read into the effects, with their motion
/// and the centre of the box as the default centre of rotation; the old
/// single `[effects.pinned]` table still reads as one region.
#[test]
fn pinned_regions_are_read_from_the_scene() {
    let text = format!(
        "{BAR_3D}\n[[effects.pinned]]\nmin = [-1, -1, -1]\nmax = [0, 2, 2]\n\
         angular_velocity = -1.2566\naxis = [2, 0, 0]\nuntil = 5.0\n\n\
         [[effects.pinned]]\nmin = [4, -1, -1]\nmax = [5, 2, 2]\nvelocity = [0.1, 0, 0]\n"
    );
    let Scene::Three(c) = load(&text).unwrap() else {
        panic!("3D")
    };
    assert_eq!(c.effects.pinned.len(), 2);
    let twist = c.effects.pinned[0].motion;
    assert_eq!(twist.angular_velocity, -1.2566);
    assert_eq!(twist.axis, Vector3::x());
    assert_eq!(twist.center, Vector3::new(-0.5, 0.5, 0.5));
    assert_eq!(twist.until, Some(5.0));
    assert_eq!(
        c.effects.pinned[1].motion.velocity,
        Vector3::new(0.1, 0.0, 0.0)
    );
    assert_eq!(c.effects.pinned[1].motion.until, None);
    let old = format!("{BAR_2D}\n[effects.pinned]\nmin = [-1, -1]\nmax = [0, 2]\n");
    let Scene::Two(c) = load(&old).unwrap() else {
        panic!("2D")
    };
    assert_eq!(c.effects.pinned.len(), 1);
    assert!(!c.effects.pinned[0].motion.is_moving());
}

/// Every bad region key is named with its index.
#[test]
fn bad_region_keys_are_named_with_their_index() {
    let region0 = "[[effects.pinned]]\nmin = [-1, -1]\nmax = [0, 2]\n";
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            BAR_2D,
            "axis = [0, 0, 1]\nangular_velocity = 1.0\n",
            "effects.pinned[1].axis",
            "3D key",
        ),
        (
            BAR_2D,
            "velocity = [1, 2, 3]\n",
            "effects.pinned[1].velocity",
            "2 components",
        ),
        (
            BAR_2D,
            "velocity = [nan, 0]\n",
            "effects.pinned[1].velocity",
            "finite",
        ),
        (
            BAR_2D,
            "angular_velocity = inf\n",
            "effects.pinned[1].angular_velocity",
            "finite",
        ),
        (
            BAR_2D,
            "center = [1, 1]\n",
            "effects.pinned[1].center",
            "without",
        ),
        (
            BAR_2D,
            "until = 1.0\n",
            "effects.pinned[1].until",
            "does not move",
        ),
        (
            BAR_2D,
            "velocity = [1, 0]\nuntil = -1.0\n",
            "effects.pinned[1].until",
            ">= 0",
        ),
        (
            BAR_2D,
            "speed = 1.0\n",
            "effects.pinned[1].speed",
            "unknown field",
        ),
        (
            BAR_3D,
            "angular_velocity = 1.0\n",
            "effects.pinned[1].axis",
            "required",
        ),
        (
            BAR_3D,
            "angular_velocity = 1.0\naxis = [0, 0, 0]\n",
            "effects.pinned[1].axis",
            "non-zero",
        ),
    ];
    for (scene, extra, key, words) in cases {
        let (min, max) = if scene.contains("dimension = 2") {
            ("[4, -1]", "[5, 2]")
        } else {
            ("[4, -1, -1]", "[5, 2, 2]")
        };
        let first = if scene.contains("dimension = 2") {
            region0.to_owned()
        } else {
            "[[effects.pinned]]\nmin = [-1, -1, -1]\nmax = [0, 2, 2]\n".to_owned()
        };
        let text =
            format!("{scene}\n{first}\n[[effects.pinned]]\nmin = {min}\nmax = {max}\n{extra}");
        let Err(SceneError::Invalid(d)) = load(&text) else {
            panic!("{extra}: expected an error")
        };
        assert_eq!(d.key.as_deref(), Some(*key), "{extra}: {d}");
        assert!(d.reason.contains(words), "{extra}: {d}");
        assert!(d.to_string().starts_with("test.toml:"), "{d}");
    }
    // A region that catches nothing is named by its index too.
    let text = format!("{BAR_2D}\n{region0}\n[[effects.pinned]]\nmin = [9, 9]\nmax = [10, 10]\n");
    let Err(SceneError::Invalid(d)) = load(&text) else {
        panic!("expected an error")
    };
    assert_eq!(d.key.as_deref(), Some("effects.pinned[1]"), "{d}");
}
