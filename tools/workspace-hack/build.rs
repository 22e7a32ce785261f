//! Empty: the build-dependencies exist only for their features (see src/lib.rs).
fn main() {}
