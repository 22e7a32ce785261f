//! The user guide (`docs/guide/`) against the code: its problem-file reference has an entry
//! for every key the parser accepts, and the book's pages and links hold together.
//!
//! **Keys.** Read from the source of the raw problem-file structs (`src/problem/file.rs`):
//! every `Deserialize` struct with named fields, each field under its serde name and every
//! `alias` (a struct read through `try_from` is skipped: its source struct holds the keys). Each
//! struct is mapped to the reference page of its table in [`PAGES`]; a struct without a page,
//! or a page entry for a struct that no longer exists, fails the test, so the list cannot
//! drift from the code. An *entry* is the key in backticks in the first cell of a Markdown
//! table row of that page (`` | `friction` | … ``; `` `output.every` `` counts for `output` and
//! `every`, `` `[[nodes.refine]]` `` for `nodes` and `refine`).

use serde_json::Value;
use std::collections::BTreeSet;
use std::path::Path;

/// The raw structs' source.
const RAW_STRUCTS: &str = include_str!("../src/problem/file.rs");

/// The reference pages' folder, from the repository's root.
const REFERENCE: &str = "docs/guide/src/reference";

/// Raw struct → (the table it reads, its reference page under [`REFERENCE`]).
const PAGES: &[(&str, &str, &str)] = &[
    ("ProblemFile", "the top level", "problem-file.md"),
    ("GeometryTable", "[geometry]", "geometry.md"),
    ("CurveFile", "[geometry] curves", "geometry.md"),
    ("HoleTable", "[geometry] holes", "geometry.md"),
    ("NodesFile", "[nodes]", "nodes.md"),
    ("RefineFile", "[[nodes.refine]]", "nodes.md"),
    ("MaterialFile", "[material]", "material.md"),
    ("DiscretisationFile", "[discretisation]", "discretisation.md"),
    ("BoundaryFile", "[[boundary]]", "boundary.md"),
    ("ComponentsFile", "displacement/traction components", "boundary.md"),
    ("ContactFile", "[contact] / [[contact]]", "contact.md"),
    ("ObstacleFile", "[[obstacle]]", "obstacle.md"),
    ("StepFile", "[[step]]", "step.md"),
    ("StepBoundaryFile", "[[step]] boundary", "step.md"),
    ("BodyFile", "[[body]]", "bodies.md"),
    ("AdaptiveFile", "[refinement]", "refinement.md"),
    ("DynamicsFile", "[dynamics]", "dynamics.md"),
    ("DynamicsOutputFile", "[dynamics.output]", "dynamics.md"),
    ("OutputFile", "[output]", "output.md"),
];

/// A key of a raw struct: its serde name and aliases.
#[derive(Debug, PartialEq)]
struct Key {
    name: String,
    aliases: Vec<String>,
}

/// The `Deserialize` structs with named fields of `source` and their keys, in source order.
fn raw_structs(source: &str) -> Vec<(String, Vec<Key>)> {
    let mut structs = Vec::new();
    let mut attributes = String::new();
    let mut lines = source.lines();
    while let Some(line) = lines.next() {
        let line = line.trim();
        if line.starts_with("#[") || (!attributes.is_empty() && !balanced(&attributes)) {
            attributes.push_str(line);
            continue;
        }
        if line.starts_with("///") || line.starts_with("//") {
            continue;
        }
        let name = line.strip_prefix("pub struct ").and_then(|rest| rest.strip_suffix(" {"));
        if let Some(name) = name {
            let read = attributes.contains("Deserialize") && !attributes.contains("try_from");
            if read {
                assert_supported(name, &attributes);
                structs.push((name.to_string(), fields(&mut lines)));
            }
        }
        attributes.clear();
    }
    structs
}

/// Whether `text` has `word` as a whole identifier.
fn has_word(text: &str, word: &str) -> bool {
    text.split(|c: char| !(c.is_alphanumeric() || c == '_')).any(|w| w == word)
}

/// Whether the brackets of an attribute closed.
fn balanced(text: &str) -> bool {
    text.matches('[').count() == text.matches(']').count()
}

/// Refuses struct attributes that would change the keys in ways [`fields`] does not read.
fn assert_supported(name: &str, attributes: &str) {
    for unsupported in ["rename_all", "flatten", "transparent"] {
        assert!(
            !has_word(attributes, unsupported),
            "{name}: `{unsupported}` is not read by this test's key extraction: extend it"
        );
    }
}

/// The fields of a struct body (up to its closing `}`) as keys.
fn fields<'a>(lines: &mut impl Iterator<Item = &'a str>) -> Vec<Key> {
    let mut keys = Vec::new();
    let mut serde = String::new();
    for line in lines.by_ref() {
        let line = line.trim();
        if line == "}" {
            break;
        }
        if line.starts_with("///") {
            continue;
        }
        if line.starts_with("#[") || (!serde.is_empty() && !balanced(&serde)) {
            serde.push_str(line);
            continue;
        }
        let field = line.strip_prefix("pub ").unwrap_or(line);
        if let Some((ident, _)) = field.split_once(':') {
            assert!(!has_word(&serde, "flatten"), "{ident}: `flatten` is not read by this test");
            if !has_word(&serde, "skip") && !has_word(&serde, "skip_deserializing") {
                let name = quoted(&serde, "rename").pop().unwrap_or_else(|| ident.to_string());
                keys.push(Key { name, aliases: quoted(&serde, "alias") });
            }
            serde.clear();
        }
    }
    keys
}

/// Every `attribute = "value"` value in `text`.
fn quoted(text: &str, attribute: &str) -> Vec<String> {
    let pattern = format!("{attribute} = \"");
    text.match_indices(&pattern)
        .filter(|(at, _)| !text[..*at].ends_with('_')) // `rename_all` is not `rename`
        .filter_map(|(at, _)| {
            let rest = &text[at + pattern.len()..];
            rest.split_once('"').map(|(value, _)| value.to_string())
        })
        .collect()
}

/// The keys a reference page has entries for: the backticked words in the first cell of its
/// table rows, split at dots and stripped of TOML's table brackets.
fn entries(page: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for row in page.lines().filter(|l| l.starts_with('|') && !l.starts_with("|---")) {
        let first = row.split('|').nth(1).unwrap_or("");
        for token in first.split('`').skip(1).step_by(2) {
            let token = token.trim_matches(|c| c == '[' || c == ']');
            found.extend(token.split('.').map(str::to_string));
        }
    }
    found
}

fn read(path: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(root.join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The keys of `structs` without an entry on their reference page, as messages.
fn undocumented(structs: &[(String, Vec<Key>)]) -> Vec<String> {
    let mut missing = Vec::new();
    for (name, keys) in structs {
        let Some((_, table, page)) = PAGES.iter().find(|(s, ..)| s == name) else {
            missing.push(format!("struct {name} (src/problem/file.rs) has no page in PAGES"));
            continue;
        };
        let path = format!("{REFERENCE}/{page}");
        let documented = entries(&read(&path));
        for key in keys {
            for word in std::iter::once(&key.name).chain(&key.aliases) {
                if !documented.contains(word) {
                    missing.push(format!("`{word}` of {table} ({name}) has no entry in {path}"));
                }
            }
        }
    }
    missing
}

#[test]
fn every_problem_file_key_has_an_entry_in_the_guide() {
    let structs = raw_structs(RAW_STRUCTS);
    let mut missing = undocumented(&structs);
    for (name, ..) in PAGES {
        if !structs.iter().any(|(s, _)| s == name) {
            missing.push(format!("PAGES names {name}, which src/problem/file.rs no longer has"));
        }
    }
    let keys: usize = structs.iter().map(|(_, k)| k.len()).sum();
    assert!(keys >= 80, "only {keys} keys found: the extraction broke");
    assert!(missing.is_empty(), "the guide's reference lacks:\n{}", missing.join("\n"));
}

#[test]
fn key_extraction_reads_names_aliases_renames_and_skips() {
    let source = r#"
/// A table.
#[derive(Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Table {
    /// Plain.
    pub plain: f64,
    /// With an alias, over two lines.
    #[serde(
        default,
        alias = "centre",
    )]
    pub center: Option<[f64; 2]>,
    #[serde(rename = "outer")]
    pub inner: bool,
    #[serde(skip_deserializing)]
    pub hidden: u8,
}
#[derive(Deserialize)]
#[serde(try_from = "Table")]
pub struct Converted {
    pub not_a_key: f64,
}
#[derive(Serialize)]
pub struct Written {
    pub neither: f64,
}
"#;
    let structs = raw_structs(source);
    let key = |name: &str, aliases: &[&str]| Key {
        name: name.into(),
        aliases: aliases.iter().map(|a| a.to_string()).collect(),
    };
    let expected = vec![key("plain", &[]), key("center", &["centre"]), key("outer", &[])];
    assert_eq!(structs, vec![("Table".to_string(), expected)]);
}

#[test]
fn a_page_without_an_entry_is_reported() {
    let structs = vec![(
        "OutputFile".to_string(),
        vec![Key { name: "no_such_key".into(), aliases: Vec::new() }],
    )];
    let missing = undocumented(&structs);
    assert_eq!(missing.len(), 1, "{missing:?}");
    assert!(missing[0].contains("`no_such_key` of [output]"), "{}", missing[0]);
}

/// The guide's pages: every Markdown file under `docs/guide/src/`, relative to it.
fn guide_pages() -> Vec<String> {
    fn walk(dir: &Path, base: &Path, out: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).unwrap().map(Result::unwrap) {
            let path = entry.path();
            if path.is_dir() {
                walk(&path, base, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path.strip_prefix(base).unwrap().to_string_lossy().replace('\\', "/"));
            }
        }
    }
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/guide/src");
    let mut pages = Vec::new();
    walk(&base, &base, &mut pages);
    pages.sort();
    pages
}

/// The targets of the inline links `[text](target)` of a Markdown page, outside code.
fn links(page: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut fenced = false;
    for line in page.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        if fenced || line.starts_with("    ") {
            continue;
        }
        // Outside inline code spans (the even pieces between backticks).
        for text in line.split('`').step_by(2) {
            for (at, _) in text.match_indices("](") {
                if let Some((target, _)) = text[at + 2..].split_once(')') {
                    found.push(target.to_string());
                }
            }
        }
    }
    found
}

/// GitHub's (and mdBook's) anchor of a heading: lower case, punctuation dropped, spaces to `-`.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The links of the Markdown file `path` (from the repository's root) that do not resolve: a
/// missing file, or a `#fragment` that is no heading of the Markdown file it points into.
fn broken_links(path: &str) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = root.join(path).parent().unwrap().to_path_buf();
    let mut broken = Vec::new();
    for target in links(&read(path)) {
        if target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        let (file, fragment) = target.split_once('#').unwrap_or((&target, ""));
        let file = if file.is_empty() { root.join(path) } else { dir.join(file) };
        if !file.exists() {
            broken.push(format!("{path}: {target} (no such file)"));
            continue;
        }
        let is_markdown = file.extension().is_some_and(|e| e == "md");
        if !fragment.is_empty() && is_markdown {
            let text = std::fs::read_to_string(&file).unwrap();
            let headings: Vec<String> = text
                .lines()
                .filter_map(|l| l.strip_prefix('#'))
                .map(|h| anchor(h.trim_start_matches('#')))
                .collect();
            if !headings.iter().any(|h| h == fragment) {
                broken.push(format!("{path}: {target} (no such heading)"));
            }
        }
    }
    broken
}

#[test]
fn every_guide_page_is_in_the_summary_and_every_link_resolves() {
    let summary = read("docs/guide/src/SUMMARY.md");
    let listed: BTreeSet<String> = links(&summary).into_iter().collect();
    let mut problems = Vec::new();
    for page in guide_pages() {
        if page != "SUMMARY.md" && !listed.contains(&page) {
            problems.push(format!("{page} is not in SUMMARY.md"));
        }
        problems.extend(broken_links(&format!("docs/guide/src/{page}")));
    }
    problems.extend(broken_links("README.md"));
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_readme_is_a_front_page() {
    let readme = read("README.md");
    let lines = readme.lines().count();
    assert!(lines <= 200, "README.md has {lines} lines: keep it a front page (≤ 200)");
    for command in [
        "cargo run --release -- problems/beam_on_foundation.toml --out out/beam",
        "cargo test --release",
        "cargo install --path .",
        "target/release/mlpg-contact",
        "docs/guide/",
    ] {
        assert!(readme.contains(command), "README.md does not mention `{command}`");
    }
}

#[test]
fn broken_links_are_reported() {
    assert_eq!(
        anchor(" The tangent and the stick/slip coordinate"),
        "the-tangent-and-the-stickslip-coordinate"
    );
    assert_eq!(links("see [a](b.md#c) and `[x](y)`\n    [code](z)\n"), vec!["b.md#c"]);
}

/// The fenced code blocks of `page` whose info string is `info`, as written.
fn code_blocks(page: &str, info: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in page.lines() {
        match (&mut current, line.trim_end()) {
            (None, fence) if fence == format!("```{info}") => current = Some(String::new()),
            (Some(block), "```") => {
                blocks.push(std::mem::take(block));
                current = None;
            }
            (Some(block), _) => {
                block.push_str(line);
                block.push('\n');
            }
            (None, _) => {}
        }
    }
    blocks
}

#[test]
fn the_guides_rust_examples_are_the_doctested_ones() {
    let doctested = code_blocks(&read("docs/guide/doctests.md"), "rust");
    let mut problems = Vec::new();
    let mut found = 0;
    for page in guide_pages() {
        let text = read(&format!("docs/guide/src/{page}"));
        for block in code_blocks(&text, "rust,ignore") {
            found += 1;
            if !doctested.contains(&block) {
                problems
                    .push(format!("{page}: a rust,ignore block is not in doctests.md:\n{block}"));
            }
        }
        if !code_blocks(&text, "rust").is_empty() {
            problems
                .push(format!("{page}: a plain rust block (mdbook test cannot link the crate)"));
        }
    }
    assert!(found >= 1, "no rust,ignore block found: the extraction broke");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// Both spellings of the centre of a circle are accepted wherever one is: every key named
/// `centre` or `center` in the raw structs has the other as its alias.
#[test]
fn centre_and_center_are_accepted_wherever_one_is() {
    let mut seen = 0;
    for (name, keys) in raw_structs(RAW_STRUCTS) {
        for key in keys {
            let other = match key.name.as_str() {
                "centre" => "center",
                "center" => "centre",
                _ => continue,
            };
            seen += 1;
            assert!(
                key.aliases.iter().any(|a| a == other),
                "{name}.{}: no alias {other}",
                key.name
            );
        }
    }
    assert!(seen >= 4, "only {seen} centre keys found (geometry, holes, curves, obstacles)");
}

/// `mdbook test` (rustdoc) compiles every untagged fenced block and every indented code block
/// as Rust: each page fences its code and names its language (`toml`, `console`, `text`, …).
#[test]
fn every_code_block_of_the_guide_names_its_language() {
    let mut problems = Vec::new();
    for page in guide_pages() {
        let text = read(&format!("docs/guide/src/{page}"));
        let (mut fenced, mut previous_blank) = (false, true);
        for (k, line) in text.lines().enumerate() {
            let opening = !fenced && line.trim_start().starts_with("```");
            if opening && line.trim() == "```" {
                problems.push(format!("{page}:{}: a fence without a language", k + 1));
            }
            if !fenced && line.starts_with("    ") && previous_blank {
                problems.push(format!("{page}:{}: an indented code block", k + 1));
            }
            if line.trim_start().starts_with("```") {
                fenced = !fenced;
            }
            previous_blank = line.trim().is_empty();
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The sources of the string values the raw structs accept (their `rename_all = "snake_case"`
/// enums).
const VALUE_SOURCES: &[&str] = &[
    include_str!("../src/problem/file.rs"),
    include_str!("../src/problem/discretisation.rs"),
    include_str!("../src/problem/contact.rs"),
    include_str!("../src/problem/refine.rs"),
    include_str!("../src/material.rs"),
];

/// Enum of string values → the reference page that lists them.
const VALUE_PAGES: &[(&str, &str)] = &[
    ("Preset", "discretisation.md"),
    ("Method", "discretisation.md"),
    ("Basis", "discretisation.md"),
    ("Precision", "discretisation.md"),
    ("ContactSolver", "contact.md"),
    ("Condensation", "contact.md"),
    ("Indicator", "refinement.md"),
    ("PlaneState", "material.md"),
    ("Turn", "geometry.md"),
    ("NodesFrom", "nodes.md"),
    ("LayoutKind", "nodes.md"),
    ("GeometryKind", "geometry.md"),
    ("HoleKind", "geometry.md"),
];

/// The unit-variant enums of `source` read with `rename_all = "snake_case"`, with their values.
fn value_enums(source: &str) -> Vec<(String, Vec<String>)> {
    let mut enums = Vec::new();
    let mut snake = false;
    let mut lines = source.lines().map(str::trim);
    while let Some(line) = lines.next() {
        if line.starts_with("#[serde(") {
            snake = line.contains("rename_all = \"snake_case\"") && !line.contains("tag");
            continue;
        }
        let Some(name) = line.strip_prefix("pub enum ").and_then(|r| r.strip_suffix(" {")) else {
            if !line.starts_with("#[") && !line.starts_with("//") {
                snake = false;
            }
            continue;
        };
        if snake {
            let variants = lines
                .by_ref()
                .take_while(|l| *l != "}")
                .filter(|l| l.chars().next().is_some_and(char::is_uppercase))
                .map(|l| snake_case(l.trim_end_matches(',')))
                .collect();
            enums.push((name.to_string(), variants));
        }
        snake = false;
    }
    enums
}

/// `StressState` → `stress_state`.
fn snake_case(camel: &str) -> String {
    let mut out = String::new();
    for (k, c) in camel.chars().enumerate() {
        if c.is_uppercase() && k > 0 {
            out.push('_');
        }
        out.extend(c.to_lowercase());
    }
    out
}

/// Every string value a raw struct's key accepts is named, quoted, on its reference page; every
/// enum type of a raw struct's field has a page in [`VALUE_PAGES`].
#[test]
fn every_string_value_has_an_entry_in_the_guide() {
    let enums: Vec<_> = VALUE_SOURCES.iter().flat_map(|s| value_enums(s)).collect();
    let mut missing = Vec::new();
    for (name, page) in VALUE_PAGES {
        let Some((_, values)) = enums.iter().find(|(e, _)| e == name) else {
            missing.push(format!("VALUE_PAGES names {name}, which the sources no longer have"));
            continue;
        };
        let path = format!("{REFERENCE}/{page}");
        let text = read(&path);
        for value in values {
            if !text.contains(&format!("\"{value}\"")) {
                missing.push(format!("\"{value}\" ({name}) is not named in {path}"));
            }
        }
    }
    let field_types = RAW_STRUCTS.lines().filter_map(|l| l.trim().strip_prefix("pub "));
    for (name, _) in &enums {
        let used = field_types.clone().any(|f| f.contains(&format!("<{name}>")))
            || field_types.clone().any(|f| f.contains(&format!("::{name}>")))
            || field_types.clone().any(|f| f.ends_with(&format!(": {name},")));
        if used && !VALUE_PAGES.iter().any(|(e, _)| e == name) {
            missing.push(format!("enum {name} is read by a raw struct but has no page"));
        }
    }
    assert!(enums.len() >= 13, "only {} enums found: the extraction broke", enums.len());
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

// The JSON Schema of the problem file (`mlpg-contact schema`, `problem::schema`): its tables'
// keys are the raw structs' keys, it accepts every shipped problem file and refuses an unknown
// key. The validator below reads the subset of JSON Schema the schema uses.

/// The errors of `value` against `schema` (`root` resolves `$ref`s), each with its key path.
fn schema_errors(schema: &Value, root: &Value, value: &Value, path: &str) -> Vec<String> {
    if let Some(reference) = schema["$ref"].as_str() {
        let name = reference.trim_start_matches("#/$defs/");
        return schema_errors(&root["$defs"][name], root, value, path);
    }
    if let Some(branches) = schema["anyOf"].as_array() {
        let fits = branches.iter().any(|b| schema_errors(b, root, value, path).is_empty());
        return if fits { Vec::new() } else { vec![format!("{path}: fits no alternative")] };
    }
    let fits_type = match schema["type"].as_str() {
        Some("object") => value.is_object(),
        Some("array") => value.is_array(),
        Some("string") => value.is_string(),
        Some("number") => value.is_number(),
        Some("integer") => value.is_u64(),
        Some("boolean") => value.is_boolean(),
        _ => true,
    };
    if !fits_type {
        return vec![format!("{path}: not of type {}", schema["type"])];
    }
    if let Some(values) = schema["enum"].as_array().filter(|v| !v.contains(value)) {
        return vec![format!("{path}: {value} is none of {values:?}")];
    }
    let mut errors = Vec::new();
    if let Some(object) = value.as_object() {
        for (key, item) in object {
            match schema["properties"].get(key) {
                Some(s) => errors.extend(schema_errors(s, root, item, &format!("{path}.{key}"))),
                None if schema["additionalProperties"] == false => {
                    errors.push(format!("{path}: unknown key `{key}`"));
                }
                None => {}
            }
        }
        let required = schema["required"].as_array().into_iter().flatten();
        for key in required.filter_map(Value::as_str).filter(|k| !object.contains_key(*k)) {
            errors.push(format!("{path}: `{key}` missing"));
        }
    }
    if let Some(items) = value.as_array() {
        let count = items.len() as u64;
        if schema["minItems"].as_u64().is_some_and(|n| count < n)
            || schema["maxItems"].as_u64().is_some_and(|n| count > n)
        {
            errors.push(format!("{path}: {count} items"));
        }
        for (k, item) in items.iter().enumerate() {
            errors.extend(schema_errors(&schema["items"], root, item, &format!("{path}[{k}]")));
        }
    }
    errors
}

/// Every shipped problem file (`problems/`, `problems/large/`) as JSON, with its path.
fn shipped_problems_as_json() -> Vec<(String, Value)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["problems", "problems/large"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap().map(Result::unwrap) {
            let path = entry.path();
            if path.extension().is_some_and(|e| e == "toml") {
                let text = std::fs::read_to_string(&path).unwrap();
                let json: Value = toml::from_str(&text).unwrap();
                files.push((path.display().to_string(), json));
            }
        }
    }
    files
}

#[test]
fn the_schema_accepts_every_shipped_problem_and_refuses_an_unknown_key() {
    let schema = mlpg_contact::problem::schema::problem_file();
    let files = shipped_problems_as_json();
    assert!(files.len() >= 25, "only {} problem files found", files.len());
    for (path, json) in &files {
        let errors = schema_errors(&schema, &schema, json, "");
        assert!(errors.is_empty(), "{path}: {}", errors.join("; "));
    }
    let (_, mut beam) =
        files.into_iter().find(|(p, _)| p.ends_with("beam_on_foundation.toml")).unwrap();
    beam["material"]["colour"] = Value::from("blue");
    let errors = schema_errors(&schema, &schema, &beam, "");
    assert_eq!(errors, vec![".material: unknown key `colour`"]);
    beam["material"].as_object_mut().unwrap().remove("colour");
    beam["nodes"]["spacing"] = Value::from("fine");
    assert_eq!(
        schema_errors(&schema, &schema, &beam, ""),
        vec![".nodes.spacing: not of type \"number\""]
    );
}

#[test]
fn the_schemas_tables_have_the_raw_structs_keys() {
    let schema = mlpg_contact::problem::schema::problem_file();
    let mut problems = Vec::new();
    for (name, keys) in raw_structs(RAW_STRUCTS) {
        let table = if name == "ProblemFile" { &schema } else { &schema["$defs"][&name] };
        let Some(properties) = table["properties"].as_object() else {
            problems.push(format!("the schema has no table for {name}"));
            continue;
        };
        let expected: BTreeSet<&str> = keys
            .iter()
            .flat_map(|k| std::iter::once(&k.name).chain(&k.aliases))
            .map(String::as_str)
            .collect();
        let found: BTreeSet<&str> = properties.keys().map(String::as_str).collect();
        if expected != found {
            problems.push(format!("{name}: the struct has {expected:?}, the schema {found:?}"));
        }
        if table["additionalProperties"] != false {
            problems.push(format!("{name}: the schema allows unknown keys"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_schema_command_prints_the_schema() {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_mlpg-contact"))
        .arg("schema")
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let printed: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(printed, mlpg_contact::problem::schema::problem_file());
}
