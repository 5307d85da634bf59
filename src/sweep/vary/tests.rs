//! Tests of `vary`.

use super::*;

fn labels(axis: &VaryAxis) -> Vec<&str> {
    axis.values.iter().map(|v| v.label.as_str()).collect()
}

fn tomls(axis: &VaryAxis) -> Vec<&str> {
    axis.values.iter().map(|v| v.toml.as_str()).collect()
}

#[test]
fn lists_split_at_top_level_commas_only() {
    let axis = parse_vary("material.young=100, 300,1e3").unwrap();
    assert_eq!(axis.key, "material.young");
    assert_eq!(tomls(&axis), ["100", "300", "1e3"]);
    let axis = parse_vary("mesh.velocity=[0,-1],[0, -5]").unwrap();
    assert_eq!(tomls(&axis), ["[0,-1]", "[0, -5]"]);
    assert_eq!(labels(&axis), ["[0,-1]", "[0,-5]"]);
    let axis = parse_vary(r#"material.model="a,b",'c]', "d\",e""#).unwrap();
    assert_eq!(tomls(&axis), [r#""a,b""#, "'c]'", r#""d\",e""#]);
    assert_eq!(labels(&axis), ["a,b", "c]", "d\",e"]);
    let axis = parse_vary("x.y={a=[1,2],b=3},{a=[4],b=5}").unwrap();
    assert_eq!(tomls(&axis), ["{a=[1,2],b=3}", "{a=[4],b=5}"]);
}

#[test]
fn linspace_gives_integers_for_integer_ends_and_floats_otherwise() {
    let axis = parse_vary("time.substeps=linspace(1, 10, 4)").unwrap();
    assert_eq!(tomls(&axis), ["1", "4", "7", "10"]);
    let axis = parse_vary("time.substeps=linspace(1,10,3)").unwrap();
    assert_eq!(tomls(&axis), ["1.0", "5.5", "10.0"]);
    let axis = parse_vary("material.poisson=linspace(0.1, 0.4, 4)").unwrap();
    assert_eq!(tomls(&axis), ["0.1", "0.2", "0.3", "0.4"]);
    let axis = parse_vary("a=linspace(2,3,1)").unwrap();
    assert_eq!(tomls(&axis), ["2"]);
    let axis = parse_vary("a=linspace(1e20, 2e20, 2)").unwrap();
    assert_eq!(tomls(&axis), ["1e20", "2e20"]);
    // Every float text is a TOML float.
    for v in parse_vary("a=linspace(-1, 1.5, 7)").unwrap().values {
        let parsed: toml::Table = toml::from_str(&format!("v = {}", v.toml)).unwrap();
        assert!(parsed["v"].is_float(), "{}", v.toml);
    }
}

#[test]
fn logspace_is_geometric_between_the_ends() {
    let axis = parse_vary("material.young=logspace(1, 1000, 4)").unwrap();
    assert_eq!(tomls(&axis), ["1", "10", "100", "1000"]);
    let axis = parse_vary("material.young=logspace(100, 1e4, 5)").unwrap();
    let values: Vec<f64> = axis
        .values
        .iter()
        .map(|v| v.toml.parse().unwrap())
        .collect();
    for pair in values.windows(2) {
        approx::assert_relative_eq!(pair[1] / pair[0], 10f64.sqrt(), max_relative = 1e-11);
    }
    assert_eq!(values[0], 100.0);
    assert_eq!(values[4], 1e4);
    assert_eq!(axis.values[1].toml, "316.227766017");
}

#[test]
fn bad_arguments_are_errors_naming_the_flag() {
    for bad in [
        "material.young",
        "material.young=",
        "material.young=1,,2",
        "material.young=1,",
        "material.young=[1,2",
        "material.young=1]",
        "material.young=\"abc",
        "=1,2",
        "material..young=1",
        "a=linspace(1,2)",
        "a=linspace(1,2,0)",
        "a=linspace(1,2,2.5)",
        "a=linspace(1,x,3)",
        "a=linspace(1,inf,3)",
        "a=linspace(1,2,3",
        "a=logspace(0,10,3)",
        "a=logspace(-1,10,3)",
        "a=linspace(1,2,20000)",
    ] {
        let err = parse_vary(bad).unwrap_err();
        assert!(matches!(err, SweepError::BadVary { .. }), "{bad}: {err}");
        assert!(err.to_string().contains(bad), "{bad}: {err}");
    }
}

fn axis(arg: &str) -> VaryAxis {
    parse_vary(arg).unwrap()
}

#[test]
fn cartesian_product_turns_the_last_axis_fastest() {
    let runs = expand(&[axis("a=1,2"), axis("b=x,y,z")], false).unwrap();
    let got: Vec<String> = runs.iter().map(RunSpec::label).collect();
    assert_eq!(
        got,
        [
            "a=1, b=x", "a=1, b=y", "a=1, b=z", "a=2, b=x", "a=2, b=y", "a=2, b=z"
        ]
    );
    assert!(runs.iter().enumerate().all(|(i, r)| r.index == i));
    assert_eq!(expand(&[], false).unwrap().len(), 1);
}

#[test]
fn zip_pairs_values_and_needs_equal_lengths() {
    let runs = expand(&[axis("a=1,2,3"), axis("b=x,y,z")], true).unwrap();
    let got: Vec<String> = runs.iter().map(RunSpec::label).collect();
    assert_eq!(got, ["a=1, b=x", "a=2, b=y", "a=3, b=z"]);
    let err = expand(&[axis("a=1,2,3"), axis("b=x,y")], true).unwrap_err();
    assert!(matches!(err, SweepError::ZipLengths { .. }), "{err}");
    assert!(err.to_string().contains("a: 3, b: 2"), "{err}");
}

#[test]
fn duplicate_keys_and_huge_products_are_errors() {
    let err = expand(&[axis("a=1"), axis("a=2")], false).unwrap_err();
    assert!(matches!(err, SweepError::DuplicateKey { .. }), "{err}");
    let big = |key: &str| axis(&format!("{key}=linspace(1,100,100)"));
    let err = expand(&[big("a"), big("b"), big("c")], false).unwrap_err();
    assert!(
        matches!(
            err,
            SweepError::TooManyRuns {
                runs: 1_000_000,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn folder_names_are_safe_unique_and_bounded() {
    let runs = expand(
        &[axis("material.young=300"), axis("time.substeps=10")],
        false,
    )
    .unwrap();
    assert_eq!(
        runs[0].folder_name(),
        "0000_material.young=300_time.substeps=10"
    );
    let runs = expand(&[axis(r#"mesh.velocity=[0, -1],"a/b c*""#)], false).unwrap();
    assert_eq!(runs[0].folder_name(), "0000_mesh.velocity=0,-1");
    assert_eq!(runs[1].folder_name(), "0001_mesh.velocity=a_bc_");
    let long = format!("a={}", "[1.5, 2.5, 3.5]".replace("1.5", &"9".repeat(300)));
    let name = expand(&[axis(&long)], false).unwrap()[0].folder_name();
    assert_eq!(name.len(), MAX_FOLDER_NAME_BYTES);
    assert!(name.starts_with("0000_a=999"));
}

#[test]
fn overrides_carry_the_value_and_name_the_flag() {
    let runs = expand(&[axis("mesh.velocity=[0,-1],[0,-5]")], false).unwrap();
    let overrides = runs[1].overrides().unwrap();
    assert_eq!(overrides.len(), 1);
    assert_eq!(overrides[0].key(), "mesh.velocity");
    assert_eq!(overrides[0].value.as_deref(), Some("[0,-5]"));
    assert_eq!(overrides[0].flag, "--vary mesh.velocity=[0,-5]");
}

#[test]
fn sweep_file_axes_take_arrays_or_range_strings() {
    let file = Path::new("study.toml");
    let table: toml::Table = toml::from_str(
        r#"
        "material.young" = [100, 3e2]
        "mesh.velocity" = [[0, -1], [0.5, -5]]
        "time.substeps" = "linspace(1, 10, 4)"
        bad = "abc"
        empty = []
        "#,
    )
    .unwrap();
    let young = axis_from_toml("material.young", &table["material.young"], file).unwrap();
    assert_eq!(tomls(&young), ["100", "300.0"]);
    let velocity = axis_from_toml("mesh.velocity", &table["mesh.velocity"], file).unwrap();
    assert_eq!(tomls(&velocity), ["[0, -1]", "[0.5, -5]"]);
    let substeps = axis_from_toml("time.substeps", &table["time.substeps"], file).unwrap();
    assert_eq!(tomls(&substeps), ["1", "4", "7", "10"]);
    assert_eq!(
        young.describe(&young.values[0]),
        "study.toml: [vary] material.young = 100"
    );
    for key in ["bad", "empty"] {
        let err = axis_from_toml(key, &table[key], file).unwrap_err();
        assert!(err.to_string().contains(&format!("`vary.{key}`")), "{err}");
    }
}
