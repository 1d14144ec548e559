//! Imports go one way. This test reads `src/`, finds which module each file refers to
//! (`crate::a::b`, `super::x`, `use crate::{…}` groups, names re-exported by a `mod.rs`
//! resolved to the file that defines them), and fails on
//!
//! - an edge between top-level modules that goes against the layer order `ARCHITECTURE.md`
//!   draws (its fenced block headed `layers`, lowest first; a module may use only modules on
//!   lower lines), or a top-level module that the block does not place;
//! - an import cycle between the files of one module (`render/looks/mod.rs` →
//!   `render/looks/mosaic/mod.rs` → `render/looks/mod.rs`, say), found by a depth-first search
//!   over the file graph;
//! - inside `render`, an edge between its parts that goes against the order of the block
//!   headed `render-layers` (cells below looks, say), or from one look's folder into another's
//!   (looks never import each other: only `looks/mod.rs`, which picks one, names them all);
//! - a folder with more than 15 source files side by side (group them by concept).
//!
//! A module's own `#[cfg(test)] mod tests` is left out: tests may reach anywhere below.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A file's module path, e.g. `["render", "look"]`; `mod.rs` and `lib.rs` name their folder.
type ModPath = Vec<String>;

struct SourceFile {
    module: ModPath,
    is_dir_module: bool,
    code: String,
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The code without comments, string literals and the trailing test module.
fn code_of(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod tests") {
        Some(i) => &text[..i],
        None => text,
    };
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let mut in_string = false;
        let mut prev = ' ';
        let chars: Vec<char> = line.chars().collect();
        let mut k = 0;
        while k < chars.len() {
            let c = chars[k];
            if !in_string && c == '/' && chars.get(k + 1) == Some(&'/') {
                break;
            }
            if c == '"' && prev != '\\' && !(prev == '\'' && chars.get(k + 1) == Some(&'\'')) {
                in_string = !in_string;
            } else if !in_string {
                out.push(c);
            }
            prev = c;
            k += 1;
        }
        out.push('\n');
    }
    out
}

fn load_sources() -> Vec<SourceFile> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files
        .into_iter()
        .filter(|p| p.file_name().unwrap() != "main.rs")
        .map(|path| {
            let rel = path.strip_prefix(&src).unwrap();
            let mut module: ModPath = rel
                .with_extension("")
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            let last = module.last().unwrap().clone();
            let is_dir_module = last == "mod" || last == "lib";
            if is_dir_module {
                module.pop();
            }
            let text = std::fs::read_to_string(&path).unwrap();
            SourceFile {
                module,
                is_dir_module,
                code: code_of(&text),
            }
        })
        .collect()
}

fn ident_at(s: &str) -> Option<&str> {
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    (end > 0).then(|| &s[..end])
}

/// Every path the code names after `crate::` or `super::`, as segments from the crate root.
fn referenced_paths(file: &SourceFile) -> Vec<ModPath> {
    let mut paths = Vec::new();
    let parent: ModPath = if file.is_dir_module {
        file.module[..file.module.len().saturating_sub(1)].to_vec()
    } else {
        file.module[..file.module.len() - 1].to_vec()
    };
    for (anchor, base) in [("crate::", Vec::new()), ("super::", parent)] {
        let mut rest = file.code.as_str();
        while let Some(i) = rest.find(anchor) {
            let before = rest[..i].chars().last();
            rest = &rest[i + anchor.len()..];
            if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':') {
                continue; // `xcrate::`, or `super::super::` handled from its first part
            }
            let mut segments = base.clone();
            let mut tail = rest;
            loop {
                if let Some(group) = tail.strip_prefix('{') {
                    // `use crate::{a::b, c}`: each item of the group.
                    let end = group.find('}').unwrap_or(group.len());
                    for item in group[..end].split(',') {
                        let mut p = segments.clone();
                        p.extend(
                            item.trim()
                                .split("::")
                                .map_while(ident_at)
                                .map(str::to_string),
                        );
                        paths.push(p);
                    }
                    break;
                }
                let Some(id) = ident_at(tail) else { break };
                if id == "super" {
                    segments.pop();
                } else {
                    segments.push(id.to_string());
                }
                tail = &tail[id.len()..];
                match tail.strip_prefix("::") {
                    Some(t) => tail = t,
                    None => {
                        paths.push(segments.clone());
                        break;
                    }
                }
            }
        }
    }
    paths
}

/// Names a `mod.rs` re-exports (`pub use child::{A, B}`, `pub use child::A`) → that child.
fn re_exports(files: &[SourceFile]) -> BTreeMap<(ModPath, String), String> {
    let mut map = BTreeMap::new();
    for f in files.iter().filter(|f| f.is_dir_module) {
        for line in f.code.lines() {
            let Some(rest) = line.trim().strip_prefix("pub use ") else {
                continue;
            };
            let Some((child, names)) = rest.split_once("::") else {
                continue;
            };
            let names = names.trim_end_matches(';');
            let names = names.trim_start_matches('{').trim_end_matches('}');
            for name in names.split(',') {
                let name = name.trim().rsplit("::").next().unwrap_or("");
                let name = name.split(" as ").last().unwrap_or(name).trim();
                if !name.is_empty() {
                    map.insert((f.module.clone(), name.to_string()), child.to_string());
                }
            }
        }
    }
    map
}

/// The file-level module graph: module → modules it refers to.
fn graph() -> BTreeMap<ModPath, BTreeSet<ModPath>> {
    let files = load_sources();
    let modules: BTreeSet<ModPath> = files.iter().map(|f| f.module.clone()).collect();
    let exports = re_exports(&files);
    let mut graph = BTreeMap::new();
    for f in &files {
        let mut targets = BTreeSet::new();
        for path in referenced_paths(f) {
            // The longest prefix that is a module file.
            let Some(n) = (0..=path.len())
                .rev()
                .find(|&n| modules.contains(&path[..n]))
            else {
                continue;
            };
            let mut target = path[..n].to_vec();
            if let Some(child) = path
                .get(n)
                .and_then(|name| exports.get(&(target.clone(), name.clone())))
            {
                target.push(child.clone());
            }
            // A file's own submodules and its own folder's facade are not edges.
            if target != f.module && !target.is_empty() {
                targets.insert(target);
            }
        }
        graph.insert(f.module.clone(), targets);
    }
    graph
}

/// The layers `ARCHITECTURE.md` draws in its fenced block headed `name`, lowest first: each
/// line names the modules of one layer.
fn documented_layers(name: &str) -> Vec<Vec<String>> {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md"))
            .unwrap();
    let fence = format!("```{name}\n");
    let start = text
        .find(&fence)
        .unwrap_or_else(|| panic!("ARCHITECTURE.md has a {fence} block"))
        + fence.len();
    let end = start + text[start..].find("```").unwrap();
    text[start..end]
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .map(|l| {
            l.split(|c: char| c.is_whitespace() || c == ',')
                .filter(|w| !w.is_empty())
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .filter(|l| !l.is_empty())
        .collect()
}

/// The edges of `graph` below the module `parent` (empty: the crate) that go against the
/// layers of `block`: between two children of `parent`, from one on a line to one on the
/// same or a higher line. The parent's own file (its `mod.rs`) may use every child.
fn edges_against_layers(
    graph: &BTreeMap<ModPath, BTreeSet<ModPath>>,
    parent: &[&str],
    block: &str,
) -> Vec<String> {
    let layers = documented_layers(block);
    let layer_of: BTreeMap<&str, usize> = layers
        .iter()
        .enumerate()
        .flat_map(|(k, l)| l.iter().map(move |m| (m.as_str(), k)))
        .collect();
    let depth = parent.len();
    let inside = |m: &ModPath| m.len() > depth && m[..depth].iter().eq(parent.iter());
    let mut wrong = Vec::new();
    for (from, targets) in graph.iter().filter(|(m, _)| inside(m)) {
        let part = &from[depth];
        let Some(&lf) = layer_of.get(part.as_str()) else {
            wrong.push(format!("{part} is not placed in ARCHITECTURE.md's {block}"));
            continue;
        };
        for to in targets.iter().filter(|m| inside(m)) {
            let t = &to[depth];
            if t == part {
                continue;
            }
            match layer_of.get(t.as_str()) {
                Some(&lt) if lt < lf => {}
                Some(_) => wrong.push(format!(
                    "{} uses {} (same or higher layer)",
                    from.join("::"),
                    to.join("::")
                )),
                None => wrong.push(format!("{t} is not placed in ARCHITECTURE.md's {block}")),
            }
        }
    }
    wrong.sort();
    wrong.dedup();
    wrong
}

#[test]
fn top_level_modules_import_only_lower_layers() {
    let wrong = edges_against_layers(&graph(), &[], "layers");
    assert!(
        wrong.is_empty(),
        "imports against the layers:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn render_parts_import_only_lower_layers() {
    let wrong = edges_against_layers(&graph(), &["render"], "render-layers");
    assert!(
        wrong.is_empty(),
        "imports inside render against its layers:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn looks_never_import_each_other() {
    let mut wrong = Vec::new();
    for (from, targets) in graph() {
        // A file inside one look's folder: render::looks::<look>[::…].
        let [r, l, look, ..] = from.as_slice() else {
            continue;
        };
        if r != "render" || l != "looks" {
            continue;
        }
        for to in &targets {
            if let [r, l, other, ..] = to.as_slice() {
                if r == "render" && l == "looks" && other != look {
                    wrong.push(format!("{} uses {}", from.join("::"), to.join("::")));
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "a look imports another:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn no_folder_is_a_heap() {
    let mut files = Vec::new();
    rust_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    let mut per_folder: BTreeMap<PathBuf, usize> = BTreeMap::new();
    for f in files {
        *per_folder
            .entry(f.parent().unwrap().to_path_buf())
            .or_default() += 1;
    }
    let heaps: Vec<String> = per_folder
        .iter()
        .filter(|(_, &n)| n > 15)
        .map(|(d, n)| format!("{} ({n} files)", d.display()))
        .collect();
    assert!(heaps.is_empty(), "folders to group by concept: {heaps:?}");
}

#[test]
fn files_within_a_module_have_no_import_cycle() {
    let graph = graph();
    // Depth-first search with colours; the first back edge found is reported as the cycle.
    fn visit(
        node: &ModPath,
        graph: &BTreeMap<ModPath, BTreeSet<ModPath>>,
        state: &mut BTreeMap<ModPath, u8>,
        stack: &mut Vec<ModPath>,
    ) -> Option<Vec<ModPath>> {
        state.insert(node.clone(), 1);
        stack.push(node.clone());
        for next in graph.get(node).into_iter().flatten() {
            match state.get(next).copied().unwrap_or(0) {
                1 => {
                    let from = stack.iter().position(|n| n == next).unwrap();
                    let mut cycle = stack[from..].to_vec();
                    cycle.push(next.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(next, graph, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(node.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for node in graph.keys() {
        if state.get(node).copied().unwrap_or(0) == 0 {
            let cycle = visit(node, &graph, &mut state, &mut Vec::new());
            let names: Vec<String> = cycle
                .unwrap_or_default()
                .iter()
                .map(|m| m.join("::"))
                .collect();
            assert!(names.is_empty(), "import cycle: {}", names.join(" → "));
        }
    }
}

#[test]
fn the_checker_sees_imports() {
    // The checker itself must find what is there: a known edge of each kind.
    let g = graph();
    let edges = |m: &[&str]| g[&m.iter().map(|s| s.to_string()).collect::<Vec<_>>()].clone();
    let has = |from: &[&str], to: &[&str]| {
        edges(from).contains(&to.iter().map(|s| s.to_string()).collect::<Vec<_>>())
    };
    assert!(
        has(&["render", "looks", "mosaic"], &["render", "scene"]),
        "super:: path"
    );
    assert!(
        has(&["io", "npy"], &["field", "grid"]),
        "crate:: path through a re-export"
    );
    assert!(has(&["input"], &["io"]), "crate:: path");
    assert!(
        has(
            &["render", "looks", "engraving"],
            &["render", "lines", "streamlines"]
        ),
        "crate:: path from a look's folder"
    );
    // A cycle in a made-up graph is found.
    let a = code_of("use crate::x::y; // crate::z\nlet s = \"crate::w\";\n");
    assert!(a.contains("crate::x::y") && !a.contains("crate::z") && !a.contains("crate::w"));
}
