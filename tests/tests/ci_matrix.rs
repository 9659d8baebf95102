//! The CI build matrix covers what the reports build: every feature set of `texsim report size`
//! (`host_sim::report::size::FEATURE_SETS`) is type-checked for both device targets by
//! `.ci/firmware-matrix.sh`, with the same features and profile, and every texcore feature is
//! built alone by `.ci/feature-matrix.sh`.

use host_sim::report::size::FEATURE_SETS;

fn read(path: &str) -> String {
    let root = host_sim::device::workspace_root();
    std::fs::read_to_string(root.join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn firmware_matrix_checks_every_size_report_set() {
    let script = read(".ci/firmware-matrix.sh");
    let listed: Vec<(String, String, String)> = script
        .lines()
        .filter_map(|l| {
            let l = l.trim().strip_prefix('"')?.strip_suffix('"')?;
            let mut it = l.split('|');
            Some((it.next()?.into(), it.next()?.into(), it.next()?.into()))
        })
        .collect();
    assert_eq!(
        listed.len(),
        FEATURE_SETS.len(),
        "sets in the script: {listed:?}"
    );
    for set in FEATURE_SETS {
        let want = (
            set.name.to_string(),
            set.features.join(","),
            set.profile.to_string(),
        );
        assert!(
            listed.contains(&want),
            "size report set {want:?} is not in .ci/firmware-matrix.sh"
        );
    }
}

#[test]
fn feature_matrix_builds_every_texcore_feature_alone() {
    let script = read(".ci/feature-matrix.sh");
    let manifest = read("texcore/Cargo.toml");
    let features: Vec<&str> = manifest
        .split("[features]")
        .nth(1)
        .and_then(|s| s.split("\n[").next())
        .expect("texcore [features]")
        .lines()
        .filter_map(|l| l.split_once(" = ").map(|(k, _)| k.trim()))
        .filter(|k| !k.starts_with('#') && *k != "default" && *k != "full")
        .collect();
    assert!(features.len() >= 14, "{features:?}");
    let list = script
        .lines()
        .find(|l| l.starts_with("features=("))
        .expect("features=( in .ci/feature-matrix.sh");
    for f in features {
        assert!(
            list.split([' ', '(', ')']).any(|w| w == f),
            "texcore feature `{f}` is not built alone by .ci/feature-matrix.sh"
        );
    }
}
