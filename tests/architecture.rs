//! The source runs in one direction: each folder of `src/` imports only the
//! folders below it, and no files import each other, directly or round a
//! longer cycle. Read from the `use` declarations and the `crate::…`,
//! `super::…` and `lumiere::…` paths of every file.
//!
//! A folder's front file (`mod.rs`, or `accel.rs` beside `accel/`) may use
//! the files it contains: that is containment, not an import back.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The folders of `src/`, bottom first: each may import only those before it.
const ORDER: [&str; 11] = [
    "platform",
    "course",
    "scene",
    "geometry",
    "transport",
    "render",
    "analysis",
    "lesson",
    "tools",
    "app",
    "cli",
];

type Module = Vec<String>;

#[test]
fn folders_and_files_import_in_one_direction() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    collect(&root, &root, &mut files);
    assert!(files.len() > 100, "only {} files found", files.len());
    let problems = check(&files);
    assert!(
        problems.is_empty(),
        "the imports do not run in one direction:\n{}",
        problems.join("\n")
    );
}

/// The checker finds what it is meant to find, and only that.
#[test]
fn the_checker_sees_upward_imports_and_cycles() {
    let file = |path: &str, text: &str| (path.to_string(), text.to_string());
    let files = vec![
        file(
            "lib.rs",
            "pub mod scene; pub mod transport; pub mod render;",
        ),
        file(
            "scene/mod.rs",
            "pub mod a;\npub use a::A;\nuse crate::render::film::Film;",
        ),
        file(
            "scene/a.rs",
            "// use crate::render::X; in a comment\nlet s = \"crate::render::X\";\npub struct A;\n#[cfg(test)]\nmod tests {\n    use super::*;\n}",
        ),
        file(
            "transport/mod.rs",
            "pub mod x; pub mod y; pub mod z;\nfn f() { x::go(); }",
        ),
        file(
            "transport/x.rs",
            "use super::y::Y;\nuse crate::scene::a::A;",
        ),
        file("transport/y.rs", "use crate::transport::{z::Z, x::X};"),
        file(
            "transport/z.rs",
            "pub(crate) use crate::transport::x::X;\nfn g<'a>(c: char) { let _ = '\\''; }",
        ),
        file("render/mod.rs", "pub mod film;"),
        file(
            "render/film.rs",
            "pub struct Film; fn h() { crate::transport::y::f(); }",
        ),
    ];
    let problems = check(&files);
    let joined = problems.join("\n");
    assert!(
        joined.contains("scene imports render (scene → render/film)"),
        "{joined}"
    );
    assert!(
        joined.contains("cycle: transport/x → transport/y → transport/x")
            || joined.contains("cycle: transport/y → transport/x → transport/y"),
        "{joined}"
    );
    assert!(joined.contains("transport/z"), "{joined}");
    // the comment, the string, the test module's `super::*`, the front
    // file's use of its own files: none is an import
    assert!(!joined.contains("scene/a →"), "{joined}");
    assert!(!joined.contains("transport →"), "{joined}");
    assert_eq!(problems.len(), 3, "{joined}");
}

/// Every `.rs` file under `dir`, as (path relative to `root`, text).
fn collect(root: &Path, dir: &Path, files: &mut Vec<(String, String)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().flatten().collect();
    entries.sort_by_key(|e| e.path());
    for entry in entries {
        let path = entry.path();
        if path.is_dir() {
            collect(root, &path, files);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let relative = path
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            files.push((relative, std::fs::read_to_string(&path).unwrap()));
        }
    }
}

/// The problems of a tree of files: upward imports between folders, and
/// cycles between files.
fn check(files: &[(String, String)]) -> Vec<String> {
    let modules: BTreeSet<Module> = files.iter().map(|(p, _)| module_of(p)).collect();
    let mut edges: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for (path, text) in files {
        let me = module_of(path);
        let binary = path == "main.rs" || path.starts_with("cli/");
        for (inner, segments) in paths_in(&strip_comments_and_strings(text)) {
            let Some(absolute) = absolute(&me, &inner, &segments, binary) else {
                continue;
            };
            let Some(target) = resolve(&modules, &absolute) else {
                continue;
            };
            // a module's use of what it contains is containment
            if target.len() >= me.len() && target[..me.len()] == me[..] {
                continue;
            }
            edges.entry(me.clone()).or_default().insert(target);
        }
    }

    let mut problems = Vec::new();
    for (from, targets) in &edges {
        let Some(folder) = from.first() else { continue };
        for to in targets {
            let other = &to[0];
            if other == folder {
                continue;
            }
            match (rank(folder), rank(other)) {
                (Some(a), Some(b)) if b < a => {}
                (Some(_), Some(_)) => problems.push(format!(
                    "{folder} imports {other} ({} → {}), a folder above it",
                    name(from),
                    name(to)
                )),
                _ => problems.push(format!(
                    "{} → {}: a folder missing from ORDER in tests/architecture.rs",
                    name(from),
                    name(to)
                )),
            }
        }
    }
    problems.extend(cycles(&edges));
    problems
}

/// `src/a/b.rs` → [a, b]; `src/a/mod.rs` → [a]; `lib.rs`, `main.rs` → [].
fn module_of(path: &str) -> Module {
    let stem = path.trim_end_matches(".rs");
    let mut parts: Module = stem.split('/').map(str::to_string).collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    if parts == ["lib"] || parts == ["main"] {
        parts.clear();
    }
    parts
}

fn rank(folder: &str) -> Option<usize> {
    ORDER.iter().position(|f| *f == folder)
}

fn name(module: &Module) -> String {
    if module.is_empty() {
        "lib".into()
    } else {
        module.join("/")
    }
}

/// `text` without comments, and with every string and character literal
/// emptied, so that neither can be read as a path.
fn strip_comments_and_strings(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            out.push(' ');
        } else if c == 'r'
            && matches!(next, Some('"') | Some('#'))
            && !chars[..i]
                .last()
                .is_some_and(|p| p.is_alphanumeric() || *p == '_')
        {
            // a raw string: r"…", r#"…"#
            let mut j = i + 1;
            let mut hashes = 0;
            while chars.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if chars.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= chars.len() {
                    break;
                }
                if chars[j] == '"' && (1..=hashes).all(|k| chars.get(j + k) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j;
        } else if c == '"' {
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' {
            // a character literal ('x', '\n', '\''), or a lifetime ('a)
            if next == Some('\\') {
                i += 2;
                while i < chars.len() && chars[i] != '\'' {
                    i += 1;
                }
                i += 1;
                out.push_str("' '");
            } else if chars.get(i + 2) == Some(&'\'') {
                i += 3;
                out.push_str("' '");
            } else {
                out.push(c);
                i += 1;
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// The paths a file names: each `use` tree's leaves, and every path that
/// starts with `crate`, `super`, `self` or `lumiere`, with the inline
/// modules (`mod tests { … }`) it sits in.
fn paths_in(text: &str) -> Vec<(Module, Vec<String>)> {
    let chars: Vec<char> = text.chars().collect();
    let word_at = |i: usize| -> String {
        chars[i..]
            .iter()
            .take_while(|c| c.is_alphanumeric() || **c == '_')
            .collect()
    };
    let mut paths = Vec::new();
    // the inline modules open here, with the brace depth inside each
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let starts_word = (c.is_alphabetic() || c == '_')
            && !(i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_'));
        if c == '{' {
            depth += 1;
        } else if c == '}' {
            if inline.last().is_some_and(|(_, d)| *d == depth) {
                inline.pop();
            }
            depth = depth.saturating_sub(1);
        } else if starts_word {
            let word = word_at(i);
            let inner: Module = inline.iter().map(|(m, _)| m.clone()).collect();
            if word == "mod" {
                let mut j = i + 3;
                while chars.get(j).is_some_and(|c| c.is_whitespace()) {
                    j += 1;
                }
                let module = word_at(j);
                j += module.len();
                while chars.get(j).is_some_and(|c| c.is_whitespace()) {
                    j += 1;
                }
                if chars.get(j) == Some(&'{') {
                    inline.push((module, depth + 1));
                    depth += 1;
                    i = j + 1;
                    continue;
                }
            } else if word == "use" {
                let end = chars[i..]
                    .iter()
                    .position(|c| *c == ';')
                    .map_or(chars.len(), |p| i + p);
                let raw: String = chars[i + 3..end].iter().collect();
                // `a::b as c` → `a::b@c`, then no spaces
                let words: Vec<&str> = raw.split_whitespace().collect();
                let tree = words.join(" ").replace(" as ", "@").replace(' ', "");
                // a re-export of a file the module contains is containment
                // (seen as such when resolved); any other use is an import
                for leaf in expand(&tree) {
                    paths.push((inner.clone(), leaf));
                }
                i = end;
                continue;
            } else if matches!(word.as_str(), "crate" | "super" | "self" | "lumiere")
                && chars.get(i + word.len()) == Some(&':')
                && !(i > 0 && chars[i - 1] == ':')
            {
                let path: String = chars[i..]
                    .iter()
                    .take_while(|c| c.is_alphanumeric() || **c == '_' || **c == ':')
                    .collect();
                let segments = path
                    .split("::")
                    .filter(|s| !s.is_empty())
                    .map(String::from)
                    .collect();
                paths.push((inner, segments));
                i += path.len();
                continue;
            }
            i += word.len();
            continue;
        }
        i += 1;
    }
    paths
}

/// The leaves of a `use` tree without spaces: `a::{b, c::{d, e}}` → a::b, a::c::d, a::c::e.
fn expand(tree: &str) -> Vec<Vec<String>> {
    let Some(open) = tree.find('{') else {
        let path = tree.split('@').next().unwrap_or(tree);
        return vec![
            path.split("::")
                .filter(|s| !s.is_empty())
                .map(String::from)
                .collect(),
        ];
    };
    let prefix: Vec<String> = tree[..open]
        .split("::")
        .filter(|s| !s.is_empty())
        .map(String::from)
        .collect();
    let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
    let mut parts = Vec::new();
    let (mut level, mut start) = (0, 0);
    for (k, c) in inner.char_indices() {
        match c {
            '{' => level += 1,
            '}' => level -= 1,
            ',' if level == 0 => {
                parts.push(&inner[start..k]);
                start = k + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts
        .into_iter()
        .filter(|p| !p.is_empty())
        .flat_map(expand)
        .map(|leaf| prefix.iter().cloned().chain(leaf).collect())
        .collect()
}

/// The absolute module path of `segments`, named in module `me` inside its
/// inline modules `inner`; `None` for paths into other crates.
fn absolute(me: &Module, inner: &Module, segments: &[String], binary: bool) -> Option<Vec<String>> {
    let (first, rest) = segments.split_first()?;
    let mut here: Module = me.iter().chain(inner).cloned().collect();
    match first.as_str() {
        "crate" => Some(rest.to_vec()),
        "lumiere" if binary => Some(rest.to_vec()),
        "self" => Some(here.into_iter().chain(rest.iter().cloned()).collect()),
        "super" => {
            here.pop();
            let mut rest = rest;
            while rest.first().is_some_and(|s| s == "super") {
                here.pop();
                rest = &rest[1..];
            }
            Some(here.into_iter().chain(rest.iter().cloned()).collect())
        }
        _ => None,
    }
}

/// The file a path leads into: its longest prefix that is a module file.
fn resolve(modules: &BTreeSet<Module>, path: &[String]) -> Option<Module> {
    (1..=path.len())
        .rev()
        .map(|n| path[..n].to_vec())
        .find(|m| modules.contains(m))
}

/// Every cycle of imports between files, as one path round it.
fn cycles(edges: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<String> {
    let mut found = Vec::new();
    let mut seen_cycles = BTreeSet::new();
    for (from, targets) in edges {
        for to in targets {
            // a path back from `to` to `from` closes a cycle through this edge
            let Some(back) = path_between(edges, to, from) else {
                continue;
            };
            let mut members: Vec<Module> = back.clone();
            members.sort();
            if seen_cycles.insert(members) {
                let names: Vec<String> =
                    std::iter::once(from).chain(back.iter()).map(name).collect();
                found.push(format!("cycle: {}", names.join(" → ")));
            }
        }
    }
    found
}

/// The modules on a path of imports from `from` to `to` (both included).
fn path_between(
    edges: &BTreeMap<Module, BTreeSet<Module>>,
    from: &Module,
    to: &Module,
) -> Option<Vec<Module>> {
    let mut previous: BTreeMap<Module, Module> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([from.clone()]);
    let mut visited = BTreeSet::from([from.clone()]);
    while let Some(module) = queue.pop_front() {
        if &module == to {
            let mut path = vec![module.clone()];
            let mut at = module;
            while let Some(p) = previous.get(&at) {
                path.push(p.clone());
                at = p.clone();
            }
            path.reverse();
            return Some(path);
        }
        for next in edges.get(&module).into_iter().flatten() {
            if visited.insert(next.clone()) {
                previous.insert(next.clone(), module.clone());
                queue.push_back(next.clone());
            }
        }
    }
    None
}
