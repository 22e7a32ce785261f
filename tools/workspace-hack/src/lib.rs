//! Feature alignment of the workspace's two builds; this crate has no code.
//!
//! `cargo test --release` resolves the root package with its dev-dependencies; `pip install .`
//! (maturin) resolves the Python member alone, with pyo3 and numpy. Cargo unifies a crate's
//! features within one resolution only, so the two builds asked for different features of
//! serde, syn, plotters and a few more, and the wheel's build compiled serde's dependants,
//! plotters and mlpg-contact itself a second time in the same target directory. Both now depend
//! on this crate, which asks for the union of those features (the approach of `cargo hakari`'s
//! workspace-hack crates), so the second build reuses the first one's artefacts.
//!
//! When a dependency changes, compare the two builds' unit graphs:
//! `python3 scripts/feature-alignment.py` lists every shared crate built with different
//! features or profiles (none when aligned); add what it names here.
