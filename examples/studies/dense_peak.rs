//! The dense matrix-multiply rate this machine sustains (faer's GEMM, the kernel behind the
//! large fronts of the sparse LU), for the flop-count floor of a factorisation. Run with
//!
//! ```text
//! cargo run --release --features studies --example dense_peak -- [size ...]
//! ```
//!
//! For each size `n` (default 512 1024 2048 4096) it times `C −= A B` with `n × n`
//! matrices in f64 and f32, on one thread and on all of rayon's threads, best of three, and
//! prints GFlop/s (`2 n³` flops per product). Nothing is asserted.

mod args;

use clap::Parser;
use std::time::Instant;

use faer::{Accum, Mat, Par, linalg::matmul::matmul};

fn rate<T: faer::traits::ComplexField + Copy>(n: usize, par: Par, one: T) -> f64 {
    let a = Mat::<T>::from_fn(n, n, |i, j| if (i + 2 * j) % 7 == 0 { one } else { T::zero_impl() });
    let b = a.transpose().to_owned();
    let mut c = Mat::<T>::zeros(n, n);
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let t = Instant::now();
        matmul(c.as_mut(), Accum::Add, a.as_ref(), b.as_ref(), one, par);
        best = best.min(t.elapsed().as_secs_f64());
    }
    2.0 * (n as f64).powi(3) / best * 1e-9
}

/// The dense matrix-multiply rate (faer GEMM) in GFlop/s, f64 and f32, one and all threads.
#[derive(Parser)]
struct Cli {
    /// Matrix sizes n (n × n products), written 512, 1024 or 4k
    #[arg(value_name = "N", value_parser = args::count, default_values_t = [512, 1024, 2048, 4096])]
    sizes: Vec<usize>,
}

fn main() {
    let sizes = args::parse::<Cli>(&[]).sizes;
    let threads = rayon::current_num_threads();
    println!("faer GEMM, GFlop/s (best of 3); {threads} rayon threads");
    println!("{:>6} {:>10} {:>10} {:>10} {:>10}", "n", "f64 x1", "f64 xall", "f32 x1", "f32 xall");
    for n in sizes {
        println!(
            "{n:>6} {:>10.1} {:>10.1} {:>10.1} {:>10.1}",
            rate(n, Par::Seq, 1.0f64),
            rate(n, Par::rayon(threads), 1.0f64),
            rate(n, Par::Seq, 1.0f32),
            rate(n, Par::rayon(threads), 1.0f32)
        );
    }
}
