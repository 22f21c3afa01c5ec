//! The filter-design evaluator (Kraus §4.2): how far a pyramid of
//! `(a, b, b, a)` downsampling steps followed by linear or quadratic B-spline reconstruction is
//! from blurring with one convolution filter.
//!
//! # Definition
//!
//! A unit impulse sits on the fine grid at phase `t` of a level-`n` cell; the downsampling
//! filter is applied `n` times; level `n` is reconstructed continuously with `R` (the hat for
//! linear, the quadratic B-spline `B₂`), and the result is written in level-`n` units `u`
//! relative to the impulse and normalised to unit area: `K_t(u)`. With `K̄` the mean over `t`:
//! `ε² = mean_t ∫(K_t − K̄)² du` and `ε_c² = mean_t (K_t(0) − K̄(0))²`.
//!
//! # How it is computed
//!
//! Fine voxel `i = k ∈ [0, N)`, `N = 2^n`, lies in level-`n` cell 0 at phase `t_k = (k + ½)/N`,
//! level-`n` position `u_k = t_k − ½` (the coarse voxel centres are the integers, as in
//! `volsample::downsample`). Level `ℓ` is `g_ℓ[j] = Σ_m 2h[m]·g_{ℓ−1}[2j + m]`,
//! `h = (a, b, b, a)` at `m = −1, 0, 1, 2` on an unbounded grid (the factor 2 keeps unit mass,
//! which is the normalisation), so `K_k(u) = Σ_j g_n[j]·R(u + u_k − j)`. Then, exactly:
//!
//! * `∫K_k² = Σ_{j,j′} g[j]·g[j′]·c(j − j′)` with `c = R ⋆ R` the autocorrelation (`B₃` for the
//!   hat, `B₅` for `B₂`, centred cardinal B-splines);
//! * `K̄ = R ⋆ μ` with the discrete measure `μ = (1/N)·Σ_k Σ_j g_k[j]·δ(j − u_k)`, whose atoms
//!   lie on the grid `1/(2N)`, so `∫K̄² = Σ_{p,p′} μ_p μ_{p′} c(p − p′)` (an autocorrelation of
//!   `μ`);
//! * `ε² = mean_k ∫K_k² − ∫K̄²`, `ε_c² = mean_k K_k(0)² − K̄(0)²`.
//!
//! **Separable 2D:** impulses at independent phases `(t_x, t_y)`, `K = K_{t_x}(u)·K_{t_y}(v)`,
//! so with `A = mean ∫K_t²`, `B = ∫K̄²`, `P = mean K_t(0)²`, `Q = K̄(0)²`:
//! `ε₂² = A² − B²` and `ε_{c,2}² = P² − Q²` (and `A³ − B³` in 3D).

use std::fmt::Write as _;

/// The sampling (reconstruction) filter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Recon {
    /// Linear interpolation (the hat; trilinear in 3D).
    Linear,
    /// The quadratic B-spline `B₂` (triquadratic in 3D).
    QuadraticBSpline,
}

impl Recon {
    /// Both.
    pub const ALL: [Recon; 2] = [Recon::Linear, Recon::QuadraticBSpline];

    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Recon::Linear => "linear",
            Recon::QuadraticBSpline => "quadratic B-spline",
        }
    }

    /// `R(x)`.
    pub fn eval(self, x: f64) -> f64 {
        match self {
            Recon::Linear => bspline(1, x),
            Recon::QuadraticBSpline => bspline(2, x),
        }
    }

    /// `(R ⋆ R)(x)`: `B₃` or `B₅`.
    pub fn autocorrelation(self, x: f64) -> f64 {
        match self {
            Recon::Linear => bspline(3, x),
            Recon::QuadraticBSpline => bspline(5, x),
        }
    }

    /// Half-width of the support of `R ⋆ R`.
    fn ac_support(self) -> f64 {
        match self {
            Recon::Linear => 2.0,
            Recon::QuadraticBSpline => 3.0,
        }
    }
}

/// The centred cardinal B-spline of degree `m`:
/// `B_m(x) = (1/m!)·Σ_{i=0}^{m+1} (−1)^i·C(m+1, i)·(x + (m+1)/2 − i)₊^m`.
pub fn bspline(m: u32, x: f64) -> f64 {
    let half = f64::from(m + 1) / 2.0;
    if x.abs() >= half {
        return 0.0;
    }
    let mut sum = 0.0;
    let mut binom = 1.0;
    let mut fact = 1.0;
    for i in 1..=m {
        fact *= f64::from(i);
    }
    for i in 0..=m + 1 {
        let y = x + half - f64::from(i);
        if y > 0.0 {
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            sum += sign * binom * y.powi(m as i32);
        }
        binom = binom * f64::from(m + 1 - i) / f64::from(i + 1);
    }
    (sum / fact).max(0.0)
}

/// The level-`n` coefficients of a unit impulse at fine index `k` after `n` downsampling steps
/// with outer weight `a`, mass-normalised: `(first index, values)`.
pub fn cascade(a: f64, n: u32, k: i64) -> (i64, Vec<f64>) {
    let b = 0.5 - a;
    let h = [2.0 * a, 2.0 * b, 2.0 * b, 2.0 * a];
    let mut lo = k;
    let mut g = vec![1.0];
    for _ in 0..n {
        let hi = lo + g.len() as i64 - 1;
        let jlo = (lo - 2).div_euclid(2) + i64::from((lo - 2).rem_euclid(2) != 0);
        let jhi = (hi + 1).div_euclid(2);
        let mut next = vec![0.0; (jhi - jlo + 1) as usize];
        for (jj, out) in next.iter_mut().enumerate() {
            let j = jlo + jj as i64;
            for (mi, w) in h.iter().enumerate() {
                let i = 2 * j + mi as i64 - 1;
                if i >= lo && i <= hi {
                    *out += w * g[(i - lo) as usize];
                }
            }
        }
        lo = jlo;
        g = next;
    }
    (lo, g)
}

/// The evaluator's result for one filter and reconstruction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quality {
    /// Outer weight `a`.
    pub a: f64,
    /// Levels `n`.
    pub levels: u32,
    /// `mean_t ∫K_t²` (1D).
    pub a_mean: f64,
    /// `∫K̄²` (1D).
    pub b_mean: f64,
    /// `mean_t K_t(0)²` (1D).
    pub p_centre: f64,
    /// `K̄(0)²` (1D).
    pub q_centre: f64,
}

impl Quality {
    /// `ε` in 1D.
    pub fn eps(&self) -> f64 {
        (self.a_mean - self.b_mean).max(0.0).sqrt()
    }
    /// `ε_c` in 1D.
    pub fn eps_c(&self) -> f64 {
        (self.p_centre - self.q_centre).max(0.0).sqrt()
    }
    /// `ε` of the separable filter in `dim` dimensions: `√(A^dim − B^dim)`.
    pub fn eps_nd(&self, dim: i32) -> f64 {
        (self.a_mean.powi(dim) - self.b_mean.powi(dim))
            .max(0.0)
            .sqrt()
    }
    /// `ε_c` of the separable filter in `dim` dimensions: `√(P^dim − Q^dim)`.
    pub fn eps_c_nd(&self, dim: i32) -> f64 {
        (self.p_centre.powi(dim) - self.q_centre.powi(dim))
            .max(0.0)
            .sqrt()
    }
}

/// Evaluates the filter `(a, ½ − a, ½ − a, a)` (any real `a`) over `n ≥ 1` levels with
/// reconstruction `recon` (see the module docs).
pub fn evaluate(a: f64, recon: Recon, n: u32) -> Quality {
    let nn = 1i64 << n;
    let nf = nn as f64;
    let mut a_sum = 0.0;
    let mut k0_sum = 0.0;
    let mut k0_sq = 0.0;
    // μ on the grid 1/(2N): atom index m = 2N·p = 2N·j − 2k − 1 + N.
    let mut atoms: Vec<(i64, f64)> = Vec::new();
    for k in 0..nn {
        let (lo, g) = cascade(a, n, k);
        let u = (k as f64 + 0.5) / nf - 0.5;
        let mut ak = 0.0;
        for (i, gi) in g.iter().enumerate() {
            for (i2, gi2) in g.iter().enumerate() {
                ak += gi * gi2 * recon.autocorrelation(i as f64 - i2 as f64);
            }
        }
        a_sum += ak;
        let k0: f64 = g
            .iter()
            .enumerate()
            .map(|(i, gi)| gi * recon.eval(u - (lo + i as i64) as f64))
            .sum();
        k0_sum += k0;
        k0_sq += k0 * k0;
        for (i, gi) in g.iter().enumerate() {
            let j = lo + i as i64;
            atoms.push((2 * nn * j - 2 * k - 1 + nn, gi / nf));
        }
    }
    let mmin = atoms.iter().map(|x| x.0).min().unwrap_or(0);
    let mmax = atoms.iter().map(|x| x.0).max().unwrap_or(0);
    let mut mu = vec![0.0; (mmax - mmin + 1) as usize];
    for (m, w) in atoms {
        mu[(m - mmin) as usize] += w;
    }
    let reach = (recon.ac_support() * 2.0 * nf).ceil() as usize;
    let mut b = 0.0;
    for delta in 0..reach.min(mu.len()) {
        let c = recon.autocorrelation(delta as f64 / (2.0 * nf));
        if c == 0.0 {
            continue;
        }
        let ac: f64 = mu.iter().zip(&mu[delta..]).map(|(x, y)| x * y).sum();
        b += if delta == 0 { c * ac } else { 2.0 * c * ac };
    }
    let k0_mean = k0_sum / nf;
    Quality {
        a,
        levels: n,
        a_mean: a_sum / nf,
        b_mean: b,
        p_centre: k0_sq / nf,
        q_centre: k0_mean * k0_mean,
    }
}

/// What a search minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Criterion {
    /// `ε` in 1D.
    Eps,
    /// `ε_c` in 1D.
    EpsC,
    /// `ε` of the separable 2D filter.
    Eps2,
    /// `ε_c` of the separable 2D filter.
    EpsC2,
}

impl Criterion {
    /// All four.
    pub const ALL: [Criterion; 4] = [
        Criterion::Eps,
        Criterion::EpsC,
        Criterion::Eps2,
        Criterion::EpsC2,
    ];

    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Criterion::Eps => "eps (1D)",
            Criterion::EpsC => "eps_c (1D)",
            Criterion::Eps2 => "eps (2D)",
            Criterion::EpsC2 => "eps_c (2D)",
        }
    }

    /// The value of the criterion.
    pub fn of(self, q: &Quality) -> f64 {
        match self {
            Criterion::Eps => q.eps(),
            Criterion::EpsC => q.eps_c(),
            Criterion::Eps2 => q.eps_nd(2),
            Criterion::EpsC2 => q.eps_c_nd(2),
        }
    }
}

/// The `a ∈ [lo, hi]` minimising `crit`: a scan in steps of `(hi − lo)/steps` at `n_scan`
/// levels, then golden-section refinement at `n` levels within one scan step of the best
/// point. Returns `(a, value at n levels)`.
pub fn minimise(
    recon: Recon,
    crit: Criterion,
    lo: f64,
    hi: f64,
    steps: usize,
    n_scan: u32,
    n: u32,
) -> (f64, f64) {
    let f = |a: f64, n: u32| crit.of(&evaluate(a, recon, n));
    let h = (hi - lo) / steps as f64;
    let best = (0..=steps)
        .map(|i| lo + h * i as f64)
        .map(|a| (a, f(a, n_scan)))
        .fold((lo, f64::INFINITY), |m, x| if x.1 < m.1 { x } else { m });
    let (mut x0, mut x1) = ((best.0 - h).max(lo), (best.0 + h).min(hi));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let mut c = x1 - g * (x1 - x0);
    let mut d = x0 + g * (x1 - x0);
    let (mut fc, mut fd) = (f(c, n), f(d, n));
    for _ in 0..40 {
        if fc < fd {
            x1 = d;
            d = c;
            fd = fc;
            c = x1 - g * (x1 - x0);
            fc = f(c, n);
        } else {
            x0 = c;
            c = d;
            fc = fd;
            d = x0 + g * (x1 - x0);
            fd = f(d, n);
        }
    }
    let a = (x0 + x1) / 2.0;
    (a, f(a, n))
}

/// The `volsample filters` table: `ε`, `ε_c` in 1D and 2D for `a = 0, ⅛, ⅕, ¼` and both
/// reconstructions at `n` levels, then the minimising `a` of each criterion in `[−¼, ½]`.
pub fn table(n: u32) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Filter quality of (a, b, b, a) downsampling, {n} levels (Kraus 2008 §4.2)"
    );
    let _ = writeln!(
        s,
        "{:<20} {:>7} {:>10} {:>10} {:>10} {:>10}",
        "reconstruction", "a", "eps 1D", "eps_c 1D", "eps 2D", "eps_c 2D"
    );
    for recon in Recon::ALL {
        for (a, name) in [(0.0, "0"), (0.125, "1/8"), (0.2, "1/5"), (0.25, "1/4")] {
            let q = evaluate(a, recon, n);
            let _ = writeln!(
                s,
                "{:<20} {:>7} {:>10.5} {:>10.5} {:>10.5} {:>10.5}",
                recon.name(),
                name,
                q.eps(),
                q.eps_c(),
                q.eps_nd(2),
                q.eps_c_nd(2)
            );
        }
    }
    let _ = writeln!(s, "\nminimising a in [-1/4, 1/2]:");
    let _ = writeln!(
        s,
        "{:<20} {:<12} {:>9} {:>10}",
        "reconstruction", "criterion", "a", "value"
    );
    for recon in Recon::ALL {
        for crit in Criterion::ALL {
            let (a, v) = minimise(recon, crit, -0.25, 0.5, 150, n.min(7), n);
            let _ = writeln!(
                s,
                "{:<20} {:<12} {:>9.5} {:>10.5}",
                recon.name(),
                crit.name(),
                a,
                v
            );
        }
    }
    s
}

/// `volsample filters`: prints [`table`] for `levels` levels (1 to 12).
///
/// # Errors
/// For `levels` outside `1..=12`.
pub fn run(levels: u32) -> Result<(), String> {
    if !(1..=12).contains(&levels) {
        return Err(format!("--levels must be in 1..=12, not {levels}"));
    }
    crate::out::emit(&table(levels));
    Ok(())
}
