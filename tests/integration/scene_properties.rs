//! Property test (issue 9): randomly mutated scene files and `--set` values
//! never make elasto panic, never make it exit with anything but 0, 1 or 2,
//! and never make it write outside its output folder.
//!
//! Most cases go through the library's load-and-validate path in process
//! (thousands, fast); a few hundred run the real binary (`check`, and `run`
//! of two frames, mostly without rendering) in a folder of their own, where
//! everything written is listed afterwards. The seed is fixed, so a failure
//! reproduces; the failing case is printed with its scene text and flags
//! (`ELASTO_PROPTEST_SEED=N` runs another seed, to explore).

use crate::cli_common as common;
use common::*;

use elasto::scene::{BUILTIN_SCENES, Scene, SceneOverride, SceneSource};
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};
use std::path::{Path, PathBuf};

/// Every key a scene can hold, a few tables, and a few that do not exist.
const KEYS: &[&str] = &[
    "name",
    "dimension",
    "mesh",
    "mesh.generator",
    "mesh.size",
    "mesh.cells",
    "mesh.offset",
    "mesh.velocity",
    "mesh.path",
    "mesh.scale",
    "mesh.rotate",
    "mesh.translate",
    "mesh.orient",
    "mesh.merge_tolerance",
    "bodies",
    "material",
    "material.model",
    "material.young",
    "material.poisson",
    "material.mu",
    "material.lambda",
    "material.density",
    "time.fps",
    "time.substeps",
    "time.dt",
    "time.frames",
    "time.duration",
    "solver.method",
    "solver.tolerance",
    "solver.max_iterations",
    "solver.step",
    "solver.projection",
    "effects",
    "effects.gravity",
    "effects.gravity.acceleration",
    "effects.ground",
    "effects.ground.height",
    "effects.ground.a",
    "effects.ground.kappa",
    "effects.pinned.min",
    "effects.pinned.max",
    "render.resolution",
    "render.field",
    "render.range",
    "render.colour",
    "render.background",
    "render.edges",
    "render.legend",
    "render.camera",
    "render.camera.center",
    "render.camera.height",
    "render.camera.eye",
    "render.camera.target",
    "render.camera.fov",
    "bogus",
    "material.bogus",
    "render.camera.center.x",
];

/// Values, as TOML text (a bare word is taken as a string): boundaries,
/// overflows, wrong types, wrong lengths, paths.
const VALUES: &[&str] = &[
    "0",
    "-1",
    "-5",
    "1",
    "2",
    "3",
    "0.5",
    "0.49999999",
    "-0.0",
    "1e308",
    "-1e308",
    "1e-300",
    "1e39",
    "-1e39",
    "1e-46",
    "nan",
    "inf",
    "-inf",
    "9223372036854775807",
    "-9223372036854775808",
    "[]",
    "[0]",
    "[1, 2]",
    "[2, 2]",
    "[2, 2, 2]",
    "[1, 2, 3]",
    "[0.5, 5.0]",
    "[1e308, 1e308]",
    "[0, -1e308]",
    "[1e-300, 1e-300]",
    "[nan, 1]",
    "[-1, 2]",
    "[1e39, 0, 0]",
    "[0, 1e-50]",
    "[8193, 8192]",
    "\"x\"",
    "\"\"",
    "\"../../escape\"",
    "\"a/b\"",
    "\"..\"",
    "\"bell\\u0007\"",
    "true",
    "{}",
    "{ a = 1 }",
    "stvk",
    "neo-hookean",
    "gradient-descent",
    "newton",
    "on-demand",
    "flat",
    "von-mises",
    "box",
];

/// Values that could make a binary run long (big counts) are left out there.
const SLOW_VALUES: &[&str] = &["1e39"];

/// Text inserted at random places.
const SNIPPETS: &[&str] = &[
    "\n",
    "=",
    "[",
    "]",
    "\"",
    "#",
    "\n[mesh]\n",
    "\nbogus = 1\n",
    "\nyoung = 1\n",
    "\n[effects.ground]\n",
    "\u{0}",
    "é",
    "1e999",
];

#[derive(Debug, Clone)]
enum Mutation {
    /// Replace the n-th number in the text with a value.
    Number(Index, usize),
    /// Delete a line.
    DeleteLine(Index),
    /// Duplicate a line.
    DuplicateLine(Index),
    /// Insert a snippet at a character position.
    Insert(Index, usize),
    /// Cut the text at a character position.
    Truncate(Index),
}

#[derive(Debug, Clone)]
struct Case {
    scene: usize,
    mutations: Vec<Mutation>,
    sets: Vec<(usize, usize)>,
    /// A `--set` argument as typed, sometimes malformed.
    raw_set: Option<String>,
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<Index>(), 0..VALUES.len()).prop_map(|(i, v)| Mutation::Number(i, v)),
        1 => any::<Index>().prop_map(Mutation::DeleteLine),
        1 => any::<Index>().prop_map(Mutation::DuplicateLine),
        1 => (any::<Index>(), 0..SNIPPETS.len()).prop_map(|(i, s)| Mutation::Insert(i, s)),
        1 => any::<Index>().prop_map(Mutation::Truncate),
    ]
}

/// A case with up to `mutations - 1` changes to the text and `sets - 1` overrides.
fn case(mutations: usize, sets: usize) -> impl Strategy<Value = Case> {
    (
        0..BUILTIN_SCENES.len(),
        prop::collection::vec(mutation(), 0..mutations),
        prop::collection::vec((0..KEYS.len(), 0..VALUES.len()), 0..sets),
        prop::option::weighted(0.1, "[ -~]{0,12}"),
    )
        .prop_map(|(scene, mutations, sets, raw_set)| Case {
            scene,
            mutations,
            sets,
            raw_set,
        })
}

/// Byte ranges of the numbers in `text` (outside quotes is not checked:
/// a number in a string is as good a target as any).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut found = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            || (bytes[i] == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        if starts && (i == 0 || !bytes[i - 1].is_ascii_alphanumeric()) {
            let start = i;
            i += 1;
            while i < bytes.len()
                && (bytes[i].is_ascii_digit()
                    || matches!(bytes[i], b'.' | b'e' | b'E' | b'-' | b'_'))
            {
                i += 1;
            }
            found.push((start, i));
        } else {
            i += 1;
        }
    }
    found
}

/// The char boundary at or before `i`.
fn boundary(text: &str, mut i: usize) -> usize {
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn mutate(text: &str, mutations: &[Mutation], values: &[&str]) -> String {
    let mut text = text.to_owned();
    for m in mutations {
        match m {
            Mutation::Number(index, value) => {
                let found = numbers(&text);
                if !found.is_empty() {
                    let (a, b) = found[index.index(found.len())];
                    let value = values[value % values.len()];
                    text.replace_range(a..b, value);
                }
            }
            Mutation::DeleteLine(index) | Mutation::DuplicateLine(index) => {
                let mut lines: Vec<&str> = text.lines().collect();
                if !lines.is_empty() {
                    let i = index.index(lines.len());
                    if matches!(m, Mutation::DeleteLine(_)) {
                        lines.remove(i);
                    } else {
                        lines.insert(i, lines[i]);
                    }
                }
                text = lines.join("\n");
            }
            Mutation::Insert(index, snippet) => {
                let at = boundary(&text, index.index(text.len() + 1));
                text.insert_str(at, SNIPPETS[*snippet]);
            }
            Mutation::Truncate(index) => {
                let at = boundary(&text, index.index(text.len() + 1));
                text.truncate(at);
            }
        }
    }
    text
}

/// The `--set` arguments of a case, as typed.
fn set_arguments(case: &Case, values: &[&str]) -> Vec<String> {
    let mut sets: Vec<String> = case
        .sets
        .iter()
        .map(|&(k, v)| format!("{}={}", KEYS[k], values[v % values.len()]))
        .collect();
    sets.extend(case.raw_set.clone());
    sets
}

/// A runner with a fixed seed; `ELASTO_PROPTEST_SEED=N` (0-255) explores another.
fn runner(cases: u32, seed: u8) -> TestRunner {
    let seed = std::env::var("ELASTO_PROPTEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(seed);
    let config = Config {
        cases,
        failure_persistence: None,
        max_shrink_iters: 200,
        rng_algorithm: RngAlgorithm::ChaCha,
        ..Config::default()
    };
    TestRunner::new_with_rng(
        config,
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    )
}

/// Loading and validating never panics, and a valid scene's resolved form
/// loads back to the same scene.
#[test]
fn validation_never_panics_and_resolves_reproducibly() {
    let mut runner = runner(6000, 7);
    runner
        .run(&case(3, 4), |case| {
            let builtin = &BUILTIN_SCENES[case.scene];
            let text = mutate(builtin.toml, &case.mutations, VALUES);
            let source = SceneSource {
                label: "fuzz.toml".into(),
                default_name: "fuzz".into(),
                path: None,
                text: text.clone(),
            };
            let sets = set_arguments(&case, VALUES);
            let outcome = std::panic::catch_unwind(|| {
                let overrides: Result<Vec<SceneOverride>, _> =
                    sets.iter().map(|s| s.parse()).collect();
                let Ok(overrides) = overrides else {
                    return Ok(None);
                };
                Scene::load_resolved(&source, &overrides).map(Some)
            });
            let result = outcome
                .map_err(|_| TestCaseError::fail(format!("panicked on\n{text}\nwith {sets:?}")))?;
            match result {
                Ok(Some((scene, resolved))) => {
                    let again = SceneSource {
                        text: resolved.clone(),
                        ..source.clone()
                    };
                    let reloaded = Scene::load(&again, &[]).map_err(|e| {
                        TestCaseError::fail(format!(
                            "the resolved scene is invalid: {e}\n{resolved}"
                        ))
                    })?;
                    prop_assert_eq!(reloaded, scene, "resolved:\n{}", resolved);
                }
                Ok(None) => {}
                Err(error) => {
                    // Every message names the source and is one line.
                    let message = error.to_string();
                    prop_assert!(!message.contains('\n'), "{}", message);
                    if error.diagnostic().is_some() {
                        prop_assert!(message.contains("fuzz.toml"), "{}", message);
                    }
                }
            }
            Ok(())
        })
        .unwrap();
}

/// Every path under `root`, relative.
fn tree(root: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![root.to_owned()];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries {
            let path = entry.unwrap().path();
            found.push(path.strip_prefix(root).unwrap().to_owned());
            if path.is_dir() && !path.is_symlink() {
                stack.push(path);
            }
        }
    }
    found
}

/// The real binary, on a few hundred cases: exit code 0, 1 or 2, no panic,
/// nothing written outside `work/out/` (the scene's default folder, or the
/// `-o` folder), and nothing changed behind a link inside it.
#[test]
fn the_binary_exits_0_1_or_2_and_writes_only_its_output_folder() {
    let values: Vec<&str> = VALUES
        .iter()
        .copied()
        .filter(|v| !SLOW_VALUES.contains(v))
        .collect();
    let root = tempfile::tempdir().unwrap();
    let absolute = format!("name=\"{}\"", root.path().join("absolute").display());
    let counts = std::cell::RefCell::new([0usize; 3]);
    let mut runner = runner(400, 11);
    runner
        // Fewer changes than in process, so that more runs get to simulate.
        .run(
            &(case(2, 3), 0..8u8, any::<bool>()),
            |(case, mode, force)| {
                let work = root.path().join("work");
                let elsewhere = root.path().join("elsewhere");
                let _ = std::fs::remove_dir_all(root.path());
                std::fs::create_dir_all(&work).unwrap();
                std::fs::create_dir_all(&elsewhere).unwrap();
                std::fs::write(elsewhere.join("frame_0000.png"), "theirs").unwrap();
                let text = mutate(BUILTIN_SCENES[case.scene].toml, &case.mutations, &values);
                std::fs::write(work.join("scene.toml"), &text).unwrap();
                let mut args: Vec<String> = vec![];
                match mode {
                    0 => args.push("check".into()),
                    _ => args.extend(["run".into(), "-q".into()]),
                }
                args.push("scene.toml".into());
                for set in set_arguments(&case, &values) {
                    args.extend(["--set".into(), set]);
                }
                if mode == 1 {
                    args.extend(["--set".into(), absolute.clone()]);
                }
                if mode > 0 {
                    // Two frames, a few iterations: every run is short.
                    args.extend(["--frames".into(), "2".into()]);
                    args.extend(["--set".into(), "solver.max_iterations=20".into()]);
                    if mode == 7 {
                        args.extend(["--resolution".into(), "32x24".into()]);
                        args.extend(["--video".into(), "apng".into()]);
                    } else {
                        args.push("--no-render".into());
                    }
                    if mode == 5 || mode == 6 {
                        // An existing folder with links to elsewhere.
                        let out = work.join("out");
                        std::fs::create_dir_all(&out).unwrap();
                        #[cfg(unix)]
                        {
                            std::os::unix::fs::symlink(&elsewhere, out.join("frames")).unwrap();
                            std::os::unix::fs::symlink(
                                elsewhere.join("frame_0000.png"),
                                out.join("stats.csv"),
                            )
                            .unwrap();
                        }
                        args.extend(["-o".into(), "out".into()]);
                    }
                    if force {
                        args.push("--force".into());
                    }
                }
                let output = crate::cli_common::elasto_command()
                    .args(&args)
                    .current_dir(&work)
                    .env_remove("RUST_BACKTRACE")
                    .output()
                    .unwrap();
                let code = output.status.code();
                let err = String::from_utf8_lossy(&output.stderr).into_owned();
                let shown = format!("elasto {args:?} on\n{text}\nstderr: {err}");
                prop_assert!(matches!(code, Some(0..=2)), "exit {:?}: {}", code, shown);
                prop_assert!(!err.contains("panicked"), "{}", shown);
                counts.borrow_mut()[code.unwrap() as usize] += 1;
                for path in tree(root.path()) {
                    let inside = path == Path::new("work")
                        || path == Path::new("work/scene.toml")
                        || path.starts_with("work/out")
                        || path.starts_with("elsewhere");
                    prop_assert!(inside, "{} was written: {}", path.display(), shown);
                }
                prop_assert_eq!(
                    tree(&elsewhere),
                    vec![PathBuf::from("frame_0000.png")],
                    "{}",
                    shown
                );
                prop_assert_eq!(
                    std::fs::read_to_string(elsewhere.join("frame_0000.png")).unwrap(),
                    "theirs",
                    "{}",
                    shown
                );
                Ok(())
            },
        )
        .unwrap();
    // The cases reach every outcome a run can have, not just validation errors.
    let counts = counts.into_inner();
    eprintln!("exit codes 0/1/2: {counts:?}");
    assert!(
        counts[0] >= 20 && counts[2] >= 20,
        "exit codes 0/1/2: {counts:?}"
    );
}

#[test]
fn mutations_reach_the_numbers_of_a_scene() {
    let text = "a = 1\nb = [2.5, -3e-4]\nname = \"x1\"\n";
    let spans: Vec<&str> = numbers(text).iter().map(|&(a, b)| &text[a..b]).collect();
    assert_eq!(spans, ["1", "2.5", "-3e-4"]);
    assert_eq!(numbers(SMALL_SCENE).len(), 13);
}
