//! Validation suite: one self-contained file per case under `tests/validation/`.
mod validation {
    mod common;
    // Linear field reproduced to round-off, structured and jittered nodes.
    mod patch_test;
}
