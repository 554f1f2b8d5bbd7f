//! No import circles between the modules of a crate (issue 35: a reader
//! follows a crate one way, from the modules that use to the modules they
//! use, and never comes back).
//!
//! Every `crates/*/src/**/*.rs` is parsed: its module path comes from its
//! file path (`gltf/read.rs` is `gltf::read`, `gltf/mod.rs` and
//! `symmetry.rs` are the parents of `gltf/…` and `symmetry/…`; each
//! `src/bin/NAME.rs` is a crate of its own). Module A depends on module B
//! when A's code names a path into B: `crate::b::…`, `super::b::…`,
//! `super::super::…`, and each branch of a grouped `use crate::{a, b::C}`,
//! resolved to the longest prefix that is a module of a file. Not counted:
//!
//! - a child naming an ancestor (`super::Options` in `symmetry/grid.rs`)
//!   and a parent naming its descendants (declaring or re-exporting them):
//!   a module and its own submodules are one unit to a reader (so a circle
//!   through a submodule, `run → run::partition → simplify → run`, shows
//!   as one through its ancestor: `run`, `simplify`);
//! - code under `#[cfg(test)]` (test modules, test-only files such as
//!   `#[cfg(test)] mod test_support;`, single items): tests may reach
//!   anywhere;
//! - comments, doc comments included, and string literals. A doc link is
//!   not an import: a low-level module may point its reader at the one that
//!   uses it ("the run calls this") without that making a circle, and
//!   forbidding those links would only turn them into unchecked plain text.
//!
//! The strongly connected components of that graph with more than one
//! module are the circles (Tarjan's algorithm). They must be exactly
//! [`KNOWN`]: a new circle fails the test, and so does dissolving a known
//! one until its entry is removed, so the list always says what is left.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The circles not dissolved yet, per crate: each entry must be a strongly
/// connected component of today's graph, and every such component must be
/// here. When you dissolve one, delete its entry (the test fails until you
/// do); never add one to make the test pass — make the imports go one way.
/// Empty since issue 35: no crate has a circle.
const KNOWN: &[(&str, &[&str])] = &[];

/// A module path inside its crate (`["gltf", "read"]`; the root is empty).
type ModPath = Vec<String>;

/// Where a dependency was first seen, for the failure message.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Site {
    file: PathBuf,
    line: usize,
}

/// One crate's module graph: every file module, and for each the modules
/// its code depends on, with the first place it does.
#[derive(Debug, Default)]
struct Graph {
    edges: BTreeMap<String, BTreeMap<String, Site>>,
}

impl Graph {
    /// The module → dependencies relation without the sites.
    fn adjacency(&self) -> BTreeMap<String, BTreeSet<String>> {
        self.edges
            .iter()
            .map(|(m, to)| (m.clone(), to.keys().cloned().collect()))
            .collect()
    }
}

fn join(p: &[String]) -> String {
    p.join("::")
}

/// The module a source file is, from its path relative to `src/` (or to a
/// binary's folder): `a/b.rs` and `a/b/mod.rs` are `a::b`; `lib.rs`,
/// `main.rs` and `mod.rs` name their folder's module.
fn module_of(rel: &Path) -> ModPath {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|s| s.to_string_lossy().into_owned())
        .collect();
    if let Some(last) = parts.last_mut() {
        if let Some(stem) = last.strip_suffix(".rs") {
            *last = stem.to_string();
        }
    }
    if parts
        .last()
        .is_some_and(|l| l == "mod" || l == "lib" || l == "main")
    {
        parts.pop();
    }
    parts
}

fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The source with comments, string literals and character literals
/// replaced by spaces (newlines kept, so lines still count), leaving only
/// code: paths in them are not dependencies, and braces in them must not
/// unbalance the item skipping.
fn code_only(src: &str) -> String {
    let s: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let blank = |out: &mut String, chars: &[char]| {
        for &c in chars {
            out.push(if c == '\n' { '\n' } else { ' ' });
        }
    };
    let mut i = 0;
    while i < s.len() {
        let c = s[i];
        let next = s.get(i + 1).copied();
        let prev_ident = i > 0 && is_ident_char(s[i - 1]);
        if c == '/' && next == Some('/') {
            let end = s[i..]
                .iter()
                .position(|&c| c == '\n')
                .map_or(s.len(), |p| i + p);
            blank(&mut out, &s[i..end]);
            i = end;
        } else if c == '/' && next == Some('*') {
            // Block comments nest in Rust.
            let mut depth = 0;
            let mut j = i;
            while j < s.len() {
                if s[j] == '/' && s.get(j + 1) == Some(&'*') {
                    depth += 1;
                    j += 2;
                } else if s[j] == '*' && s.get(j + 1) == Some(&'/') {
                    depth -= 1;
                    j += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    j += 1;
                }
            }
            blank(&mut out, &s[i..j.min(s.len())]);
            i = j.min(s.len());
        } else if let Some(end) = raw_string_end(&s, i).filter(|_| !prev_ident) {
            blank(&mut out, &s[i..end]);
            i = end;
        } else if c == '"' {
            let mut j = i + 1;
            while j < s.len() && s[j] != '"' {
                j += if s[j] == '\\' { 2 } else { 1 };
            }
            let end = (j + 1).min(s.len());
            blank(&mut out, &s[i..end]);
            i = end;
        } else if c == '\'' {
            // A character literal ('x', '\n', '\u{7f}', '{'), or a lifetime
            // ('a), which stays.
            let end = if next == Some('\\') {
                // The escaped character is at i + 2, even when it is '.
                s.get(i + 3..)
                    .and_then(|rest| rest.iter().position(|&c| c == '\''))
                    .map(|p| i + 3 + p + 1)
            } else if s.get(i + 2) == Some(&'\'') {
                Some(i + 3)
            } else {
                None
            };
            match end {
                Some(end) => {
                    blank(&mut out, &s[i..end.min(s.len())]);
                    i = end.min(s.len());
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// Where the raw string (`r"…"`, `r#"…"#`, `br#"…"#`) starting at `s[i]`
/// ends, if one does.
fn raw_string_end(s: &[char], i: usize) -> Option<usize> {
    let r = if s[i] == 'b' { i + 1 } else { i };
    if s.get(r) != Some(&'r') {
        return None;
    }
    let hashes = s[r + 1..].iter().take_while(|&&c| c == '#').count();
    if s.get(r + 1 + hashes) != Some(&'"') {
        return None;
    }
    let closes = |j: usize| s[j] == '"' && (1..=hashes).all(|k| s.get(j + k) == Some(&'#'));
    Some(
        (r + 2 + hashes..s.len())
            .find(|&j| closes(j))
            .map_or(s.len(), |j| j + 1 + hashes),
    )
}

/// Blanks every item under `#[cfg(test)]` in comment-free code, and returns
/// the names of the file modules it declares (`#[cfg(test)] mod helpers;`),
/// which are test code as a whole.
fn strip_test_items(code: &str) -> (String, Vec<String>) {
    const ATTR: &str = "#[cfg(test)]";
    let mut s: Vec<char> = code.chars().collect();
    let attr: Vec<char> = ATTR.chars().collect();
    let mut test_files = Vec::new();
    let mut i = 0;
    while i + attr.len() <= s.len() {
        if s[i..i + attr.len()] != attr[..] {
            i += 1;
            continue;
        }
        let start = i;
        let mut j = i + attr.len();
        // Further attributes, then the item: it ends at a `;` outside any
        // bracket or at the brace that closes its body.
        let mut depth = 0i32;
        let mut seen_body = false;
        while j < s.len() {
            match s[j] {
                '(' | '[' | '{' => {
                    depth += 1;
                    seen_body |= s[j] == '{';
                }
                ')' | ']' | '}' => {
                    depth -= 1;
                    if depth == 0 && s[j] == '}' && seen_body {
                        j += 1;
                        break;
                    }
                }
                ';' if depth == 0 => {
                    j += 1;
                    break;
                }
                _ => {}
            }
            j += 1;
        }
        let j = j.min(s.len());
        let item: String = s[start + attr.len()..j].iter().collect();
        if let Some(name) = declared_file_module(&item) {
            test_files.push(name);
        }
        for c in &mut s[start..j] {
            if *c != '\n' {
                *c = ' ';
            }
        }
        i = j;
    }
    (s.into_iter().collect(), test_files)
}

/// `NAME` when `item` (attributes allowed) is `[pub(…)] mod NAME;`.
fn declared_file_module(item: &str) -> Option<String> {
    let mut rest = item.trim();
    while let Some(r) = rest.strip_prefix("#[") {
        rest = r.split_once(']')?.1.trim_start();
    }
    if let Some(r) = rest.strip_prefix("pub") {
        rest = r.trim_start();
        if let Some(r) = rest.strip_prefix('(') {
            rest = r.split_once(')')?.1.trim_start();
        }
    }
    let name = rest.strip_prefix("mod")?.trim().strip_suffix(';')?.trim();
    (!name.is_empty() && name.chars().all(is_ident_char)).then(|| name.to_string())
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    PathSep,
    Open(char),
    Close(char),
    Comma,
    Dollar,
    Other,
}

/// Tokens of comment-free code with their 1-based lines: only what paths
/// and module blocks are made of is told apart.
fn tokens(code: &str) -> Vec<(Tok, usize)> {
    let s: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut line = 1;
    let mut i = 0;
    while i < s.len() {
        let c = s[i];
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if is_ident_char(c) {
            let j = s[i..]
                .iter()
                .position(|&c| !is_ident_char(c))
                .map_or(s.len(), |p| i + p);
            out.push((Tok::Ident(s[i..j].iter().collect()), line));
            i = j;
        } else if c == ':' && s.get(i + 1) == Some(&':') {
            out.push((Tok::PathSep, line));
            i += 2;
        } else {
            out.push((
                match c {
                    '{' | '(' | '[' => Tok::Open(c),
                    '}' | ')' | ']' => Tok::Close(c),
                    ',' => Tok::Comma,
                    '$' => Tok::Dollar,
                    _ => Tok::Other,
                },
                line,
            ));
            i += 1;
        }
    }
    out
}

/// The paths of a use tree (or a plain path) starting at `t[i]`, each
/// with its line: `a::{b, c::{d, self}}` gives `a::b`, `a::c::d`, `a::c`.
/// A path stops at anything that is not `::` followed by a name or a group
/// (`::<T>`, `::*`, a call).
fn use_tree(
    t: &[(Tok, usize)],
    mut i: usize,
    prefix: &[String],
) -> (Vec<(Vec<String>, usize)>, usize) {
    let mut path = prefix.to_vec();
    let mut line = t.get(i).map_or(0, |x| x.1);
    loop {
        match t.get(i) {
            Some((Tok::Ident(name), l)) => {
                line = *l;
                if name != "self" || path.is_empty() {
                    path.push(name.clone());
                }
                i += 1;
            }
            Some((Tok::Open('{'), _)) => {
                let mut all = Vec::new();
                i += 1;
                loop {
                    match t.get(i) {
                        Some((Tok::Close('}'), _)) => {
                            i += 1;
                            break;
                        }
                        Some((Tok::Comma, _)) => i += 1,
                        None => break,
                        Some(_) => {
                            let before = i;
                            let (paths, next) = use_tree(t, i, &path);
                            all.extend(paths);
                            // Skip what a branch does not consume (`*`,
                            // `as name`), up to the next comma or brace.
                            i = next.max(before + 1);
                            while let Some((tok, _)) = t.get(i) {
                                if matches!(tok, Tok::Comma | Tok::Close('}')) {
                                    break;
                                }
                                i += 1;
                            }
                        }
                    }
                }
                return (all, i);
            }
            _ => return (vec![(path, line)], i),
        }
        if t.get(i).map(|x| &x.0) == Some(&Tok::PathSep) {
            match t.get(i + 1).map(|x| &x.0) {
                Some(Tok::Ident(_)) | Some(Tok::Open('{')) => i += 1,
                _ => return (vec![(path, line)], i),
            }
        } else {
            return (vec![(path, line)], i);
        }
    }
}

/// Every module path that `file`'s code (comment-free, test items
/// blanked) names, resolved from the module `module` the file is: each as
/// an absolute path within the crate, not yet cut to a file module.
fn references(code: &str, module: &[String]) -> Vec<(Vec<String>, usize)> {
    let t = tokens(code);
    let mut out = Vec::new();
    // Inline `mod name { … }` blocks: `super` and `self` in them are
    // relative to the inline module. (depth of its brace, name)
    let mut inline: Vec<(usize, String)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < t.len() {
        match &t[i].0 {
            Tok::Open('{') => depth += 1,
            Tok::Close('}') => {
                if inline.last().is_some_and(|(d, _)| *d == depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
            }
            Tok::Ident(kw) if kw == "mod" => {
                if let (Some((Tok::Ident(name), _)), Some((Tok::Open('{'), _))) =
                    (t.get(i + 1), t.get(i + 2))
                {
                    inline.push((depth + 1, name.clone()));
                }
            }
            Tok::Ident(root) if root == "crate" || root == "super" || root == "self" => {
                let after_sep = i > 0 && t[i - 1].0 == Tok::PathSep;
                let macro_var = i > 0 && t[i - 1].0 == Tok::Dollar;
                let followed = t.get(i + 1).map(|x| &x.0) == Some(&Tok::PathSep);
                if !after_sep && !macro_var && followed {
                    let (paths, next) = use_tree(&t, i, &[]);
                    let here: Vec<String> = module
                        .iter()
                        .cloned()
                        .chain(inline.iter().map(|(_, n)| n.clone()))
                        .collect();
                    for (path, line) in paths {
                        if let Some(abs) = absolute(&path, &here) {
                            out.push((abs, line));
                        }
                    }
                    i = next.max(i + 1);
                    continue;
                }
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// `path` (starting with `crate`, `self` or `super`s) made absolute from
/// the module `here`; `None` when it climbs above the crate root.
fn absolute(path: &[String], here: &[String]) -> Option<Vec<String>> {
    let (base, rest) = match path.first().map(String::as_str) {
        Some("crate") => (Vec::new(), &path[1..]),
        Some("self") => (here.to_vec(), &path[1..]),
        Some("super") => {
            let ups = path.iter().take_while(|s| *s == "super").count();
            let keep = here.len().checked_sub(ups)?;
            (here[..keep].to_vec(), &path[ups..])
        }
        _ => return None,
    };
    Some(base.into_iter().chain(rest.iter().cloned()).collect())
}

/// The module graph of one crate given its files, as (path relative to
/// the crate's module root, contents).
fn graph(files: &[(PathBuf, String)], origin: &Path) -> Graph {
    let mut cleaned = Vec::new();
    let mut test_only: BTreeSet<ModPath> = BTreeSet::new();
    for (rel, text) in files {
        let module = module_of(rel);
        let (code, tests) = strip_test_items(&code_only(text));
        if code.contains("#![cfg(test)]") {
            // A file that is test code as a whole.
            test_only.insert(module.clone());
        }
        for t in tests {
            test_only.insert(module.iter().cloned().chain([t]).collect());
        }
        cleaned.push((rel, module, code));
    }
    let in_tests = |m: &ModPath| test_only.iter().any(|t| m.starts_with(t));
    let modules: BTreeSet<ModPath> = cleaned
        .iter()
        .map(|(_, m, _)| m.clone())
        .filter(|m| !in_tests(m))
        .collect();
    let mut g = Graph::default();
    for m in &modules {
        g.edges.insert(join(m), BTreeMap::new());
    }
    for (rel, module, code) in &cleaned {
        if in_tests(module) {
            continue;
        }
        for (abs, line) in references(code, module) {
            let Some(target) = (1..=abs.len())
                .rev()
                .map(|k| abs[..k].to_vec())
                .find(|p| modules.contains(p))
            else {
                continue;
            };
            // Itself, an ancestor or a descendant: not an edge.
            if module.starts_with(&target) || target.starts_with(module) {
                continue;
            }
            g.edges
                .entry(join(module))
                .or_default()
                .entry(join(&target))
                .or_insert_with(|| Site {
                    file: origin.join(rel),
                    line,
                });
        }
    }
    g
}

/// The strongly connected components of more than one node (Tarjan 1972),
/// each sorted, in sorted order. Nodes only named as targets count too.
fn circles(adj: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct State<'a> {
        adj: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(st: &mut State<'a>, v: &'a str) {
        let n = st.index.len();
        st.index.insert(v, n);
        st.low.insert(v, n);
        st.stack.push(v);
        st.on_stack.insert(v);
        let adj = st.adj;
        for w in adj.get(v).into_iter().flatten() {
            let w = w.as_str();
            if !st.index.contains_key(w) {
                visit(st, w);
                let lw = st.low[w];
                let lv = st.low.get_mut(v).expect("visited");
                *lv = (*lv).min(lw);
            } else if st.on_stack.contains(w) {
                let iw = st.index[w];
                let lv = st.low.get_mut(v).expect("visited");
                *lv = (*lv).min(iw);
            }
        }
        if st.low[v] == st.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = st.stack.pop() {
                st.on_stack.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                st.found.push(comp);
            }
        }
    }
    let mut st = State {
        adj,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    let nodes: BTreeSet<&str> = adj
        .iter()
        .flat_map(|(v, ws)| std::iter::once(v).chain(ws))
        .map(String::as_str)
        .collect();
    for v in nodes {
        if !st.index.contains_key(v) {
            visit(&mut st, v);
        }
    }
    st.found.sort();
    st.found
}

/// Every `.rs` file under `dir`, relative to it, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        let entries = std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
        for e in entries {
            let p = e.expect("directory entry").path();
            if p.is_dir() {
                todo.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p.strip_prefix(dir).expect("under dir").to_path_buf());
            }
        }
    }
    out.sort();
    out
}

/// Source files as (path relative to the module root, contents).
type Files = Vec<(PathBuf, String)>;

/// The workspace's crates (and each `src/bin/NAME…` as a crate of its own):
/// name, the folder module paths are relative to, and its files.
fn workspace_crates() -> Vec<(String, PathBuf, Files)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let crates = root.join("crates");
    let mut names: Vec<String> = std::fs::read_dir(&crates)
        .expect("crates/")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| crates.join(n).join("src").is_dir())
        .collect();
    names.sort();
    let read = |dir: &Path, rel: &Path| {
        let p = dir.join(rel);
        std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    };
    let mut out = Vec::new();
    for name in names {
        let src = crates.join(&name).join("src");
        let mut lib = Vec::new();
        let mut bins: BTreeMap<String, Files> = BTreeMap::new();
        for rel in rust_files(&src) {
            if let Ok(in_bin) = rel.strip_prefix("bin") {
                // bin/x.rs is the root of binary x; bin/x/… its modules.
                let first = in_bin
                    .iter()
                    .next()
                    .map(|s| s.to_string_lossy().into_owned());
                let Some(first) = first else { continue };
                let (bin, local) = match first.strip_suffix(".rs") {
                    Some(stem) => (stem.to_string(), PathBuf::from("main.rs")),
                    None => (
                        first.clone(),
                        in_bin.strip_prefix(&first).expect("prefix").to_path_buf(),
                    ),
                };
                let text = read(&src, &rel);
                bins.entry(bin).or_default().push((local, text));
            } else {
                let text = read(&src, &rel);
                lib.push((rel, text));
            }
        }
        out.push((
            name.clone(),
            PathBuf::from(format!("crates/{name}/src")),
            lib,
        ));
        for (bin, files) in bins {
            out.push((
                format!("{name}/bin/{bin}"),
                PathBuf::from(format!("crates/{name}/src/bin/{bin}")),
                files,
            ));
        }
    }
    out
}

#[test]
fn module_circles_are_exactly_the_known_ones() {
    let crates = workspace_crates();
    assert!(
        crates
            .iter()
            .any(|(n, _, f)| n == "simplify" && f.len() > 10),
        "the workspace's sources were not found"
    );
    let mut found: BTreeSet<(String, Vec<String>)> = BTreeSet::new();
    let mut explain: BTreeMap<(String, Vec<String>), String> = BTreeMap::new();
    for (name, origin, files) in &crates {
        let g = graph(files, origin);
        for c in circles(&g.adjacency()) {
            // The edges inside the circle, each with where it comes from.
            let mut why = String::new();
            for from in &c {
                for (to, site) in &g.edges[from] {
                    if c.contains(to) {
                        why.push_str(&format!(
                            "\n    {from} -> {to}   ({}:{})",
                            site.file.display(),
                            site.line
                        ));
                    }
                }
            }
            explain.insert((name.clone(), c.clone()), why);
            found.insert((name.clone(), c));
        }
    }
    let known: BTreeSet<(String, Vec<String>)> = KNOWN
        .iter()
        .map(|(c, ms)| {
            let mut ms: Vec<String> = ms.iter().map(|m| m.to_string()).collect();
            ms.sort();
            (c.to_string(), ms)
        })
        .collect();
    let mut report = String::new();
    for new in found.difference(&known) {
        report.push_str(&format!(
            "\nnew import circle in crate `{}`: {:?}{}\n  (make the imports go one way: move what both use into the module it belongs to, or a small module both import)",
            new.0, new.1, explain[new]
        ));
    }
    for gone in known.difference(&found) {
        report.push_str(&format!(
            "\nknown circle in crate `{}` {:?} is no longer a circle (dissolved or changed): update KNOWN in {}",
            gone.0,
            gone.1,
            file!()
        ));
    }
    assert!(report.is_empty(), "{report}");
}

/// The simplifier's steps in the order they run (issue 35): each imports
/// only the steps before it and the contracts, so a reader follows the
/// crate top to bottom as meshoptimizer's one-file simplifier is read.
/// The entry points (arrays, meshes, scenes) come last and may use every
/// step; the contracts (what a caller gives and gets back) use none.
const SIMPLIFY_STEPS: &[&[&str]] = &[
    &["error", "input", "options", "report"],
    &["prepare"],
    &["edges"],
    &["terms"],
    &["collapse"],
    &["refit"],
    &["assemble"],
    // The quad ordering held to the measured output, around whole runs.
    &["quad_hold"],
    // Leftover triangle pairs joined into quads, after `simplify_mesh`.
    &["quad_pairs"],
    &["simplify", "mesh", "scene"],
];

#[test]
fn simplify_steps_import_only_the_steps_before_them() {
    let crates = workspace_crates();
    let (_, origin, files) = crates
        .iter()
        .find(|(n, _, _)| n == "simplify")
        .expect("the simplify crate's sources");
    let g = graph(files, origin);
    let rank = |m: &str| -> Option<usize> {
        let top = m.split("::").next().unwrap_or("");
        SIMPLIFY_STEPS.iter().position(|s| s.contains(&top))
    };
    let mut report = String::new();
    let mut checked = 0;
    for (from, to) in &g.edges {
        let Some(rf) = rank(from) else {
            // Only the crate root (lib.rs) may stand outside the steps.
            if !from.is_empty() {
                report.push_str(&format!(
                    "\nmodule `{from}` is in no step of SIMPLIFY_STEPS"
                ));
            }
            continue;
        };
        for (to, site) in to {
            checked += 1;
            match rank(to) {
                Some(rt) if rt <= rf => {}
                _ => report.push_str(&format!(
                    "\n`{from}` imports `{to}`, a later step ({}:{})",
                    site.file.display(),
                    site.line
                )),
            }
        }
    }
    assert!(
        checked > 50,
        "only {checked} imports seen: the parser lost the crate"
    );
    assert!(report.is_empty(), "{report}");
}

fn adj(edges: &[(&str, &str)]) -> BTreeMap<String, BTreeSet<String>> {
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (a, b) in edges {
        g.entry(a.to_string()).or_default().insert(b.to_string());
    }
    g
}

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

#[test]
fn tarjan_finds_each_circle_and_nothing_else() {
    // a → b → c → a is one circle; c → d leads into a second one d ⇄ e;
    // e → f and g → a lead out of or into circles without being on one;
    // h → h (a self-loop) is not a circle of modules.
    let g = adj(&[
        ("a", "b"),
        ("b", "c"),
        ("c", "a"),
        ("c", "d"),
        ("d", "e"),
        ("e", "d"),
        ("e", "f"),
        ("g", "a"),
        ("h", "h"),
    ]);
    assert_eq!(
        circles(&g),
        vec![strings(&["a", "b", "c"]), strings(&["d", "e"])]
    );
    // A chain and a diamond have none.
    assert!(circles(&adj(&[("a", "b"), ("b", "c"), ("a", "c"), ("c", "d")])).is_empty());
    // Two circles joined by one edge stay two; one more edge back makes one.
    let two = [("a", "b"), ("b", "a"), ("b", "c"), ("c", "d"), ("d", "c")];
    assert_eq!(circles(&adj(&two)).len(), 2);
    let mut one = two.to_vec();
    one.push(("d", "a"));
    assert_eq!(circles(&adj(&one)), vec![strings(&["a", "b", "c", "d"])]);
}

fn files(list: &[(&str, &str)]) -> Files {
    list.iter()
        .map(|(p, t)| (PathBuf::from(p), t.to_string()))
        .collect()
}

fn edge_list(g: &Graph) -> Vec<(String, String)> {
    g.edges
        .iter()
        .flat_map(|(a, to)| to.keys().map(move |b| (a.clone(), b.clone())))
        .collect()
}

fn pairs(v: &[(&str, &str)]) -> Vec<(String, String)> {
    v.iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect()
}

#[test]
fn edges_come_from_code_paths_only() {
    let g = graph(
        &files(&[
            ("lib.rs", "mod a; mod b; mod c; mod d; pub use a::A;"),
            (
                "a.rs",
                "//! See [`crate::b`] and `crate::c`.\n\
                 use crate::{d::D, util::{self, X}};\n\
                 /* crate::c */ const S: &str = \"crate::c\"; const R: &str = r#\"crate::c\"#;\n\
                 const Q: char = '{'; fn f<'a>(x: &'a u8) {}\n\
                 #[cfg(test)]\nmod tests { use crate::c::C; }\n\
                 macro_rules! m { () => { $crate::c::C } }",
            ),
            (
                "b.rs",
                "use super::a;\n#[cfg(test)]\nuse crate::c;\nfn g() {}",
            ),
            (
                "c/mod.rs",
                "mod inner; pub(super) use self::inner::I; use super::Root;",
            ),
            ("c/inner.rs", "use super::super::b::B; use crate::c::Thing;"),
            (
                "d.rs",
                "#[cfg(test)]\nmod helpers;\nfn h() { crate::util::go(); }",
            ),
            ("d/helpers.rs", "use crate::a::A;"),
            ("util.rs", "pub fn go() {}"),
        ]),
        Path::new("src"),
    );
    assert_eq!(
        edge_list(&g),
        pairs(&[
            ("a", "d"),
            ("a", "util"),
            ("b", "a"),
            ("c::inner", "b"),
            ("d", "util"),
        ])
    );
    // The test-only file is no module of the graph.
    assert!(!g.edges.contains_key("d::helpers"));
    // Line numbers point at the reference.
    assert_eq!(g.edges["c::inner"]["b"].line, 1);
    assert_eq!(g.edges["a"]["util"].line, 2);
}

#[test]
fn super_in_an_inline_module_is_relative_to_it() {
    // `super` inside `mod inner { … }` in x.rs is x itself: `super::y`
    // names an item of x, not the sibling module y.
    let g = graph(
        &files(&[
            ("lib.rs", "mod x; mod y;"),
            (
                "x.rs",
                "pub fn y() {}\nmod inner { use super::y; }\nuse super::y::Z;",
            ),
            ("y.rs", ""),
        ]),
        Path::new("src"),
    );
    assert_eq!(edge_list(&g), pairs(&[("x", "y")]));
    assert_eq!(g.edges["x"]["y"].line, 3);
}

#[test]
fn module_paths_follow_the_file_layout() {
    assert_eq!(module_of(Path::new("lib.rs")), Vec::<String>::new());
    assert_eq!(module_of(Path::new("gltf/mod.rs")), strings(&["gltf"]));
    assert_eq!(
        module_of(Path::new("gltf/read.rs")),
        strings(&["gltf", "read"])
    );
    assert_eq!(module_of(Path::new("symmetry.rs")), strings(&["symmetry"]));
}
