//! Pearson's χ² goodness-of-fit test, as the sampling lab and the tests of
//! the warps use it: observed counts in bins against each bin's
//! probability, bins pooled until each group expects at least
//! [`MIN_EXPECTED`] samples, and the tail probability of the statistic.

use std::f64::consts::PI;

/// Groups of bins expecting fewer samples than this are pooled (the χ²
/// approximation of the multinomial needs a few per group).
pub const MIN_EXPECTED: f64 = 5.0;

/// The outcome of a test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chi2 {
    /// Σ (observed − expected)² / expected over the groups.
    pub statistic: f64,
    /// Degrees of freedom: the groups less one.
    pub dof: usize,
    /// P(χ² ≥ statistic) if the counts follow the probabilities.
    pub p_value: f64,
}

/// χ² test of `observed` counts against bin `probabilities` (which should
/// cover the whole domain and sum to 1). Bins are taken by increasing
/// expectation and grouped until each group expects ≥ [`MIN_EXPECTED`]. A
/// count in a bin of probability 0 rejects outright (p = 0).
pub fn chi2_test(observed: &[u64], probabilities: &[f64]) -> Chi2 {
    let total: u64 = observed.iter().sum();
    let impossible = observed
        .iter()
        .zip(probabilities)
        .any(|(&o, &p)| o > 0 && p <= 0.0);
    if impossible {
        return Chi2 {
            statistic: f64::INFINITY,
            dof: 0,
            p_value: 0.0,
        };
    }
    let mut order: Vec<usize> = (0..observed.len().min(probabilities.len())).collect();
    order.sort_by(|&a, &b| probabilities[a].total_cmp(&probabilities[b]));
    let mut groups: Vec<(f64, f64)> = Vec::new(); // (observed, expected)
    let mut open = (0.0, 0.0);
    for i in order {
        open.0 += observed[i] as f64;
        open.1 += probabilities[i].max(0.0) * total as f64;
        if open.1 >= MIN_EXPECTED {
            groups.push(open);
            open = (0.0, 0.0);
        }
    }
    if open.1 > 0.0 || open.0 > 0.0 {
        match groups.last_mut() {
            Some(last) => {
                last.0 += open.0;
                last.1 += open.1;
            }
            None => groups.push(open),
        }
    }
    let statistic: f64 = groups
        .iter()
        .filter(|&&(_, e)| e > 0.0)
        .map(|&(o, e)| (o - e) * (o - e) / e)
        .sum();
    let dof = groups.len().saturating_sub(1).max(1);
    Chi2 {
        statistic,
        dof,
        p_value: chi2_survival(statistic, dof),
    }
}

/// P(X ≥ statistic) for X ~ χ² with `dof` degrees of freedom.
pub fn chi2_survival(statistic: f64, dof: usize) -> f64 {
    gamma_q(dof as f64 / 2.0, statistic / 2.0)
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, 9 terms; ~15 digits).
pub fn ln_gamma(x: f64) -> f64 {
    const COEFFICIENTS: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // reflection: Γ(x) Γ(1 − x) = π / sin(πx)
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let series = COEFFICIENTS[1..]
        .iter()
        .enumerate()
        .fold(COEFFICIENTS[0], |sum, (i, c)| {
            sum + c / (x + i as f64 + 1.0)
        });
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + series.ln()
}

/// The regularised upper incomplete gamma function Q(a, x) = Γ(a, x) / Γ(a):
/// its series below x = a + 1, Lentz's continued fraction above.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    if !x.is_finite() {
        return 0.0;
    }
    let log_prefactor = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        while term.abs() > sum.abs() * 1e-15 {
            n += 1.0;
            term *= x / n;
            sum += term;
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let (mut c, mut d) = (1.0 / tiny, 1.0 / b);
        let mut fraction = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            d = if d.abs() < tiny { tiny } else { d };
            c = b + an / c;
            c = if c.abs() < tiny { tiny } else { c };
            d = 1.0 / d;
            let delta = d * c;
            fraction *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        fraction * log_prefactor.exp()
    }
}
