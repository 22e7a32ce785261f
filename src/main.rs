//! Command-line interface (in progress).
fn main() {}
