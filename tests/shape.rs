//! The source's shape, held by test: no Rust source file over [`MAX_FILE_LINES`] lines, no
//! production function over [`MAX_FN_LINES`] lines, and no import circle between the modules
//! of a crate.
//!
//! Every `.rs` file of the repository counts (build outputs and hidden folders aside). Test code
//! (`#[cfg(test)]` modules, `#[test]` functions, files under a `tests/` folder) is exempt from
//! the function rule only. A function's length runs from its `fn` line to its closing brace.
//!
//! The module graph of a crate is its `mod` tree with an edge wherever a module's production
//! code names another module's item: a `use` (of any visibility) or a path in code that starts
//! with `crate::`, `self::` or `super::`. Re-exports are followed to the module that defines the
//! item, so `use crate::X`, with `pub use a::X` at the root, is an import of `a`. An edge between
//! two modules counts between their ancestors that are siblings (`a::b` importing `c::d` is `a`
//! importing `c`); a module naming its own ancestor or descendant adds none. Each crate's
//! graph must have no circle. Test modules import as they please and are left out.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use syn::spanned::Spanned;
use syn::visit::{self, Visit};

/// The most lines a source file may have.
const MAX_FILE_LINES: usize = 600;
/// The most lines a production function may have.
const MAX_FN_LINES: usize = 80;

/// Findings tolerated for now: file, the finding's start (`fn name`, `import circle`) and
/// why. Each must still be found: an allowance nothing needs fails the test.
#[rustfmt::skip]
const ALLOWED: &[(&str, &str, &str)] = &[];

/// A module path inside its crate (`[]` is the crate root).
type ModPath = Vec<String>;

/// A name in a module's namespace.
enum Name {
    /// A child module.
    Module,
    /// An item defined here (type, function, constant, …).
    Item,
    /// A `use` of this path (from the module's root, `crate` first).
    Alias(ModPath),
}

/// One module: its file, whether it is test code, its names and what it refers to.
struct Module {
    file: PathBuf,
    test: bool,
    names: HashMap<String, Name>,
    /// `use path::*` (absolute paths).
    globs: Vec<ModPath>,
    /// Paths its production code names (absolute), with their line.
    refs: Vec<(ModPath, usize)>,
}

#[test]
fn no_long_file_no_long_function_no_import_circle() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).canonicalize();
    let root = root.unwrap();
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    files.sort();
    assert!(files.len() > 50, "found only {} .rs files", files.len());
    let shown = |file: &Path| {
        file.strip_prefix(&root)
            .unwrap_or(file)
            .display()
            .to_string()
    };
    let parsed: BTreeMap<PathBuf, syn::File> = files
        .iter()
        .map(|file| {
            let source = std::fs::read_to_string(file).unwrap();
            let ast = syn::parse_file(&source).unwrap_or_else(|e| panic!("{}: {e}", shown(file)));
            (file.clone(), ast)
        })
        .collect();

    // A crate root is a file no `mod` declaration reaches.
    let reached: BTreeSet<PathBuf> = parsed
        .iter()
        .flat_map(|(file, ast)| ast.items.iter().map(move |item| (file, item)))
        .filter_map(|(file, item)| match item {
            syn::Item::Mod(m) if m.content.is_none() => {
                Some(module_file(file, &m.ident.to_string()))
            }
            _ => None,
        })
        .collect();
    let mut crates = BTreeMap::new();
    for file in parsed.keys().filter(|f| !reached.contains(*f)) {
        let mut modules = BTreeMap::new();
        let test = shown(file).split('/').any(|part| part == "tests");
        load(
            &parsed,
            file,
            &parsed[file].items,
            vec![],
            test,
            &mut modules,
        );
        crates.insert(file.clone(), modules);
    }
    // A file is test code if all of it is (a `#[cfg(test)] mod tests;`), not if it holds one.
    let modules = || crates.values().flat_map(|modules| modules.values());
    let production: BTreeSet<&PathBuf> = modules().filter(|m| !m.test).map(|m| &m.file).collect();
    let test_files: BTreeSet<&PathBuf> = modules()
        .map(|m| &m.file)
        .filter(|f| !production.contains(f))
        .collect();

    let mut findings = Vec::new();
    for (file, ast) in &parsed {
        let lines = std::fs::read_to_string(file).unwrap().lines().count();
        if lines > MAX_FILE_LINES {
            let what = format!("{lines} lines (most {MAX_FILE_LINES})");
            findings.push((shown(file), what));
        }
        let mut long = LongFunctions {
            test: test_files.contains(file),
            found: vec![],
        };
        long.visit_file(ast);
        for (name, line, n) in long.found {
            let what = format!("fn {name} is {n} lines (most {MAX_FN_LINES})");
            findings.push((format!("{}:{line}", shown(file)), what));
        }
    }
    for (crate_root, modules) in &crates {
        for circle in circles(modules, &shown) {
            findings.push((shown(crate_root), format!("import circle {circle}")));
        }
    }
    report(&findings);
}

/// The circle check finds a circle that only resolving a root re-export shows, and none once
/// the item moves out.
#[test]
fn a_circle_through_a_root_re_export_is_found() {
    let crate_of = |a: &str, b: &str| {
        let files = [
            ("lib.rs", "mod a; mod b; pub use a::X;"),
            ("a/mod.rs", a),
            ("b/mod.rs", b),
        ];
        let parsed: BTreeMap<PathBuf, syn::File> = files
            .iter()
            .map(|(f, src)| (Path::new("/virtual").join(f), syn::parse_file(src).unwrap()))
            .collect();
        let root = Path::new("/virtual/lib.rs");
        let mut modules = BTreeMap::new();
        load(
            &parsed,
            root,
            &parsed[root].items,
            vec![],
            false,
            &mut modules,
        );
        circles(&modules, &|f: &Path| f.display().to_string())
    };
    let found = crate_of(
        "pub struct X; fn f(_: crate::b::Y) {}",
        "pub struct Y; use crate::X;",
    );
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].starts_with("a ↔ b:"), "{found:?}");
    assert!(crate_of("pub struct X;", "pub struct Y; use crate::X;").is_empty());
}

/// Prints the allowed findings and fails on the others, or on an allowance nothing needs.
fn report(findings: &[(String, String)]) {
    let mut report = String::new();
    let mut needed = BTreeSet::new();
    for (place, what) in findings {
        let file = place.split(':').next().unwrap_or(place);
        let allowed = ALLOWED
            .iter()
            .position(|(f, start, _)| *f == file && what.starts_with(start));
        match allowed {
            Some(i) => {
                needed.insert(i);
                println!("allowed ({}): {place}: {what}", ALLOWED[i].2);
            }
            None => writeln!(report, "  {place}: {what}").unwrap(),
        }
    }
    for (i, (file, start, why)) in ALLOWED.iter().enumerate() {
        if !needed.contains(&i) {
            let what = format!("`{start}` allowed ({why}) but not found: drop it");
            writeln!(report, "  {file}: {what}").unwrap();
        }
    }
    assert!(report.is_empty(), "the source's shape:\n{report}");
}

/// Every `.rs` file under `dir`, skipping hidden folders and build outputs (a cargo target
/// folder holds a `CACHEDIR.TAG`).
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    if dir.join("CACHEDIR.TAG").exists() {
        return;
    }
    for entry in std::fs::read_dir(dir).expect("a readable folder") {
        let path = entry.expect("a folder entry").path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name.starts_with('.') {
            continue;
        }
        if path.is_dir() {
            rust_files(&path, out);
        } else if name.ends_with(".rs") {
            out.push(path);
        }
    }
}

/// The file of `mod name;` declared in `file`: in the folder named after `file` if there is
/// one (and `file` is no `mod.rs`), else beside `file` (a crate root, a `mod.rs`).
fn module_file(file: &Path, name: &str) -> PathBuf {
    let dir = file.parent().expect("a file in a folder");
    let stem = file.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    let nested = dir.join(stem);
    let base = if stem == "mod" || !nested.is_dir() {
        dir.to_path_buf()
    } else {
        nested
    };
    let flat = base.join(format!("{name}.rs"));
    if flat.exists() {
        flat
    } else {
        base.join(name).join("mod.rs")
    }
}

/// Whether attributes hold `#[cfg(test)]` (alone or within `all(…)`) or `#[test]`.
fn is_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("test")
            || (a.path().is_ident("cfg") && {
                let tokens = a.meta.require_list().map(|l| l.tokens.to_string());
                tokens.is_ok_and(|t| t == "test" || t.starts_with("all (test"))
            })
    })
}

/// Registers the module at `path` made of `items` (in `file`) and its descendants.
fn load(
    parsed: &BTreeMap<PathBuf, syn::File>,
    file: &Path,
    items: &[syn::Item],
    path: ModPath,
    test: bool,
    modules: &mut BTreeMap<ModPath, Module>,
) {
    let mut names = HashMap::new();
    let mut uses = vec![];
    for item in items {
        match item {
            syn::Item::Mod(m) => {
                let name = m.ident.to_string();
                let child = [path.clone(), vec![name.clone()]].concat();
                let test = test || is_test(&m.attrs);
                if let Some((_, inner)) = &m.content {
                    load(parsed, file, inner, child, test, modules);
                } else if let Some((child_file, ast)) =
                    parsed.get_key_value(&module_file(file, &name))
                {
                    load(parsed, child_file, &ast.items, child, test, modules);
                }
                names.insert(name, Name::Module);
            }
            syn::Item::Use(u) => {
                let mut leaves = vec![];
                use_leaves(&u.tree, &mut vec![], &mut leaves);
                let production = !(test || is_test(&u.attrs));
                uses.extend(
                    leaves
                        .into_iter()
                        .map(|l| (l, production, u.span().start().line)),
                );
            }
            _ => {
                if let Some(name) = item_name(item) {
                    names.entry(name).or_insert(Name::Item);
                }
            }
        }
    }
    // Names bound by `use`s, then what they name from the crate root.
    for ((_, alias), _, _) in &uses {
        if let Some(name) = alias.as_ref().filter(|a| *a != "*" && *a != "_") {
            names.insert(name.clone(), Name::Alias(vec![]));
        }
    }
    let mut module = Module {
        file: file.to_path_buf(),
        test,
        names: HashMap::new(),
        globs: vec![],
        refs: vec![],
    };
    for ((segments, alias), production, line) in uses {
        let Some(target) = absolute(&path, &segments, &names) else {
            continue;
        };
        match alias.as_deref() {
            Some("*") => module.globs.push(target.clone()),
            Some("_") | None => {}
            Some(name) => {
                module
                    .names
                    .insert(name.into(), Name::Alias(target.clone()));
            }
        }
        if production {
            module.refs.push((target, line));
        }
    }
    if !test {
        let mut refs = Refs { found: vec![] };
        for item in items.iter().filter(|i| !matches!(i, syn::Item::Use(_))) {
            refs.visit_item(item);
        }
        for (segments, line) in refs.found {
            if let Some(target) = absolute(&path, &segments, &names) {
                module.refs.push((target, line));
            }
        }
    }
    for (name, kind) in names {
        module.names.entry(name).or_insert(kind);
    }
    modules.insert(path, module);
}

/// The name an item defines, if any.
fn item_name(item: &syn::Item) -> Option<String> {
    let ident = match item {
        syn::Item::Const(i) => &i.ident,
        syn::Item::Enum(i) => &i.ident,
        syn::Item::Fn(i) => &i.sig.ident,
        syn::Item::Macro(i) => i.ident.as_ref()?,
        syn::Item::Static(i) => &i.ident,
        syn::Item::Struct(i) => &i.ident,
        syn::Item::Trait(i) => &i.ident,
        syn::Item::Type(i) => &i.ident,
        syn::Item::Union(i) => &i.ident,
        _ => return None,
    };
    Some(ident.to_string())
}

/// Each leaf of a `use` tree: its path and the name it binds (`*` for a glob).
fn use_leaves(tree: &syn::UseTree, prefix: &mut ModPath, out: &mut Vec<(ModPath, Option<String>)>) {
    match tree {
        syn::UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            use_leaves(&p.tree, prefix, out);
            prefix.pop();
        }
        syn::UseTree::Name(n) if n.ident == "self" => {
            out.push((prefix.clone(), prefix.last().cloned()));
        }
        syn::UseTree::Name(n) => {
            let name = n.ident.to_string();
            out.push(([prefix.clone(), vec![name.clone()]].concat(), Some(name)));
        }
        syn::UseTree::Rename(r) => {
            let path = [prefix.clone(), vec![r.ident.to_string()]].concat();
            out.push((path, Some(r.rename.to_string())));
        }
        syn::UseTree::Glob(_) => out.push((prefix.clone(), Some("*".into()))),
        syn::UseTree::Group(g) => g.items.iter().for_each(|t| use_leaves(t, prefix, out)),
    }
}

/// `segments`, named in module `at`, as a path from the crate root; `None` for another crate's.
fn absolute(at: &[String], segments: &[String], names: &HashMap<String, Name>) -> Option<ModPath> {
    let (first, rest) = segments.split_first()?;
    let mut base: ModPath = match first.as_str() {
        "crate" => vec![],
        "self" => at.to_vec(),
        "super" => at[..at.len().checked_sub(1)?].to_vec(),
        name if names.contains_key(name) => return Some([at, segments].concat()),
        _ => return None,
    };
    let mut rest = rest;
    while rest.first().is_some_and(|s| s == "super") {
        base.pop()?;
        rest = &rest[1..];
    }
    Some([base, rest.to_vec()].concat())
}

/// The module that defines what `path` (from the crate root) names, following `use`s.
fn resolve(modules: &BTreeMap<ModPath, Module>, path: &[String], depth: usize) -> ModPath {
    let mut at: ModPath = vec![];
    for (i, segment) in path.iter().enumerate() {
        let Some(module) = modules.get(&at).filter(|_| depth < 16) else {
            return at;
        };
        match module.names.get(segment) {
            Some(Name::Module) => at.push(segment.clone()),
            Some(Name::Item) => return at,
            Some(Name::Alias(target)) => {
                let onward = [target.as_slice(), &path[i + 1..]].concat();
                return resolve(modules, &onward, depth + 1);
            }
            None => {
                for glob in &module.globs {
                    let onward = [glob.as_slice(), &path[i..]].concat();
                    let found = resolve(modules, &onward, depth + 1);
                    if found != *glob {
                        return found;
                    }
                }
                return at;
            }
        }
    }
    at
}

/// The import circles among sibling modules, one line each: the modules, then each import
/// that closes the circle with where it is.
fn circles(modules: &BTreeMap<ModPath, Module>, shown: &impl Fn(&Path) -> String) -> Vec<String> {
    let mut edges: BTreeMap<ModPath, BTreeMap<ModPath, String>> = BTreeMap::new();
    for (from, module) in modules.iter().filter(|(_, m)| !m.test) {
        for (path, line) in &module.refs {
            let to = resolve(modules, path, 0);
            let shared = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
            if shared == from.len() || shared == to.len() {
                continue;
            }
            let evidence = format!(
                "{}:{line} `crate::{}`",
                shown(&module.file),
                path.join("::")
            );
            edges
                .entry(from[..=shared].to_vec())
                .or_default()
                .entry(to[..=shared].to_vec())
                .or_insert(evidence);
        }
    }
    let mut out = vec![];
    for component in strongly_connected(&edges) {
        let mut line = component
            .iter()
            .map(|m| m.join("::"))
            .collect::<Vec<_>>()
            .join(" ↔ ");
        line.push(':');
        for from in &component {
            for (to, evidence) in edges[from].iter().filter(|(to, _)| component.contains(to)) {
                write!(
                    line,
                    "\n      {} → {}: {evidence}",
                    from.join("::"),
                    to.join("::")
                )
                .unwrap();
            }
        }
        out.push(line);
    }
    out
}

/// The strongly connected components of more than one node (Tarjan).
fn strongly_connected(edges: &BTreeMap<ModPath, BTreeMap<ModPath, String>>) -> Vec<Vec<ModPath>> {
    struct Tarjan<'a> {
        edges: &'a BTreeMap<ModPath, BTreeMap<ModPath, String>>,
        index: HashMap<&'a ModPath, (usize, usize)>,
        stack: Vec<&'a ModPath>,
        out: Vec<Vec<ModPath>>,
    }
    impl<'a> Tarjan<'a> {
        fn visit(&mut self, node: &'a ModPath) -> usize {
            let n = self.index.len();
            self.index.insert(node, (n, n));
            self.stack.push(node);
            let mut low = n;
            for next in self.edges.get(node).into_iter().flat_map(|e| e.keys()) {
                low = match self.index.get(next) {
                    None => low.min(self.visit(next)),
                    Some(&(i, _)) if self.stack.contains(&next) => low.min(i),
                    Some(_) => low,
                };
            }
            if low == n {
                let at = self
                    .stack
                    .iter()
                    .rposition(|m| *m == node)
                    .expect("on the stack");
                let component: Vec<_> = self.stack.drain(at..).cloned().collect();
                if component.len() > 1 {
                    self.out.push(component);
                }
            }
            low
        }
    }
    let mut tarjan = Tarjan {
        edges,
        index: HashMap::new(),
        stack: vec![],
        out: vec![],
    };
    for node in edges.keys() {
        if !tarjan.index.contains_key(node) {
            tarjan.visit(node);
        }
    }
    tarjan.out
}

/// Paths in code that start with `crate`, `self` or `super` (test modules and `use`s aside:
/// those are read by [`load`]).
struct Refs {
    found: Vec<(ModPath, usize)>,
}

impl<'ast> Visit<'ast> for Refs {
    fn visit_item_mod(&mut self, _: &'ast syn::ItemMod) {}

    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        let mut leaves = vec![];
        use_leaves(&u.tree, &mut vec![], &mut leaves);
        let line = u.span().start().line;
        self.found
            .extend(leaves.into_iter().map(|(path, _)| (path, line)));
    }

    fn visit_path(&mut self, path: &'ast syn::Path) {
        let segments: ModPath = path.segments.iter().map(|s| s.ident.to_string()).collect();
        if segments.len() > 1 && ["crate", "self", "super"].contains(&segments[0].as_str()) {
            self.found.push((segments, path.span().start().line));
        }
        visit::visit_path(self, path);
    }
}

/// Production functions over [`MAX_FN_LINES`] lines: name, first line, length.
struct LongFunctions {
    test: bool,
    found: Vec<(String, usize, usize)>,
}

impl LongFunctions {
    fn check(&mut self, attrs: &[syn::Attribute], sig: &syn::Signature, body: &syn::Block) {
        let first = sig.fn_token.span.start().line;
        let lines = body.brace_token.span.close().end().line + 1 - first;
        if !self.test && !is_test(attrs) && lines > MAX_FN_LINES {
            self.found.push((sig.ident.to_string(), first, lines));
        }
    }
}

impl<'ast> Visit<'ast> for LongFunctions {
    fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
        let outer = self.test;
        self.test |= is_test(&m.attrs);
        visit::visit_item_mod(self, m);
        self.test = outer;
    }

    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        self.check(&f.attrs, &f.sig, &f.block);
        visit::visit_item_fn(self, f);
    }

    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        self.check(&f.attrs, &f.sig, &f.block);
        visit::visit_impl_item_fn(self, f);
    }

    fn visit_trait_item_fn(&mut self, f: &'ast syn::TraitItemFn) {
        if let Some(body) = &f.default {
            self.check(&f.attrs, &f.sig, body);
        }
        visit::visit_trait_item_fn(self, f);
    }
}
