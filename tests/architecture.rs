//! The folder tree is the pipeline: every top-level module of `src/` imports only modules of
//! its own or an earlier stage, and the module graph has no cycle. The stages are the table in
//! `src/lib.rs`'s "Pipeline" section (`| stage | [`module`], … | … |`); a module missing from
//! the table, or a `crate::` path into a later stage, fails this test with the offending file.
//!
//! Only code counts: comments (including doc links) and `#[cfg(test)] mod tests` blocks are
//! left out, since tests may reach anywhere and a doc link is not a dependency.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// `module → stage` from the pipeline table of `lib.rs`.
fn stages(lib: &str) -> Result<BTreeMap<String, u32>, String> {
    let mut stages = BTreeMap::new();
    for line in lib.lines() {
        let Some(row) = line.strip_prefix("//! |") else { continue };
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        let Ok(stage) = cells[0].parse::<u32>() else { continue };
        for name in cells.get(1).unwrap_or(&"").split(',') {
            let name = name.trim().trim_start_matches("[`").trim_end_matches("`]");
            if !name.is_empty() && stages.insert(name.to_string(), stage).is_some() {
                return Err(format!("module `{name}` appears twice in the stage table"));
            }
        }
    }
    Ok(stages)
}

/// The top-level modules declared in `lib.rs` (`mod x;` / `pub mod x;`).
fn declared(lib: &str) -> BTreeSet<String> {
    lib.lines()
        .filter_map(|l| {
            let l = l.trim();
            let l = l.strip_prefix("pub ").unwrap_or(l);
            l.strip_prefix("mod ")?.strip_suffix(';').map(str::to_string)
        })
        .collect()
}

/// The code of a source file: comments and the `#[cfg(test)]` test module removed.
fn code(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod tests") {
        Some(k) => &text[..k],
        None => text,
    };
    text.lines()
        .map(|l| match l.find("//") {
            Some(k) => &l[..k],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The top-level modules that `code` names through `crate::`.
fn references(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let ident = |s: &str| -> String {
        s.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect()
    };
    let mut rest = code;
    while let Some(k) = rest.find("crate::") {
        let after = &rest[k + "crate::".len()..];
        if let Some(group) = after.strip_prefix('{') {
            // `use crate::{a, b::c, d::{e, f}}`: the first segment of each top-level item.
            let mut depth = 0;
            let mut start = true;
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => start = true,
                    c if start && (c.is_ascii_alphabetic() || c == '_') => {
                        out.insert(ident(&group[i..]));
                        start = false;
                    }
                    c if start && !c.is_whitespace() => start = false,
                    _ => {}
                }
            }
        } else {
            out.insert(ident(after));
        }
        rest = after;
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = fs::read_dir(dir).expect("read src/").flatten().collect();
    entries.sort_by_key(|e| e.path());
    for e in entries {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Checks the crate rooted at `src`: every violation, one line each (empty when the layout
/// holds).
fn violations(src: &Path) -> Vec<String> {
    let lib = fs::read_to_string(src.join("lib.rs")).expect("read lib.rs");
    let stage = match stages(&lib) {
        Ok(s) => s,
        Err(e) => return vec![e],
    };
    let mut errors = Vec::new();
    let modules = declared(&lib);
    for m in &modules {
        if !stage.contains_key(m) {
            errors.push(format!("module `{m}` is not in lib.rs's stage table"));
        }
    }
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut files = Vec::new();
    rust_files(src, &mut files);
    for file in files {
        let rel = file.strip_prefix(src).expect("under src");
        let first = rel.components().next().expect("a path").as_os_str().to_string_lossy();
        let module = first.trim_end_matches(".rs").to_string();
        if module == "lib" || module == "main" {
            continue;
        }
        let text = fs::read_to_string(&file).expect("read a source file");
        for target in references(&code(&text)) {
            if target == module || !modules.contains(&target) {
                continue;
            }
            let (from, to) = (stage.get(&module), stage.get(&target));
            if let (Some(&from), Some(&to)) = (from, to) {
                if to > from {
                    errors.push(format!(
                        "{}: `{module}` (stage {from}) imports `{target}` (stage {to}), a later stage",
                        rel.display()
                    ));
                }
            }
            graph.entry(module.clone()).or_default().insert(target);
        }
    }
    if let Some(cycle) = find_cycle(&graph) {
        errors.push(format!("import cycle: {}", cycle.join(" -> ")));
    }
    errors
}

/// A cycle of `graph`, if it has one (depth-first search with an explicit path).
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        v: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(k) = path.iter().position(|p| p == v) {
            let mut cycle = path[k..].to_vec();
            cycle.push(v.to_string());
            return Some(cycle);
        }
        if done.contains(v) {
            return None;
        }
        path.push(v.to_string());
        for w in graph.get(v).into_iter().flatten() {
            if let Some(c) = visit(w, graph, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(v.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph.keys().find_map(|v| visit(v, graph, &mut Vec::new(), &mut done))
}

/// Module docs that open with "Stage N" must agree with the table.
#[test]
fn module_docs_name_their_stage() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let lib = fs::read_to_string(src.join("lib.rs")).expect("read lib.rs");
    let stage = stages(&lib).expect("the stage table");
    let mut wrong = Vec::new();
    for (module, &n) in &stage {
        let file = [src.join(format!("{module}.rs")), src.join(module).join("mod.rs")]
            .into_iter()
            .find(|p| p.exists())
            .expect("a module file");
        let text = fs::read_to_string(&file).expect("read a module");
        let first = text.lines().next().unwrap_or_default();
        if let Some(rest) = first.strip_prefix("//! Stage ") {
            let said: String = rest.chars().take_while(char::is_ascii_digit).collect();
            if !said.is_empty() && said.parse::<u32>().ok() != Some(n) {
                wrong.push(format!("{}: says stage {said}, the table says {n}", file.display()));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Every `stage N: [`module`]` (or `[`crate::module`]`) cited in a doc comment of `src/`,
/// with the file: the citations that the stage table must agree with.
fn cited_stages(src: &Path) -> Vec<(PathBuf, u32, String)> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut out = Vec::new();
    for file in files {
        let text = fs::read_to_string(&file).expect("read a source file");
        // Doc comments joined, so that a citation may wrap over two lines.
        let docs: String = text
            .lines()
            .filter_map(|l| {
                let l = l.trim_start();
                l.strip_prefix("//!").or_else(|| l.strip_prefix("///"))
            })
            .collect::<Vec<_>>()
            .join(" ");
        let mut rest = docs.as_str();
        while let Some(k) = rest.find("stage ") {
            rest = &rest[k + "stage ".len()..];
            let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
            let Some(after) = rest[digits.len()..].strip_prefix(":") else { continue };
            let Some(link) = after.trim_start().strip_prefix("[`") else { continue };
            let name: String =
                link.trim_start_matches("crate::").chars().take_while(|c| *c != '`').collect();
            if let Ok(n) = digits.parse() {
                out.push((file.clone(), n, name));
            }
        }
    }
    out
}

/// The citations of [`cited_stages`] that disagree with the stage table of `src/lib.rs`.
fn wrong_citations(src: &Path) -> Vec<String> {
    let lib = fs::read_to_string(src.join("lib.rs")).expect("read lib.rs");
    let stage = stages(&lib).expect("the stage table");
    cited_stages(src)
        .iter()
        .filter(|(_, n, module)| stage.get(module.as_str()) != Some(n))
        .map(|(file, n, module)| {
            let table = stage.get(module.as_str());
            format!("{}: cites stage {n} for `{module}`, the table says {table:?}", file.display())
        })
        .collect()
}

#[test]
fn cited_stages_agree_with_the_table() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let cited = cited_stages(&src);
    assert!(cited.len() >= 10, "the citations of error.rs are found: {cited:?}");
    let wrong = wrong_citations(&src);
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn a_wrong_stage_citation_is_caught() {
    let dir = scratch("citation", "/// Failed (stage 1: [`crate::early`]).\npub struct A;\n");
    let wrong = wrong_citations(&dir);
    assert_eq!(wrong.len(), 1, "{wrong:?}");
    assert!(wrong[0].contains("cites stage 1 for `early`, the table says Some(0)"), "{wrong:?}");
}

#[test]
fn modules_import_only_earlier_stages() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let errors = violations(&src);
    assert!(
        errors.is_empty(),
        "the module layout breaks the pipeline order:\n{}",
        errors.join("\n")
    );
}

/// A scratch crate: `lib.rs` with a two-stage table, `early.rs` and `late.rs`.
fn scratch(name: &str, early: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mlpg-architecture-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(dir.join("late")).expect("scratch dir");
    let lib = "//! | stage | module | what |\n//! |---|---|---|\n//! | 0 | [`early`] | a |\n//! | 1 | [`late`] | b |\npub mod early;\npub mod late;\n";
    fs::write(dir.join("lib.rs"), lib).expect("write");
    fs::write(dir.join("early.rs"), early).expect("write");
    fs::write(dir.join("late/mod.rs"), "use crate::early::A;\npub struct B;\n").expect("write");
    dir
}

#[test]
fn a_backward_import_is_caught() {
    let ok = scratch(
        "ok",
        "pub struct A;\n/// Links to [`crate::late::B`] are no import.\n#[cfg(test)]\nmod tests {\n    use crate::late::B;\n}\n",
    );
    assert_eq!(violations(&ok), Vec::<String>::new());
    let bad = scratch("bad", "use crate::{late::B};\npub struct A;\n");
    let errors = violations(&bad);
    assert!(
        errors.iter().any(|e| e.contains("`early` (stage 0) imports `late` (stage 1)")),
        "{errors:?}"
    );
    assert!(errors.iter().any(|e| e.starts_with("import cycle")), "{errors:?}");
    let _ = fs::remove_dir_all(ok);
    let _ = fs::remove_dir_all(bad);
}

#[test]
fn a_module_outside_the_table_is_caught() {
    let dir = scratch("missing", "pub struct A;\n");
    let lib = fs::read_to_string(dir.join("lib.rs")).expect("read") + "pub mod extra;\n";
    fs::write(dir.join("lib.rs"), lib).expect("write");
    fs::write(dir.join("extra.rs"), "").expect("write");
    assert_eq!(violations(&dir), vec!["module `extra` is not in lib.rs's stage table".to_string()]);
    let _ = fs::remove_dir_all(dir);
}

/// The modules whose code names nothing of the crate outside itself: pure algorithms that
/// bodies, matrices and problem files sit on, not under.
const PURE: &[&str] = &["lcp"];

/// The `crate::` paths out of `module` (its file or folder under `src`) other than into
/// itself, one line each.
fn impurities(src: &Path, module: &str) -> Vec<String> {
    let mut files = Vec::new();
    let file = src.join(format!("{module}.rs"));
    if file.exists() {
        files.push(file);
    }
    if src.join(module).is_dir() {
        rust_files(&src.join(module), &mut files);
    }
    let mut out = Vec::new();
    for file in files {
        let text = fs::read_to_string(&file).expect("read a source file");
        for target in references(&code(&text)) {
            if target != module {
                out.push(format!(
                    "{}: the pure module `{module}` imports `{target}`",
                    file.display()
                ));
            }
        }
    }
    out
}

#[test]
fn pure_modules_import_nothing_else_of_the_crate() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    for module in PURE {
        let wrong = impurities(&src, module);
        assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    }
}

#[test]
fn an_impure_import_is_caught() {
    let dir = scratch("pure", "pub struct A;\n");
    fs::write(dir.join("late/inner.rs"), "use crate::late::B;\nuse crate::early::A;\n")
        .expect("write");
    let wrong = impurities(&dir, "late");
    // `late/mod.rs` and `late/inner.rs` both name `early`; `crate::late` is the module itself.
    assert_eq!(wrong.len(), 2, "{wrong:?}");
    assert!(wrong.iter().all(|w| w.ends_with("imports `early`")), "{wrong:?}");
}
