//! No import circles between files: in every library crate, the graph of which source file
//! names which (through `crate::`, `super::` or `self::` paths, outside comments and test
//! modules) has no cycle. A circle hides the design: a newcomer cannot read either file
//! first.
//!
//! A path is resolved to the longest module prefix that is a file; a name a module
//! re-exports (`pub use sub::Name`) is followed to the file that defines it.

use crate::common;

use common::Scratch;
use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

type Module = Vec<String>;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The module a file defines (`a/b.rs` and `a/b/mod.rs` are `a::b`; `lib.rs` is the root).
fn module_of(src: &Path, file: &Path) -> Module {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut m: Module = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(m.last().map(String::as_str), Some("mod" | "lib" | "main")) {
        m.pop();
    }
    m
}

/// The file's code before its test module, without `//` comments.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    text.lines()
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n")
}

fn ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// Every `crate::a::b`, `super::a` and `self::a` path in `code`, as its head and segments.
fn paths(code: &str) -> Vec<(String, Vec<String>)> {
    let mut out = Vec::new();
    for head in ["crate", "super", "self"] {
        let pat = format!("{head}::");
        let mut from = 0;
        while let Some(i) = code[from..].find(&pat) {
            let start = from + i;
            from = start + pat.len();
            if code[..start].chars().next_back().is_some_and(ident) {
                continue;
            }
            let mut segs = Vec::new();
            let mut rest = &code[start + pat.len()..];
            loop {
                let n = rest.find(|c: char| !ident(c)).unwrap_or(rest.len());
                if n == 0 {
                    break;
                }
                segs.push(rest[..n].to_string());
                rest = &rest[n..];
                match rest.strip_prefix("::") {
                    Some(r) => rest = r,
                    None => break,
                }
            }
            out.push((head.to_string(), segs));
        }
    }
    out
}

/// `pub use sub::{A, B}` in a module: name -> the submodule it comes from.
fn reexports(code: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for stmt in code.split("pub use ").skip(1) {
        let stmt = stmt.split(';').next().unwrap_or("");
        let Some((sub, rest)) = stmt.split_once("::") else {
            continue;
        };
        if !sub.chars().all(ident) || ["crate", "super", "self", "std"].contains(&sub) {
            continue;
        }
        if sub.starts_with("navkf_") || sub == "serde" {
            continue;
        }
        for name in rest.split(|c: char| !ident(c)).filter(|s| !s.is_empty()) {
            out.push((name.to_string(), sub.to_string()));
        }
    }
    out
}

fn cycles(src: &Path) -> Vec<Vec<Module>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let modules: BTreeMap<Module, String> = files
        .iter()
        .map(|f| (module_of(src, f), code(&fs::read_to_string(f).unwrap())))
        .collect();
    let mut reexported: BTreeMap<(Module, String), Module> = BTreeMap::new();
    for (m, text) in &modules {
        for (name, sub) in reexports(text) {
            let mut target = m.clone();
            target.push(sub);
            reexported.insert((m.clone(), name), target);
        }
    }
    let resolve = |mut path: Module| -> Option<Module> {
        let full = path.clone();
        while !path.is_empty() && !modules.contains_key(&path) {
            path.pop();
        }
        if let Some(next) = full.get(path.len()) {
            if let Some(target) = reexported.get(&(path.clone(), next.clone())) {
                let mut t = target.clone();
                while !t.is_empty() && !modules.contains_key(&t) {
                    t.pop();
                }
                return Some(t);
            }
        }
        modules.contains_key(&path).then_some(path)
    };
    let mut edges: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for (m, text) in &modules {
        for (head, segs) in paths(text) {
            let mut base = match head.as_str() {
                "crate" => Vec::new(),
                "super" => m[..m.len().saturating_sub(1)].to_vec(),
                _ => m.clone(),
            };
            base.extend(segs);
            if let Some(to) = resolve(base) {
                if &to != m {
                    edges.entry(m.clone()).or_default().insert(to);
                }
            }
        }
    }
    strongly_connected(&modules.keys().cloned().collect::<Vec<_>>(), &edges)
        .into_iter()
        .filter(|c| c.len() > 1)
        .collect()
}

/// Tarjan's strongly connected components.
fn strongly_connected(
    nodes: &[Module],
    edges: &BTreeMap<Module, BTreeSet<Module>>,
) -> Vec<Vec<Module>> {
    struct State<'a> {
        edges: &'a BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<Module, usize>,
        low: BTreeMap<Module, usize>,
        stack: Vec<Module>,
        on_stack: BTreeSet<Module>,
        out: Vec<Vec<Module>>,
    }
    fn visit(v: &Module, s: &mut State) {
        let i = s.index.len();
        s.index.insert(v.clone(), i);
        s.low.insert(v.clone(), i);
        s.stack.push(v.clone());
        s.on_stack.insert(v.clone());
        for w in s.edges.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                visit(w, s);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.on_stack.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = s.stack.pop().unwrap();
                s.on_stack.remove(&w);
                let done = &w == v;
                comp.push(w);
                if done {
                    break;
                }
            }
            s.out.push(comp);
        }
    }
    let mut s = State {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in nodes {
        if !s.index.contains_key(v) {
            visit(v, &mut s);
        }
    }
    s.out
}

#[test]
fn no_source_file_imports_one_that_imports_it_back() {
    let mut found = Vec::new();
    let crates = root().join("crates");
    for e in fs::read_dir(&crates).unwrap() {
        let src = e.unwrap().path().join("src");
        if !src.is_dir() {
            continue;
        }
        for c in cycles(&src) {
            let names: Vec<String> = c.iter().map(|m| m.join("::")).collect();
            found.push(format!("{}: {}", src.display(), names.join(" <-> ")));
        }
    }
    assert!(found.is_empty(), "import circles:\n{}", found.join("\n"));
}

#[test]
fn the_check_sees_a_circle() {
    let dir = Scratch::new("cycles");
    fs::create_dir_all(dir.join("a")).unwrap();
    fs::write(dir.join("lib.rs"), "pub mod a;\npub mod b;\n").unwrap();
    fs::write(dir.join("a/mod.rs"), "pub use inner::X;\nmod inner;\n").unwrap();
    fs::write(
        dir.join("a/inner.rs"),
        "use crate::b::Y;\npub struct X(Y);\n",
    )
    .unwrap();
    fs::write(
        dir.join("b.rs"),
        "// crate::a is named in a comment only\npub struct Y;\n",
    )
    .unwrap();
    assert!(cycles(&dir).is_empty());
    fs::write(dir.join("b.rs"), "pub struct Y(Box<crate::a::X>);\n").unwrap();
    let found = cycles(&dir);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].contains(&vec!["a".to_string(), "inner".to_string()]));
}
