//! The crate's modules form one-way layers: no module refers to a module of a layer above its own.
//!
//! The order, lowest first, is written once, in [`LAYERS`]; the crate doc in
//! `src/lib.rs` and `docs/architecture.md` repeat it for readers, and a test
//! checks that both say the same. Every `crate::` path in the code
//! of `src/` (comments aside) is checked, including grouped imports such as
//! `use crate::{math::Vector, sim::Simulation}` and `$crate::` in macros.
//! Modules of one layer may refer to each other.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The layers of the crate, lowest first: a module may use modules of its
/// own layer and of the layers below.
const LAYERS: &[&[&str]] = &[
    &["math", "input_file"],
    &["mesh", "material"],
    &["assembly", "contact", "mesh_io"],
    &["energy", "finite_volume"],
    &["solver"],
    &["integrator"],
    &["sim"],
    &["output", "render", "encode", "compare", "study"],
    &["scene"],
    &["sweep"],
    &["app"],
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|layer| layer.contains(&module))
}

/// The top-level modules that `code` (the text of one source file) refers to
/// through `crate::` paths, comments excluded.
fn referenced_modules(code: &str) -> BTreeSet<String> {
    let mut modules = BTreeSet::new();
    for line in code.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(at) = rest.find("crate::") {
            let preceded_by_ident = rest[..at]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_');
            rest = &rest[at + "crate::".len()..];
            if preceded_by_ident {
                continue;
            }
            if let Some(group) = rest.strip_prefix('{') {
                // `crate::{a::X, b, c::{Y, Z}}`: the first path segment of each item at depth 0.
                let mut depth = 0;
                let mut start = true;
                for (i, c) in group.char_indices() {
                    match c {
                        '{' => depth += 1,
                        '}' if depth == 0 => break,
                        '}' => depth -= 1,
                        ',' if depth == 0 => start = true,
                        c if start && (c.is_alphanumeric() || c == '_') => {
                            let name: String = group[i..]
                                .chars()
                                .take_while(|c| c.is_alphanumeric() || *c == '_')
                                .collect();
                            modules.insert(name);
                            start = false;
                        }
                        _ => {}
                    }
                }
            } else {
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    modules.insert(name);
                }
            }
        }
    }
    modules
}

/// The upward references of a file of module `module` with text `code`, as
/// messages.
fn violations(module: &str, file: &str, code: &str) -> Vec<String> {
    let Some(own) = layer_of(module) else {
        return vec![format!(
            "{file}: module `{module}` is in no layer of tests/integration/layering.rs"
        )];
    };
    referenced_modules(code)
        .into_iter()
        .filter_map(|target| {
            let layer = layer_of(&target)?;
            (layer > own).then(|| {
                format!(
                    "{file}: `{module}` (layer {own}) refers to `crate::{target}` (layer {layer}, above it)"
                )
            })
        })
        .collect()
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn no_module_refers_to_a_layer_above_its_own() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut problems = Vec::new();
    let mut checked = 0;
    for path in &files {
        let relative = path.strip_prefix(&src).unwrap();
        let first = relative.components().next().unwrap().as_os_str();
        let module = first.to_string_lossy().trim_end_matches(".rs").to_owned();
        if module == "lib" || module == "main" {
            continue;
        }
        let code = std::fs::read_to_string(path).unwrap();
        problems.extend(violations(&module, &relative.display().to_string(), &code));
        checked += 1;
    }
    assert!(
        checked > 40,
        "only {checked} files found under {}",
        src.display()
    );
    assert!(
        problems.is_empty(),
        "upward references:\n{}",
        problems.join("\n")
    );
}

/// The checker itself: an upward import is found in every form it can take,
/// and a downward one is not.
#[test]
fn the_check_finds_upward_imports_in_every_form() {
    let upward = [
        "use crate::solver::Objective;",
        "use crate::{math::Vector, solver::SparseHessian};",
        "use crate::{\n    math::Vector,\n    sim::{FrameStats, SolverStats},\n};",
        "fn f() -> crate::sim::SolverStats { todo!() }",
        "$crate::solver::newton(x)",
    ];
    for code in upward {
        let found = violations("energy", "energy/fixture.rs", &code.replace('\n', " "));
        assert_eq!(found.len(), 1, "{code:?} gave {found:?}");
    }
    let downward = [
        "use crate::math::Vector;",
        "use crate::{assembly::SparseHessian, mesh::Mesh};",
        "use super::EnergyTerm;",
        "// see crate::sim::Simulation, a comment",
        "let mycrate::solver = 1;",
        "use crate::finite_volume::report_face_sum;",
    ];
    for code in downward {
        let found = violations("energy", "energy/fixture.rs", code);
        assert!(found.is_empty(), "{code:?} gave {found:?}");
    }
    assert_eq!(violations("nowhere", "nowhere.rs", "").len(), 1);
}

/// The numbered layer list between `<!-- layers: begin -->` and
/// `<!-- layers: end -->` in `text` (with `//! ` prefixes removed): one
/// layer per line, `1. `math`, `input_file``, links or plain code.
fn documented_layers(text: &str) -> Vec<Vec<String>> {
    let lines: Vec<&str> = text
        .lines()
        .map(|l| l.trim_start().trim_start_matches("//!").trim())
        .collect();
    let begin = lines
        .iter()
        .position(|l| *l == "<!-- layers: begin -->")
        .expect("a `<!-- layers: begin -->` marker");
    let end = lines
        .iter()
        .position(|l| *l == "<!-- layers: end -->")
        .expect("a `<!-- layers: end -->` marker");
    lines[begin + 1..end]
        .iter()
        .enumerate()
        .map(|(i, line)| {
            let items = line
                .strip_prefix(&format!("{}. ", i + 1))
                .unwrap_or_else(|| {
                    panic!("layer line {} is not numbered {}: {line}", i + 1, i + 1)
                });
            items
                .split(',')
                .map(|item| {
                    item.trim_matches(|c: char| {
                        c == '[' || c == ']' || c == '`' || c.is_whitespace()
                    })
                    .to_owned()
                })
                .collect()
        })
        .collect()
}

/// `src/lib.rs`'s crate doc and `docs/architecture.md` list the enforced layers.
#[test]
fn the_documented_layers_are_the_enforced_ones() {
    let enforced: Vec<Vec<String>> = LAYERS
        .iter()
        .map(|layer| layer.iter().map(|m| (*m).to_owned()).collect())
        .collect();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for file in ["src/lib.rs", "docs/architecture.md"] {
        let text = std::fs::read_to_string(root.join(file)).unwrap();
        assert_eq!(
            documented_layers(&text),
            enforced,
            "{file}'s layer list differs from LAYERS in tests/integration/layering.rs"
        );
    }
    // Every top-level module is in a layer: the files of `src/` and the layers agree.
    let mut modules = BTreeSet::new();
    for entry in std::fs::read_dir(root.join("src")).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        let name = name.trim_end_matches(".rs").to_owned();
        if name != "lib" && name != "main" {
            modules.insert(name);
        }
    }
    let layered: BTreeSet<String> = enforced.into_iter().flatten().collect();
    assert_eq!(modules, layered, "the modules of src/ against the layers");
}
