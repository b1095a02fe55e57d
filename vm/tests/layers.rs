//! The module layers of `lib.rs`'s doc, checked on the real module graph: every `.rs`
//! file of the crate is parsed with `syn`, `mod` declarations are followed from `lib.rs`
//! (inline modules, `mod.rs` directories and `#[path]` included), and every path that
//! reaches a module of the crate is collected: `use` trees in all their forms (groups,
//! nested groups, renames, globs, `self`), `crate::`, `super::` and `self::` paths in
//! types, expressions, patterns and macro bodies, and paths through a child module's
//! name. A module may name only its own top-level module or one of a lower layer, so the
//! graph has no cycles; a top-level module missing from the table, or a table entry with
//! no module, fails too. A test (`syn` is a dev-dependency); it reads `src/` from disk.

#![allow(
    clippy::disallowed_methods,
    reason = "the guard reads the crate's sources"
)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use proc_macro2::{Spacing, TokenStream, TokenTree};
use syn::visit::{self, Visit};

/// (top-level module, layer), as `lib.rs`'s doc lists them. A module may use only its
/// own top-level module (its submodules included) or one of a lower layer. The crate
/// root (`lib.rs`, the API) is layer [`ROOT_LAYER`]; nested modules (`ops::bits`,
/// `vcd::tests`) have their top-level module's layer.
const LAYERS: &[(&str, u8)] = &[
    ("fault", 0),
    ("memory", 0),
    ("op", 0),
    ("vcd", 0),
    ("fuse", 1),
    ("fast", 1),
    ("machine", 1),
    ("clock", 1),
    ("terminals", 1),
    ("interrupts", 1),
    ("exch", 1),
    ("decode", 2),
    ("program", 3),
    ("calls", 4),
    ("tier", 4),
    ("tier_generic", 3),
    ("ops", 4),
    ("engine", 5),
    ("debug", 6),
    ("load", 6),
];

/// `lib.rs`: the API over every layer, which no module may name.
const ROOT_LAYER: u8 = 7;

/// A module of the tree: its path from the crate root (empty for the root), the file
/// that holds it and the module paths it names, each with the path as written.
#[derive(Debug, Default)]
struct Module {
    file: PathBuf,
    uses: Vec<(Vec<String>, String)>,
}

/// The crate's module tree, keyed by module path (`[]` is the root, `["ops", "bits"]`).
type Tree = BTreeMap<Vec<String>, Module>;

/// Reads the tree from `root` (a crate's `lib.rs`) through `read`, which returns a
/// file's text. Problems (a file missing or not Rust) are pushed to `errors`.
fn module_tree(
    root: &Path,
    read: &dyn Fn(&Path) -> Option<String>,
    errors: &mut Vec<String>,
) -> Tree {
    let mut tree = Tree::new();
    // Pass 1: the modules and their items, so that pass 2 can resolve paths.
    let mut bodies: Vec<(Vec<String>, Vec<syn::Item>)> = Vec::new();
    load_file(&mut tree, &mut bodies, Vec::new(), root, true, read, errors);
    // Pass 2: the paths each module names.
    for (module, items) in &bodies {
        let mut names = Names {
            tree: &tree,
            module,
            uses: Vec::new(),
        };
        for item in items {
            names.visit_item(item);
        }
        let uses = names.uses;
        tree.get_mut(module)
            .expect("module in tree")
            .uses
            .extend(uses);
    }
    tree
}

/// Parses `file` as module `path` and follows its `mod` declarations. `mod_rs` is true
/// for `lib.rs` and `mod.rs` files, whose children live beside them.
fn load_file(
    tree: &mut Tree,
    bodies: &mut Vec<(Vec<String>, Vec<syn::Item>)>,
    path: Vec<String>,
    file: &Path,
    mod_rs: bool,
    read: &dyn Fn(&Path) -> Option<String>,
    errors: &mut Vec<String>,
) {
    let Some(text) = read(file) else {
        errors.push(format!(
            "module {} : cannot read {}",
            show(&path),
            file.display()
        ));
        return;
    };
    let parsed = match syn::parse_file(&text) {
        Ok(parsed) => parsed,
        Err(e) => {
            errors.push(format!("{}: {e}", file.display()));
            return;
        }
    };
    let dir = file.parent().unwrap_or(Path::new("")).to_path_buf();
    let children = if mod_rs {
        dir.clone()
    } else {
        dir.join(file.file_stem().unwrap_or_default())
    };
    tree.insert(
        path.clone(),
        Module {
            file: file.to_path_buf(),
            uses: Vec::new(),
        },
    );
    load_items(
        tree,
        bodies,
        path,
        file,
        &dir,
        &children,
        parsed.items,
        read,
        errors,
    );
}

/// Records module `path` with `items` and follows the `mod` items among them (at item
/// level: the crate declares no module inside a function). `children` is the directory
/// of its file-backed children.
#[allow(clippy::too_many_arguments)]
fn load_items(
    tree: &mut Tree,
    bodies: &mut Vec<(Vec<String>, Vec<syn::Item>)>,
    path: Vec<String>,
    file: &Path,
    dir: &Path,
    children: &Path,
    items: Vec<syn::Item>,
    read: &dyn Fn(&Path) -> Option<String>,
    errors: &mut Vec<String>,
) {
    let mut kept = Vec::new();
    for item in items {
        let syn::Item::Mod(module) = item else {
            kept.push(item);
            continue;
        };
        let mut child = path.clone();
        child.push(module.ident.to_string());
        let explicit = module.attrs.iter().find_map(|a| match &a.meta {
            syn::Meta::NameValue(nv) if nv.path.is_ident("path") => match &nv.value {
                syn::Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Str(s),
                    ..
                }) => Some(s.value()),
                _ => None,
            },
            _ => None,
        });
        match module.content {
            Some((_, inner)) => {
                let below = children.join(module.ident.to_string());
                tree.insert(
                    child.clone(),
                    Module {
                        file: file.to_path_buf(),
                        uses: Vec::new(),
                    },
                );
                load_items(tree, bodies, child, file, dir, &below, inner, read, errors);
            }
            None => {
                let name = module.ident.to_string();
                let (target, mod_rs) = match explicit {
                    // `#[path]` outside inline modules is relative to the file's directory.
                    Some(p) => (dir.join(&p), p.ends_with("mod.rs")),
                    None => {
                        let flat = children.join(format!("{name}.rs"));
                        if read(&flat).is_some() {
                            (flat, false)
                        } else {
                            (children.join(&name).join("mod.rs"), true)
                        }
                    }
                };
                load_file(tree, bodies, child, &target, mod_rs, read, errors);
            }
        }
    }
    bodies.push((path, kept));
}

/// Collects the module paths one module names. Nested `mod` items were taken out by
/// `load_items`; each is visited as its own module.
struct Names<'a> {
    tree: &'a Tree,
    module: &'a [String],
    uses: Vec<(Vec<String>, String)>,
}

impl Names<'_> {
    /// Records `segments` (as written) if it starts at a module of the crate: `crate`,
    /// `super`, `self`, `$crate` or a child module's name. The module recorded is the
    /// longest prefix that is a module of the tree.
    fn record(&mut self, segments: &[String]) {
        let Some(first) = segments.first() else {
            return;
        };
        let mut at: Vec<String> = match first.as_str() {
            "crate" | "$crate" => Vec::new(),
            "self" => self.module.to_vec(),
            "super" => {
                let mut up = self.module.to_vec();
                up.pop();
                up
            }
            name => {
                let mut child = self.module.to_vec();
                child.push(name.to_string());
                if !self.tree.contains_key(&child) {
                    return;
                }
                child
            }
        };
        for segment in &segments[1..] {
            match segment.as_str() {
                "super" => {
                    at.pop();
                }
                "self" => {}
                name => {
                    let mut next = at.clone();
                    next.push(name.to_string());
                    if !self.tree.contains_key(&next) {
                        break;
                    }
                    at = next;
                }
            }
        }
        self.uses.push((at, segments.join("::")));
    }

    /// Every path of a `use` tree, `prefix` being the segments above it.
    fn use_tree(&mut self, prefix: &mut Vec<String>, tree: &syn::UseTree) {
        match tree {
            syn::UseTree::Path(p) => {
                prefix.push(p.ident.to_string());
                self.use_tree(prefix, &p.tree);
                prefix.pop();
            }
            syn::UseTree::Name(n) => self.use_name(prefix, &n.ident),
            syn::UseTree::Rename(r) => self.use_name(prefix, &r.ident),
            syn::UseTree::Glob(_) => {
                let whole = prefix.clone();
                self.record(&whole);
            }
            syn::UseTree::Group(g) => {
                for item in &g.items {
                    self.use_tree(prefix, item);
                }
            }
        }
    }

    fn use_name(&mut self, prefix: &[String], ident: &syn::Ident) {
        let mut whole = prefix.to_vec();
        // `a::{self}` names `a` itself.
        if ident != "self" || whole.is_empty() {
            whole.push(ident.to_string());
        }
        self.record(&whole);
    }

    /// Paths inside a macro's tokens (`format!`, `matches!`, `macro_rules!` bodies):
    /// `crate`, `super`, `self` or `$crate` followed by `::`.
    fn tokens(&mut self, tokens: TokenStream) {
        let list: Vec<TokenTree> = tokens.into_iter().collect();
        let mut i = 0;
        while i < list.len() {
            match &list[i] {
                TokenTree::Group(g) => self.tokens(g.stream()),
                TokenTree::Ident(id)
                    if matches!(id.to_string().as_str(), "crate" | "super" | "self") =>
                {
                    let dollar =
                        i > 0 && matches!(&list[i - 1], TokenTree::Punct(p) if p.as_char() == '$');
                    let mut segments = vec![if dollar {
                        format!("${id}")
                    } else {
                        id.to_string()
                    }];
                    let mut j = i + 1;
                    while let (
                        Some(TokenTree::Punct(a)),
                        Some(TokenTree::Punct(b)),
                        Some(TokenTree::Ident(next)),
                    ) = (list.get(j), list.get(j + 1), list.get(j + 2))
                    {
                        if a.as_char() != ':' || a.spacing() != Spacing::Joint || b.as_char() != ':'
                        {
                            break;
                        }
                        segments.push(next.to_string());
                        j += 3;
                    }
                    if segments.len() > 1 {
                        self.record(&segments);
                    }
                    i = j.max(i + 1);
                    continue;
                }
                _ => {}
            }
            i += 1;
        }
    }
}

impl<'ast> Visit<'ast> for Names<'_> {
    fn visit_item_use(&mut self, item: &'ast syn::ItemUse) {
        if item.leading_colon.is_none() {
            self.use_tree(&mut Vec::new(), &item.tree);
        }
    }

    fn visit_path(&mut self, path: &'ast syn::Path) {
        if path.leading_colon.is_none() {
            let segments: Vec<String> = path.segments.iter().map(|s| s.ident.to_string()).collect();
            // A lone name is an item or a value (`self` too), not a module.
            if segments.len() > 1 {
                self.record(&segments);
            }
        }
        visit::visit_path(self, path);
    }

    // `pub(crate)`, `pub(super)`, `pub(in crate::x)` say who may see an item, not
    // what the module uses.
    fn visit_vis_restricted(&mut self, _: &'ast syn::VisRestricted) {}

    fn visit_macro(&mut self, mac: &'ast syn::Macro) {
        self.visit_path(&mac.path);
        self.tokens(mac.tokens.clone());
    }
}

fn show(path: &[String]) -> String {
    if path.is_empty() {
        "crate".to_string()
    } else {
        path.join("::")
    }
}

/// Every breach of `layers` in the crate whose root is `root`: a module naming a
/// module of its own or a higher layer (other than its own top-level module), a
/// top-level module missing from `layers`, an entry of `layers` with no module, and
/// any file that cannot be read or parsed.
fn check(
    layers: &[(&str, u8)],
    root: &Path,
    read: &dyn Fn(&Path) -> Option<String>,
) -> Vec<String> {
    let mut wrong = Vec::new();
    let tree = module_tree(root, read, &mut wrong);
    let layer = |path: &[String]| -> Option<u8> {
        match path.first() {
            None => Some(ROOT_LAYER),
            Some(top) => layers.iter().find(|l| l.0 == top).map(|l| l.1),
        }
    };
    for top in tree.keys().filter(|p| p.len() == 1) {
        if layer(top).is_none() {
            let file = tree[top].file.display();
            wrong.push(format!(
                "module {} ({file}) is not in the layer table",
                top[0]
            ));
        }
    }
    for (name, _) in layers {
        if !tree.contains_key(&[name.to_string()][..]) {
            wrong.push(format!("layer table lists {name}, which is not a module"));
        }
    }
    for (module, m) in &tree {
        let Some(own) = layer(module) else { continue };
        for (used, written) in &m.uses {
            if module.is_empty() || used.first() == module.first() {
                continue;
            }
            match layer(used) {
                Some(l) if l < own => {}
                Some(l) => wrong.push(format!(
                    "{} (layer {own}, {}) names {written}: {} (layer {l})",
                    show(module),
                    m.file.display(),
                    show(used)
                )),
                // Unlisted: reported above.
                None => {}
            }
        }
    }
    wrong
}

#[test]
fn module_layers() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let wrong = check(LAYERS, &src.join("lib.rs"), &|p| {
        std::fs::read_to_string(p).ok()
    });
    assert!(
        wrong.is_empty(),
        "module layers broken:\n{}",
        wrong.join("\n")
    );
}

/// The real tree is seen whole: nested modules, and the paths the old line-based guard
/// missed (`ops/*` name `super::`, `engine` names `crate::tier` in an expression).
#[test]
fn the_real_tree_is_read() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut errors = Vec::new();
    let tree = module_tree(
        &src.join("lib.rs"),
        &|p| std::fs::read_to_string(p).ok(),
        &mut errors,
    );
    assert!(errors.is_empty(), "{errors:?}");
    let has = |p: &str| tree.contains_key(&p.split("::").map(String::from).collect::<Vec<_>>());
    assert!(has("ops::bits") && has("ops::timers") && has("vcd::tests") && has("tier"));
    let uses = |p: &str| &tree[&p.split("::").map(String::from).collect::<Vec<_>>()].uses;
    assert!(uses("ops::bits")
        .iter()
        .any(|(m, w)| m == &["ops"] && w.starts_with("super::")));
    assert!(uses("engine")
        .iter()
        .any(|(m, w)| m == &["tier"] && w == "crate::tier::compile"));
    assert!(uses("vcd::tests").iter().any(|(m, _)| m == &["vcd"]));
}

/// The real crate with one upper-layer import appended to `memory.rs` (in memory only):
/// the guard reports it.
#[test]
fn the_real_crate_with_an_upward_import_fails() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let memory = src.join("memory.rs");
    let wrong = check(LAYERS, &src.join("lib.rs"), &|p| {
        let text = std::fs::read_to_string(p).ok()?;
        Some(if p == memory {
            format!("{text}\nuse crate::{{\n    memory::{{self, Memory}},\n    engine::{{Engine}},\n}};\n")
        } else {
            text
        })
    });
    assert_eq!(wrong.len(), 1, "{wrong:?}");
    assert!(wrong[0].starts_with("memory (layer 0"), "{wrong:?}");
    assert!(
        wrong[0].ends_with("names crate::engine::Engine: engine (layer 5)"),
        "{wrong:?}"
    );
}

/// Checks an in-memory crate: `files` are (path under `src/`, text).
fn check_sources(layers: &[(&str, u8)], files: &[(&str, &str)]) -> Vec<String> {
    let files: BTreeMap<PathBuf, String> = files
        .iter()
        .map(|(p, t)| (Path::new("src").join(p), t.to_string()))
        .collect();
    check(layers, Path::new("src/lib.rs"), &|p| files.get(p).cloned())
}

/// A small crate: `low` (0), `mid` (1) with a submodule in `mid/`, `high` (2).
const SMALL: &[(&str, u8)] = &[("low", 0), ("mid", 1), ("high", 2)];

fn small(mid: &str, mid_sub: &str) -> Vec<String> {
    check_sources(
        SMALL,
        &[
            (
                "lib.rs",
                "mod low;\nmod mid;\nmod high;\npub use high::Api;\n",
            ),
            (
                "low.rs",
                "pub struct Low;\npub mod inner { pub struct Deep; }\n",
            ),
            ("mid/mod.rs", mid),
            ("mid/sub.rs", mid_sub),
            ("high.rs", "use crate::{low::Low, mid};\npub struct Api;\n"),
        ],
    )
}

#[test]
fn a_clean_crate_passes() {
    let wrong = small(
        "mod sub;\nuse crate::low::{self, inner::{Deep}, Low};\npub struct Mid(Low, Deep);\n",
        "use super::Mid;\nuse crate::mid::Mid as M;\nfn f() -> crate::low::Low { crate::low::Low }\n",
    );
    assert!(wrong.is_empty(), "{wrong:?}");
}

#[test]
fn a_multi_line_group_of_an_upper_layer_fails() {
    let wrong = small(
        "mod sub;\nuse crate::{\n    low::Low,\n    high::Api,\n};\n",
        "",
    );
    assert_eq!(wrong.len(), 1, "{wrong:?}");
    assert!(
        wrong[0].contains("mid (layer 1") && wrong[0].contains("crate::high::Api"),
        "{wrong:?}"
    );
}

#[test]
fn a_name_after_a_nested_group_fails() {
    let wrong = small(
        "mod sub;\nuse crate::{low::{inner::Deep, Low}, high};\n",
        "",
    );
    assert_eq!(wrong.len(), 1, "{wrong:?}");
    assert!(
        wrong[0].contains("names crate::high: high (layer 2)"),
        "{wrong:?}"
    );
}

#[test]
fn a_super_path_fails() {
    // `mid::sub` reaches `high` through `super::super`.
    let wrong = small("mod sub;\n", "use super::super::high::Api;\n");
    assert_eq!(wrong.len(), 1, "{wrong:?}");
    assert!(wrong[0].contains("mid::sub (layer 1") && wrong[0].contains("super::super::high::Api"));
}

#[test]
fn a_path_in_an_expression_or_type_fails() {
    let wrong = small(
        "mod sub;\nfn f() { let _ = crate::high::Api; }\n",
        "fn g(_: crate::high::Api) {}\n",
    );
    assert_eq!(wrong.len(), 2, "{wrong:?}");
}

#[test]
fn a_path_in_a_macro_fails() {
    let wrong = small(
        "mod sub;\nfn f() { assert!(matches!(x, crate::high::Api)); }\n",
        "",
    );
    assert_eq!(wrong.len(), 1, "{wrong:?}");
}

#[test]
fn naming_the_root_fails() {
    // `crate::Api` is the root's re-export: the API layer, above every module.
    let wrong = small("mod sub;\nuse crate::Api;\n", "");
    assert_eq!(wrong.len(), 1, "{wrong:?}");
    assert!(wrong[0].contains("crate (layer 7)"), "{wrong:?}");
}

#[test]
fn an_unlisted_module_fails() {
    let wrong = check_sources(
        SMALL,
        &[
            ("lib.rs", "mod low;\nmod mid;\nmod high;\nmod extra;\n"),
            ("low.rs", ""),
            ("mid.rs", ""),
            ("high.rs", ""),
            ("extra.rs", "use crate::high;\n"),
        ],
    );
    assert_eq!(
        wrong,
        ["module extra (src/extra.rs) is not in the layer table"]
    );
}

#[test]
fn a_table_entry_without_a_module_and_a_missing_file_fail() {
    let wrong = check_sources(SMALL, &[("lib.rs", "mod low;\nmod mid;\n"), ("low.rs", "")]);
    assert_eq!(wrong.len(), 3, "{wrong:?}");
    assert!(wrong[0].contains("cannot read src/mid/mod.rs"), "{wrong:?}");
    assert!(wrong
        .iter()
        .any(|w| w == "layer table lists mid, which is not a module"));
    assert!(wrong
        .iter()
        .any(|w| w == "layer table lists high, which is not a module"));
}
