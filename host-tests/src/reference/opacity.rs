//! Opacity correction for a step `d ≠ d_ref`, and the exact extinction-to-opacity step.

use super::volume::{RefAssoc, RefExtinction};

/// `φ(x) = (1 − e^(−x))/x = −expm1(−x)/x`, with `φ(0) = 1` and `φ(+∞) = 0`.
///
/// Accurate to a few ulps for `x ≥ 0` (std `expm1`).
pub fn phi(x: f64) -> f64 {
    if x == 0.0 {
        1.0
    } else if x.is_infinite() {
        0.0
    } else {
        -(-x).exp_m1() / x
    }
}

/// `α/τ = (1 − e^(−τd))/τ` for a finite `τ ≥ 0`: `d·φ(τd)`, `d` at `τ = 0`, and `1/τ` when
/// `τd` overflows to infinity (`α = 1`).
pub fn alpha_over_tau(tau: f64, d: f64) -> f64 {
    let x = tau * d;
    if x.is_finite() {
        d * phi(x)
    } else {
        1.0 / tau
    }
}

/// Associated sample of a constant medium `e` over a step `d`: `α = 1 − e^(−τd)` (as
/// `−expm1(−τd)`) and `C̃ = C^τ·α/τ` (as `C^τ·d·φ(τd)`, so `C̃ = C^τ·d` at `τ = 0`).
pub fn extinction_sample(e: RefExtinction, d: f64) -> RefAssoc {
    let alpha = -(-(e.tau * d)).exp_m1();
    let k = alpha_over_tau(e.tau, d);
    RefAssoc {
        color: [e.color_tau[0] * k, e.color_tau[1] * k, e.color_tau[2] * k],
        alpha,
    }
}

/// Opacity correction of an associated sample `s` (valid for `d_ref`) to the step `d`, the
/// textbook way: `α_d = 1 − (1 − α)^(d/d_ref)` (std `powf`), `C̃_d = C̃·α_d/α`.
///
/// Returns `s` unchanged when `d == d_ref`, and transparent black when `α = 0`. `α = 1` stays
/// `1` for `d > 0`. Absolute error about `(d/d_ref)·2⁻⁵²`; the relative error of `α_d` grows for
/// `α` below about `1e-8` (where `1 − α` rounds), which is the price of the textbook form.
pub fn opacity_correct(s: RefAssoc, d: f64, d_ref: f64) -> RefAssoc {
    if d == d_ref {
        return s;
    }
    if s.alpha == 0.0 {
        return RefAssoc::TRANSPARENT;
    }
    let alpha_d = 1.0 - (1.0 - s.alpha).powf(d / d_ref);
    let ratio = alpha_d / s.alpha;
    RefAssoc {
        color: [s.color[0] * ratio, s.color[1] * ratio, s.color[2] * ratio],
        alpha: alpha_d,
    }
}

#[cfg(test)]
mod tests {
    use super::super::composite::over;
    use super::*;

    #[test]
    fn phi_limits() {
        assert_eq!(phi(0.0), 1.0);
        assert_eq!(phi(f64::INFINITY), 0.0);
        for x in [1e-300, 1e-20, 1e-9, 1e-6] {
            // φ(x) = 1 − x/2 + x²/6 − …
            assert!(
                (phi(x) - (1.0 - x / 2.0 + x * x / 6.0)).abs() < 1e-15,
                "{x}"
            );
        }
        assert!((phi(1.0) - (1.0 - (-1.0f64).exp())).abs() < 1e-15);
        assert!((phi(1000.0) - 1e-3).abs() < 1e-18);
        assert!(phi(5e-324) == 1.0);
    }

    #[test]
    fn alpha_over_tau_limits() {
        assert_eq!(alpha_over_tau(0.0, 0.5), 0.5);
        assert!((alpha_over_tau(2.0, 0.5) - (1.0 - (-1.0f64).exp()) / 2.0).abs() < 1e-15);
        assert_eq!(alpha_over_tau(1e300, 1e300), 1e-300);
    }

    #[test]
    fn extinction_sample_closed_forms() {
        let e = RefExtinction {
            tau: 2.0,
            color_tau: [2.0, 1.0, 0.0],
        };
        let s = extinction_sample(e, 0.5);
        let a = 1.0 - (-1.0f64).exp();
        assert!((s.alpha - a).abs() < 1e-15);
        assert!((s.color[0] - a).abs() < 1e-15);
        assert!((s.color[1] - a / 2.0).abs() < 1e-15);
        assert_eq!(s.color[2], 0.0);
        let zero = extinction_sample(
            RefExtinction {
                tau: 0.0,
                color_tau: [0.0; 3],
            },
            3.0,
        );
        assert_eq!(zero, RefAssoc::TRANSPARENT);
    }

    #[test]
    fn correction_identity_and_limits() {
        let s = RefAssoc::new([0.1, 0.2, 0.05], 0.3);
        assert_eq!(opacity_correct(s, 1.0, 1.0), s);
        assert_eq!(
            opacity_correct(RefAssoc::TRANSPARENT, 0.5, 1.0),
            RefAssoc::TRANSPARENT
        );
        let opaque = RefAssoc::new([0.5, 1.0, 0.0], 1.0);
        assert_eq!(opacity_correct(opaque, 0.01, 1.0), opaque);
        assert_eq!(opacity_correct(opaque, 100.0, 1.0), opaque);
        // Doubling the distance: α' = 1 − (1 − α)².
        let c = opacity_correct(s, 2.0, 1.0);
        assert!((c.alpha - 0.51).abs() < 1e-15);
        assert!((c.color[1] - 0.2 * 0.51 / 0.3).abs() < 1e-15);
        // Small α: ratio → d/d_ref.
        let tiny = opacity_correct(RefAssoc::new([1e-6; 3], 1e-6), 0.5, 1.0);
        assert!((tiny.alpha / 1e-6 - 0.5).abs() < 1e-6);
    }

    #[test]
    fn half_steps_compose_to_a_full_step() {
        let s = RefAssoc::new([0.3, 0.1, 0.6], 0.7);
        let h = opacity_correct(s, 0.5, 1.0);
        let two = over(h, h);
        assert!((two.alpha - s.alpha).abs() < 1e-15);
        for k in 0..3 {
            assert!((two.color[k] - s.color[k]).abs() < 1e-15);
        }
    }
}
