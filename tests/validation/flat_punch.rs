//! A flat rigid punch pressed into an elastic block, plane strain (`problems/flat_punch.toml`):
//! the punch is a polyline obstacle of half-width `b = 0.1` whose two corners are rounded to
//! `r = 0.005`; it moves down by `δ = 0.01` (`[[step]] obstacle_displacement`) onto the top of
//! the half block `[0, 2] × [−2, 0]` (roller on the symmetry axis, bottom clamped).
//! Half-space solution for a flat frictionless punch of half-width `a` (Johnson, *Contact
//! Mechanics* (1985), §2.8, eq. 2.64 without tilt): `p(x) = P / (π √(a² − x²))`, `P` the
//! force per unit length of the whole punch.
//!
//! Measured: `P = −2 F_y`, `F` the resultant of the contact forces on the half block; `a` is
//! the half-width of the contact zone, taken as the punch's half-width `b`: the rounded
//! corners carry the contact a little onto their arcs, between `b − r` and `b` (the last
//! closed candidate and the first open one bracket it, checked). The pressure of each closed
//! candidate (force / owned segment) is compared with `p(x)` for `|x| ≤ 0.8 a` (the edges are
//! singular for the sharp punch and only capped by the rounded corners).
//!
//! The block is finite: `a/W = a/H = 0.05`. A clamped base under a layer makes the pressure
//! slightly more uniform than on a half-space; solving on the block `[0, 4] × [−4, 0]` measures
//! that effect (printed, and bounded below).

use super::common::assert_lcp_residuals;
use mlpg_contact::problem::Problem;
use std::f64::consts::PI;

const TOML: &str = include_str!("../../problems/flat_punch.toml");
const HALF_WIDTH: f64 = 0.1;
const CORNER: f64 = 0.005;

fn problem(h: f64, size: f64) -> Problem {
    let text = TOML
        .replace("spacing = 0.003125", &format!("spacing = {h}"))
        .replace("x = [0.0, 2.0]", &format!("x = [0.0, {size}]"))
        .replace("y = [-2.0, 0.0]", &format!("y = [-{size}, 0.0]"));
    Problem::from_toml(&text).unwrap()
}

/// What a run measures.
struct Outcome {
    /// `P`: twice the vertical resultant of the contact forces on the half block.
    load: f64,
    /// The fitted half-width `a`.
    half_width: f64,
    /// `P` from the fitted slope, relative to the measured `P`, minus 1.
    load_fit: f64,
    /// `max |p_c / p(x_c) − 1|` over the closed candidates with `x_c ≤ 0.8 a`.
    profile: f64,
}

fn run(h: f64, size: f64) -> Outcome {
    let label = format!("punch h = {h}, W = {size}");
    let s = mlpg_contact::solve(&problem(h, size)).unwrap();
    let c = s.contact().unwrap();
    assert_lcp_residuals(&label, &c.lcp.residuals, 1e-9);
    assert!(s.equilibrium_error < 1e-8, "{label}: equilibrium {}", s.equilibrium_error);
    assert_eq!(c.onset.closed_intervals, 1, "{label}");
    // The resultant from each candidate's own normal, against the support reactions.
    let mut f = [0.0; 2];
    for (k, &pc) in c.lcp.z.iter().enumerate() {
        let nu = c.candidates.normal(k);
        f = [f[0] + pc * nu[0], f[1] + pc * nu[1]];
    }
    for (axis, (r, fa)) in s.reaction_force.iter().zip(f).enumerate() {
        let balance = r + fa;
        assert!(balance.abs() < 1e-8 * c.total_force, "{label}: balance {axis} {balance}");
    }
    let load = -2.0 * f[1];
    // Least squares 1/p² = α + β x² over the closed candidates with x ≤ 0.8 b: for the
    // half-space α = π² a²/P² and β = −π²/P², so a = √(−α/β) and P = π/√(−β).
    let x = |k: usize| c.candidates.points[k][0];
    let pts: Vec<(f64, f64)> = (0..c.closed.len())
        .filter(|&k| c.closed[k] && x(k) <= 0.8 * HALF_WIDTH)
        .map(|k| (x(k).powi(2), c.pressure[k].powi(-2)))
        .collect();
    assert!(pts.len() >= 5, "{label}: {} closed candidates", pts.len());
    let n = pts.len() as f64;
    let (mx, my) = pts.iter().fold((0.0, 0.0), |s, p| (s.0 + p.0 / n, s.1 + p.1 / n));
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let beta = sxy / sxx;
    let alpha = my - beta * mx;
    let (a, load_fit) = ((-alpha / beta).sqrt(), PI / (-beta).sqrt());
    let exact = |x: f64| load / (PI * (a * a - x * x).sqrt());
    let profile = (0..c.closed.len())
        .filter(|&k| c.closed[k] && x(k) <= 0.8 * a)
        .map(|k| (c.pressure[k] / exact(x(k)) - 1.0).abs())
        .fold(0.0, f64::max);
    // The contact zone ends on the rounded corner: the last closed candidate past b − r − h,
    // the first open one before b + h; the fitted a likewise (to a spacing).
    let last_closed = (0..c.closed.len()).filter(|&k| c.closed[k]).map(x).fold(0.0, f64::max);
    let first_open =
        (0..c.closed.len()).filter(|&k| !c.closed[k]).map(x).fold(f64::INFINITY, f64::min);
    println!(
        "{label:<28} P = {load:.5e}  a_fit = {a:.5}  P_fit/P − 1 = {:+.2e}  contact ends in [{last_closed:.5}, {first_open:.5}]  max |p/exact − 1| (|x| ≤ 0.8a) = {profile:.3e}",
        load_fit / load - 1.0
    );
    assert!(
        last_closed >= HALF_WIDTH - CORNER - h && first_open <= HALF_WIDTH + h,
        "{label}: contact ends between {last_closed} and {first_open}"
    );
    assert!((HALF_WIDTH - CORNER - h..=HALF_WIDTH + h).contains(&a), "{label}: a = {a}");
    Outcome { load, half_width: a, load_fit: load_fit / load - 1.0, profile }
}

// Observed (box spacing h = 0.0125, 0.00625, 0.003125; coarse 0.1; β = 0.5):
// P = 5.2053e-3, 5.2932e-3, 5.3601e-3; a_fit = 0.08906, 0.09495, 0.09713 (the contact ends
// on the rounded corners, between b − r = 0.095 and b = 0.1); P_fit/P − 1 = −7.7e-3,
// +2.2e-3, +2.2e-3; max |p/p(x) − 1| for |x| ≤ 0.8 a: 2.7e-2, 2.9e-3, 2.8e-3. On the block
// twice as large (h = 0.003125): a_fit = 0.09681, profile error 6.2e-4: the finite block
// costs about 0.2 % of the profile. With a = b instead of the fitted a the centre pressure is
// 3.2 % high at every spacing and block size: the rounded corners shorten the contact zone by
// about 3 %, which the formula must be given.
// Bounds: the task's 3 % on the profile at the finest spacing; the slope's load within 1 % of
// the measured one at the two finer spacings (the 1/√(a² − x²) shape, not only its scale).
#[test]
fn flat_punch_matches_the_half_space() {
    let h = [0.0125, 0.00625, 0.003125];
    let out: Vec<Outcome> = h.iter().map(|&hi| run(hi, 2.0)).collect();
    println!("h          P            a_fit     P_fit/P−1   profile(|x|≤0.8a)");
    for (hi, o) in h.iter().zip(&out) {
        println!(
            "{hi:<10} {:.5e}  {:.5}  {:+.2e}  {:.3e}",
            o.load, o.half_width, o.load_fit, o.profile
        );
    }
    let finest = &out[2];
    assert!(finest.profile < 0.03, "profile error {}", finest.profile);
    assert!(finest.profile < out[0].profile, "profile errors do not fall");
    for o in &out[1..] {
        assert!(o.load_fit.abs() < 0.01, "P from the slope: {:+e}", o.load_fit);
    }
    // The half-width converges towards the corner: each spacing's a_fit above the previous.
    assert!(out.windows(2).all(|w| w[1].half_width > w[0].half_width));
    // The finite block: twice the size changes the profile error by less than 1 % and the
    // half-width by less than one spacing.
    let big = run(h[2], 4.0);
    assert!((big.profile - finest.profile).abs() < 0.01, "block size: {}", big.profile);
    assert!(
        (big.half_width - finest.half_width).abs() < h[2],
        "block size: a = {}",
        big.half_width
    );
}
