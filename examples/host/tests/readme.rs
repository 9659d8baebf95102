//! The project README shows the crate README's first example verbatim (the crate README's
//! examples run as texcore doc tests), so the example on the project's first screen compiles.

#[test]
fn project_readme_shows_the_doc_tested_example() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let project = std::fs::read_to_string(root.join("README.md")).unwrap();
    let krate = std::fs::read_to_string(root.join("texcore/README.md")).unwrap();
    let start = krate
        .find("```rust\n")
        .expect("a Rust example in texcore/README.md");
    let end = start + 8 + krate[start + 8..].find("```\n").unwrap() + 4;
    let example = &krate[start..end];
    let at = project.find(example).expect("the example in README.md");
    // On the first screen: within the README's first 40 lines, after its two commands.
    assert!(project[..at].lines().count() < 40);
    assert!(project.starts_with(
        "# texcore\n\n```sh\ncargo run --release -p host-sim --bin texsim -- gallery out/"
    ));
}
