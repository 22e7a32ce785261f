//! The command line of the studies and benchmarks in `examples/studies/`, one parser for all.
//!
//! Each study declares its own `#[derive(clap::Parser)]` struct, flattens the groups below that
//! it needs (`#[command(flatten)]`), and reads its arguments with [`parse`], which sets the
//! study's own defaults (shown by `--help`). Switches that used to be environment variables
//! are flags now; [`refuse_retired_env`] stops a study when one of those variables is still
//! set, instead of silently ignoring it.

// Each study uses only some of the groups.
#![allow(dead_code)]

use clap::{Args, Parser};

/// A ladder of node spacings `coarsest, coarsest/2, …` down to `--finest`.
#[derive(Args, Debug)]
pub struct Ladder {
    /// Finest node spacing h of the ladder (each level halves the previous one)
    #[arg(long, value_name = "H", value_parser = positive)]
    pub finest: f64,
}

/// `--only k`: one variant of the study's list.
#[derive(Args, Debug)]
pub struct Only {
    /// Run only variant K of the study's list (1-based; default: all)
    #[arg(long, value_name = "K", value_parser = one_based)]
    pub only: Option<usize>,
}

impl Only {
    /// Whether variant `k` (0-based) runs.
    pub fn runs(&self, k: usize) -> bool {
        self.only.is_none_or(|o| o == k + 1)
    }
}

/// Discretisation parameters that override the problem's values.
#[derive(Args, Debug)]
pub struct Operator {
    /// Stabilisation blend β in [0, 1], overriding the problem's `discretisation.beta` (0: the
    /// paper's mixed method, 1: direct MLS strains at the cell boundaries, method.md §3.9)
    #[arg(long, value_name = "BETA", value_parser = beta)]
    pub beta: Option<f64>,
    /// Support factor α_s in [1, 6] (support radius α_s h), overriding the problem's
    /// `discretisation.support_factor`
    #[arg(long, value_name = "ALPHA", value_parser = support_factor)]
    pub support_factor: Option<f64>,
}

/// Parses the command line into `T`. `defaults` are `(argument id, value)` pairs (the id is
/// the field's name, e.g. `"finest"`) that set this study's defaults for arguments of the
/// shared groups; `--help` shows them.
pub fn parse<T: Parser>(defaults: &[(&'static str, &'static str)]) -> T {
    let mut command = T::command();
    for &(id, value) in defaults {
        command = command.mut_arg(id, |arg| arg.default_value(value).required(false));
    }
    let matches = command.clone().get_matches();
    T::from_arg_matches(&matches).unwrap_or_else(|e| e.format(&mut command).exit())
}

/// Exits with an error naming the flag when one of the environment variables `retired`
/// (`(variable, flag)` pairs) is set: those switches are flags now.
pub fn refuse_retired_env(retired: &[(&str, &str)]) {
    let set: Vec<String> = retired
        .iter()
        .filter(|(var, _)| std::env::var_os(var).is_some())
        .map(|(var, flag)| format!("{var} is no longer read; pass {flag} instead"))
        .collect();
    if !set.is_empty() {
        eprintln!("error: {}", set.join("; "));
        std::process::exit(2);
    }
}

/// A positive number.
pub fn positive(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err("expected a positive number".into()),
    }
}

/// A 1-based position in a list.
pub fn one_based(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(k) if k >= 1 => Ok(k),
        _ => Err("expected a variant number 1, 2, …".into()),
    }
}

/// A blend `β ∈ [0, 1]`.
pub fn beta(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err("expected a number in [0, 1]".into()),
    }
}

/// A support factor `α_s ∈ [1, 6]` (the range the problem files accept).
pub fn support_factor(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if (1.0..=6.0).contains(&v) => Ok(v),
        _ => Err("expected a number in [1, 6]".into()),
    }
}

/// A count written `25000`, `25_000`, `25k` or `1.5M`.
pub fn count(s: &str) -> Result<usize, String> {
    let s = s.trim();
    let (num, mult) = match s.chars().last() {
        Some('k' | 'K') => (&s[..s.len() - 1], 1e3),
        Some('m' | 'M') => (&s[..s.len() - 1], 1e6),
        _ => (s, 1.0),
    };
    match num.replace('_', "").parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok((v * mult).round() as usize),
        _ => Err("expected a count such as 25000, 25k or 1.5M".into()),
    }
}
