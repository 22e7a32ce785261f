//! What the β studies (`examples/studies/beta_study.rs`, `examples/studies/beta_study_hertz.rs`)
//! share: the variants, the spacing ladder, the problem substitution, the per-stage times, the
//! pressure ripple and the error-against-cost charts. Their command line is `args.rs`.

use mlpg_contact::mls::Basis;
use mlpg_contact::post::plot;
use mlpg_contact::problem::Problem;

/// One discretisation variant of the study.
pub struct Variant {
    pub name: &'static str,
    pub basis: Basis,
    pub support_factor: f64,
    pub beta: f64,
}

/// The variants of the β study: the paper's mixed method, the blend β with larger supports, and
/// the quadratic basis.
pub const VARIANTS: [Variant; 5] = [
    Variant {
        name: "mixed β=0, α_s=2 (paper)",
        basis: Basis::Linear,
        support_factor: 2.0,
        beta: 0.0,
    },
    Variant { name: "β=1, α_s=2", basis: Basis::Linear, support_factor: 2.0, beta: 1.0 },
    Variant { name: "β=1, α_s=3", basis: Basis::Linear, support_factor: 3.0, beta: 1.0 },
    Variant { name: "β=0.5, α_s=3", basis: Basis::Linear, support_factor: 3.0, beta: 0.5 },
    Variant {
        name: "quadratic β=0, α_s=2.5",
        basis: Basis::Quadratic,
        support_factor: 2.5,
        beta: 0.0,
    },
];

/// `coarsest, coarsest/2, …` down to `finest`.
pub fn spacings(coarsest: f64, finest: f64) -> Vec<f64> {
    let mut spacings = vec![coarsest];
    while spacings.last().copied().unwrap_or(0.0) / 2.0 >= finest * 0.999 {
        let h = spacings[spacings.len() - 1] / 2.0;
        spacings.push(h);
    }
    spacings
}

/// Loads `problems/<file>`.
pub fn load(file: &str) -> Problem {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems").join(file);
    Problem::from_toml(&std::fs::read_to_string(path).expect("problem file"))
        .expect("valid problem")
}

/// `base` with the spacing and the variant's basis, support factor and β substituted.
pub fn substitute(base: &Problem, v: &Variant, h: f64) -> Problem {
    let mut p = base.clone();
    p.node_spacing = h;
    p.discretisation.mls.basis = v.basis;
    p.discretisation.mls.support_factor = v.support_factor;
    p.discretisation.beta = v.beta;
    p
}

/// (MLS at nodes and faces, assembly, factorisation, condensation, lemke, `total`) [s].
pub fn stage_times(s: &mlpg_contact::Solution, total: f64) -> [f64; 6] {
    let stage = |names: &[&str]| -> f64 {
        s.timings.iter().filter(|t| names.contains(&t.stage)).map(|t| t.seconds).sum()
    };
    [
        stage(&["mls_nodes", "mls_faces"]),
        stage(&["assembly"]),
        stage(&["factorisation"]),
        stage(&["condensation"]),
        stage(&["lemke"]),
        total,
    ]
}

/// Node-to-node ripple: largest second difference of the pressure over closed candidates
/// whose neighbours are closed too, relative to the peak pressure `peak`.
pub fn ripple(c: &mlpg_contact::ContactSolution, peak: f64) -> f64 {
    (1..c.pressure.len().saturating_sub(1))
        .filter(|&k| c.closed[k - 1] && c.closed[k] && c.closed[k + 1])
        .map(|k| (c.pressure[k] - 0.5 * (c.pressure[k - 1] + c.pressure[k + 1])).abs())
        .fold(0.0, f64::max)
        / peak.max(f64::MIN_POSITIVE)
}

/// One error-against-cost chart: file stem, x label, x of a row, y label, y of a row.
pub type ChartSpec<R> = (&'static str, &'static str, fn(&R) -> f64, &'static str, fn(&R) -> f64);

/// Writes each chart (SVG and PNG, one line per variant) to `target/<dir>/` and says where.
pub fn write_charts<R>(
    dir: &str,
    title: &str,
    results: &[(&str, Vec<R>)],
    charts: &[ChartSpec<R>],
) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target").join(dir);
    std::fs::create_dir_all(&dir).expect("output directory");
    for &(stem, x_label, x, y_label, y) in charts {
        let chart = plot::Chart {
            title: format!("{title}: {y_label} against {x_label}"),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: results
                .iter()
                .enumerate()
                .map(|(k, (name, rows))| plot::Series {
                    label: (*name).into(),
                    points: rows.iter().map(|r| (x(r), y(r))).filter(|p| p.1.is_finite()).collect(),
                    style: plot::Style::Line,
                    colour: k,
                })
                .collect(),
        };
        plot::write_chart(&dir.join(stem), &chart).expect("plot");
    }
    println!("plots: {}", dir.display());
}
