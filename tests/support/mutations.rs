//! The number mutations shared by the CI mutation campaign (`tests/mutation_campaign.rs`)
//! and the opt-in fault campaign (`examples/studies/fault_campaign.rs`): the replacement
//! values and the scanner that finds the numbers of a problem file.

/// What a number is replaced by.
pub const REPLACEMENTS: [&str; 14] = [
    "nan",
    "inf",
    "-inf",
    "0",
    "0.0",
    "-1",
    "1e300",
    "-1e300",
    "1e-300",
    "1e100",
    "\"abc\"",
    "[1.0, 2.0, 3.0]",
    "true",
    "{}",
];

/// Byte ranges of the numbers in `text` (outside strings and comments).
pub fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let (mut i, mut in_string, mut in_comment) = (0, false, false);
    while i < b.len() {
        let c = b[i];
        if in_comment {
            in_comment = c != b'\n';
        } else if in_string {
            in_string = c != b'"';
        } else if c == b'#' {
            in_comment = true;
        } else if c == b'"' {
            in_string = true;
        } else if c.is_ascii_digit() || (c == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let prev = if i == 0 { b' ' } else { b[i - 1] };
            if !(prev.is_ascii_alphanumeric() || prev == b'_') {
                let start = i;
                i += 1;
                // Digits, '.', 'e'/'E', and a sign only right after an exponent mark.
                let continues = |i: usize| {
                    let c = b[i];
                    c.is_ascii_digit()
                        || b"._eE".contains(&c)
                        || (b"+-".contains(&c) && b"eE".contains(&b[i - 1]))
                };
                while i < b.len() && continues(i) {
                    i += 1;
                }
                out.push((start, i));
                continue;
            }
        }
        i += 1;
    }
    out
}
