//! The declared minimum Rust version (`rust-version` of each workspace crate) is the true one:
//! the largest `rust-version` among the locked dependencies the crate builds with (normal, build
//! and dev, for the two targets the FMUs ship: x86_64 Linux and Windows), read from
//! `cargo metadata`. A dependency update that needs a newer Rust fails here until the declaration
//! follows; a declaration above what the dependencies need fails too, so it stays the minimum.
//! Our own code is held to it by clippy's `incompatible_msrv` lint (on in `make lint` / CI, which
//! checks every std API we call against the declared version).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use serde_json::Value;
use std::collections::{BTreeSet, HashMap};

fn version(s: &str) -> Vec<u64> {
    let mut v: Vec<u64> = s.split('.').map(|p| p.parse().unwrap_or(0)).collect();
    v.resize(3, 0);
    v
}

#[test]
fn declared_rust_version_is_what_the_locked_dependencies_need() {
    let out = std::process::Command::new(env!("CARGO"))
        .args(["metadata", "--format-version", "1", "--locked"])
        .args(["--filter-platform", "x86_64-unknown-linux-gnu"])
        .args(["--filter-platform", "x86_64-pc-windows-gnu"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo metadata");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let meta: Value = serde_json::from_slice(&out.stdout).unwrap();
    let packages: HashMap<&str, &Value> = meta["packages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p["id"].as_str().unwrap(), p))
        .collect();
    let deps: HashMap<&str, Vec<&str>> = meta["resolve"]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| {
            let ids = n["deps"].as_array().unwrap().iter();
            (
                n["id"].as_str().unwrap(),
                ids.map(|d| d["pkg"].as_str().unwrap()).collect(),
            )
        })
        .collect();
    let rust_version = |id: &str| packages[id]["rust_version"].as_str().map(version);
    for member in meta["workspace_members"].as_array().unwrap() {
        let member = member.as_str().unwrap();
        let name = packages[member]["name"].as_str().unwrap();
        let declared = rust_version(member).unwrap_or_else(|| panic!("{name}: no rust-version"));
        // Everything the member builds with, itself excluded.
        let mut seen = BTreeSet::new();
        let mut todo: Vec<&str> = deps[member].clone();
        while let Some(id) = todo.pop() {
            if seen.insert(id) {
                todo.extend(&deps[id]);
            }
        }
        seen.remove(member);
        let (needed, by) = seen
            .iter()
            .filter_map(|id| Some((rust_version(id)?, *id)))
            .max()
            .expect("dependencies with a rust-version");
        let by = format!("{} {}", packages[by]["name"], packages[by]["version"]);
        assert!(
            declared >= needed,
            "{name}: rust-version {declared:?}, but {by} needs {needed:?}: raise it"
        );
        assert!(
            declared[..2] == needed[..2],
            "{name}: rust-version {declared:?}, but the dependencies need only {needed:?} ({by}): \
             lower it (if clippy's incompatible_msrv agrees)"
        );
    }
}
