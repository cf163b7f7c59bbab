//! The house: no import cycle among the library's top-level modules (src/*.rs, src/*/). A module
//! imports another when its code (tests included) names `crate::other`, in a path or in a
//! `use crate::{…}` group; `crate::Name` of a root re-export (`pub use m::Name` in lib.rs) counts
//! as an import of m. The data path runs one way (lib.rs): a stage may use what lies below it,
//! never what is built on it.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Graph = BTreeMap<String, BTreeMap<String, BTreeSet<String>>>;

/// Code without `//` comments (doc links such as [`crate::feed::tolerance`] are not imports).
fn code(text: &str) -> String {
    text.lines()
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n")
}

fn ident(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// The first path segments named after `crate::` in `text`: `crate::a::x` gives a,
/// `crate::{a, b::{c, d}, e}` gives a, b, e.
fn crate_roots(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut rest = text;
    while let Some(i) = rest.find("crate::") {
        // `$crate::` in macros and `cnc_crate::` are not this crate's root.
        let before = rest[..i].chars().last();
        rest = &rest[i + "crate::".len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$') {
            continue;
        }
        let r = rest.trim_start();
        if let Some(group) = r.strip_prefix('{') {
            let mut depth = 1;
            let mut item_start = true;
            for (k, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    ',' if depth == 1 => item_start = true,
                    c if item_start && depth == 1 && !c.is_whitespace() => {
                        out.insert(ident(&group[k..]).to_string());
                        item_start = false;
                    }
                    _ => {}
                }
            }
        } else {
            out.insert(ident(r).to_string());
        }
    }
    out.remove("");
    out
}

/// Root re-exports of lib.rs: `pub use m::…::Name;` maps Name to m.
fn root_exports(lib: &str) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for line in code(lib).lines() {
        if let Some(path) = line.trim().strip_prefix("pub use ") {
            let path = path.trim_end_matches(';');
            let module = ident(path).to_string();
            if let Some(name) = path.rsplit("::").next().filter(|_| path.contains("::")) {
                out.insert(name.to_string(), module);
            }
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// module → imported module → the files (relative to src/) that import it.
fn module_graph(src: &Path) -> Result<Graph, String> {
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    let exports = root_exports(&lib);
    let is_module = |m: &str| src.join(format!("{m}.rs")).is_file() || src.join(m).is_dir();
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut graph = Graph::new();
    for f in files {
        let rel = f.strip_prefix(src).unwrap().to_string_lossy().replace('\\', "/");
        let top = rel.split('/').next().unwrap().trim_end_matches(".rs").to_string();
        // lib.rs declares the modules; src/bin is another crate (it names the library by name).
        if top == "lib" || top == "bin" {
            continue;
        }
        graph.entry(top.clone()).or_default();
        for root in crate_roots(&code(&std::fs::read_to_string(&f).unwrap())) {
            let target = if is_module(&root) {
                root
            } else if let Some(m) = exports.get(&root) {
                m.clone()
            } else {
                return Err(format!(
                    "{rel}: crate::{root} is neither a module nor a root re-export"
                ));
            };
            if target != top {
                graph
                    .entry(top.clone())
                    .or_default()
                    .entry(target)
                    .or_default()
                    .insert(rel.clone());
            }
        }
    }
    Ok(graph)
}

/// A cycle of the graph as "a → b (file) → … → a", or None.
fn find_cycle(graph: &Graph) -> Option<String> {
    fn visit(g: &Graph, m: &str, stack: &mut Vec<String>, done: &mut BTreeSet<String>) -> Option<String> {
        if let Some(i) = stack.iter().position(|s| s == m) {
            let mut cycle = stack[i..].to_vec();
            cycle.push(m.to_string());
            let named: Vec<String> = cycle
                .windows(2)
                .map(|w| {
                    let files = &g[&w[0]][&w[1]];
                    format!(
                        "{} → {} ({})",
                        w[0],
                        w[1],
                        files.iter().cloned().collect::<Vec<_>>().join(", ")
                    )
                })
                .collect();
            return Some(named.join("; "));
        }
        if done.contains(m) {
            return None;
        }
        stack.push(m.to_string());
        for next in g.get(m).into_iter().flat_map(|e| e.keys()) {
            if let Some(c) = visit(g, next, stack, done) {
                return Some(c);
            }
        }
        stack.pop();
        done.insert(m.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|m| visit(graph, m, &mut Vec::new(), &mut done))
}

#[test]
fn src_modules_import_no_cycle() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let graph = module_graph(&src).unwrap();
    // The scan sees the data path: the stages and the layers below them.
    for (from, to) in [
        ("path", "geometry"),
        ("gcode", "geometry"),
        ("engine", "interp"),
        ("fmu", "engine"),
    ] {
        assert!(graph[from].contains_key(to), "{from} → {to} not seen: {graph:?}");
    }
    if let Some(cycle) = find_cycle(&graph) {
        panic!("import cycle among src/ modules: {cycle}");
    }
}

#[test]
fn the_scan_reads_paths_and_groups() {
    let text = "use crate::a::X;\nuse crate::{b, c::{d, e::F}, g::*};\nlet x = crate::h::f(crate::Vec3);\n\
                // crate::commented\nmacro_rules! m { () => { $crate::m::x } }";
    let roots: Vec<String> = crate_roots(&code(text)).into_iter().collect();
    assert_eq!(roots, ["Vec3", "a", "b", "c", "g", "h"]);
    assert_eq!(
        root_exports("pub use geometry::Vec3;\npub mod a;")["Vec3"],
        "geometry"
    );
}

#[test]
fn a_cycle_is_found_and_named() {
    let edge = |g: &mut Graph, a: &str, b: &str| {
        let file = format!("{a}/mod.rs");
        g.entry(a.into())
            .or_default()
            .entry(b.into())
            .or_default()
            .insert(file);
        g.entry(b.into()).or_default();
    };
    let mut g = Graph::new();
    edge(&mut g, "config", "feed");
    edge(&mut g, "feed", "valid");
    edge(&mut g, "path", "feed");
    assert_eq!(find_cycle(&g), None);
    edge(&mut g, "valid", "path");
    let cycle = find_cycle(&g).expect("feed → valid → path → feed");
    assert_eq!(
        cycle,
        "feed → valid (feed/mod.rs); valid → path (valid/mod.rs); path → feed (path/mod.rs)"
    );
}
