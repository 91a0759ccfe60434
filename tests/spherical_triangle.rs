//! The spherical triangle sampler (solid-angle sampling of triangle
//! lights) draws what its pdf says: uniform directions over the triangle's
//! solid angle, which the Van Oosterom–Strackee formula gives.

use glam::{DVec3, Vec2};
use lumiere::transport::sampler::SampleStream;
use lumiere::transport::warps::{spherical_triangle, spherical_triangle_area};

/// Barycentrics (b1, b2) of where the ray from `p` along `w` meets the plane of `v`.
fn barycentrics(v: &[DVec3; 3], p: DVec3, w: DVec3) -> (f64, f64) {
    let (e1, e2) = (v[1] - v[0], v[2] - v[0]);
    let s1 = w.cross(e2);
    let divisor = s1.dot(e1);
    let s = p - v[0];
    (s.dot(s1) / divisor, w.dot(s.cross(e1)) / divisor)
}

/// Bin of barycentrics (b1, b2) among the K² sub-triangles of a K × K grid.
fn bin_of(b1: f64, b2: f64, k: usize) -> usize {
    let (x, y) = (b1.clamp(0.0, 1.0) * k as f64, b2.clamp(0.0, 1.0) * k as f64);
    let (i, j) = ((x as usize).min(k - 1), (y as usize).min(k - 1));
    let (fx, fy) = (x - i as f64, y - j as f64);
    // cells (i, j) with i + j = k − 1 have only their lower half in the triangle
    let upper = (fx + fy >= 1.0 && i + j < k - 1) as usize;
    2 * (i * k + j) + upper
}

/// ∫ cos θ_q / d² dA from `p` over each of the K² sub-triangles (bins),
/// by the centroid rule on the triangles of a `fine` × `fine` grid (`fine`
/// a multiple of K): the solid angle each bin subtends.
fn bin_solid_angles(v: &[DVec3; 3], p: DVec3, k: usize, fine: usize) -> Vec<f64> {
    let normal = (v[1] - v[0]).cross(v[2] - v[0]);
    let area = normal.length() / 2.0;
    let normal = normal.normalize();
    let cell_area = area / (fine * fine) as f64;
    let mut bins = vec![0.0; 2 * k * k];
    for i in 0..fine {
        for j in 0..fine - i {
            // the lower fine triangle of cell (i, j), and its upper one if inside
            let mut centroids = vec![((i as f64 + 1.0 / 3.0), (j as f64 + 1.0 / 3.0))];
            if i + j < fine - 1 {
                centroids.push((i as f64 + 2.0 / 3.0, j as f64 + 2.0 / 3.0));
            }
            for (ci, cj) in centroids {
                let (b1, b2) = (ci / fine as f64, cj / fine as f64);
                let q = v[0] + b1 * (v[1] - v[0]) + b2 * (v[2] - v[0]);
                let d = q - p;
                let density = normal.dot(d).abs() / d.length().powi(3);
                bins[bin_of(b1, b2, k)] += density * cell_area;
            }
        }
    }
    bins
}

/// Wilson–Hilferty's approximation of the χ² quantile with `dof` degrees of
/// freedom exceeded with probability Φ(−z).
fn chi2_quantile(dof: f64, z: f64) -> f64 {
    let a = 2.0 / (9.0 * dof);
    dof * (1.0 - a + z * a.sqrt()).powi(3)
}

/// Pearson's χ² of observed counts against expected ones, pooling the bins
/// expected to hold fewer than 5 (Nori's rule); returns (χ², degrees of freedom).
fn chi2(observed: &[u64], expected: &[f64]) -> (f64, f64) {
    let (mut statistic, mut bins) = (0.0, 0usize);
    let (mut pooled_observed, mut pooled_expected) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pooled_observed += o as f64;
            pooled_expected += e;
        } else {
            statistic += (o as f64 - e).powi(2) / e;
            bins += 1;
        }
    }
    if pooled_expected > 0.0 {
        statistic += (pooled_observed - pooled_expected).powi(2) / pooled_expected.max(1e-9);
        bins += 1;
    }
    (statistic, bins as f64 - 1.0)
}

/// Directions drawn by `spherical_triangle` are uniform in solid angle over
/// the triangle: χ² over 100 sub-triangles against the solid angle each
/// subtends (integrated numerically), for a near, a far, a large and a
/// grazing triangle. The Van Oosterom–Strackee solid angle matches the
/// numerical integral within its estimated error (about 10⁻⁶ of Ω, far
/// below the bins' counting noise) and the returned pdf is its inverse.
#[test]
fn spherical_triangle_samples_are_uniform_in_solid_angle() {
    let p = DVec3::ZERO;
    let triangles: [(&str, [DVec3; 3]); 4] = [
        (
            "near",
            [
                DVec3::new(-0.6, -0.4, 0.3),
                DVec3::new(0.7, -0.5, 0.35),
                DVec3::new(0.1, 0.8, 0.25),
            ],
        ),
        (
            "far",
            [
                DVec3::new(1.0, 2.0, 12.0),
                DVec3::new(1.3, 2.05, 12.1),
                DVec3::new(1.1, 2.3, 11.9),
            ],
        ),
        (
            "large",
            [
                DVec3::new(-6.0, -5.0, 0.4),
                DVec3::new(7.0, -6.0, 0.5),
                DVec3::new(0.5, 8.0, 0.3),
            ],
        ),
        (
            "grazing",
            [
                DVec3::new(1.0, -0.3, 0.02),
                DVec3::new(1.6, 0.1, 0.06),
                DVec3::new(1.1, 0.5, 0.03),
            ],
        ),
    ];
    let k = 10;
    let samples = 200_000u64;
    for (name, v) in triangles {
        let [a, b, c] = v.map(|q| (q - p).normalize());
        let solid_angle = spherical_triangle_area(a, b, c);
        let bins = bin_solid_angles(&v, p, k, 64 * k);
        let integral: f64 = bins.iter().sum();
        let coarse: f64 = bin_solid_angles(&v, p, k, 32 * k).iter().sum();
        // the centroid rule's error is c·h² + O(h⁴): halving h, Richardson's
        // (I_h − I_2h)/3 estimates it; twice that covers the O(h⁴) rest, and
        // the f64 sum of fine² terms adds at most fine²·2⁻⁵³ of I
        let quadrature_error = 2.0 * (integral - coarse).abs() / 3.0;
        let rounding = (64.0 * k as f64).powi(2) * f64::EPSILON / 2.0 * integral;
        assert!(
            (integral - solid_angle).abs() <= quadrature_error + rounding,
            "{name}: Ω = {solid_angle}, numerical integral {integral} ± {:.1e}",
            quadrature_error + rounding
        );
        let mut observed = vec![0u64; bins.len()];
        for i in 0..samples {
            let s = SampleStream::new(3, 0, i);
            let u = Vec2::new(s.uniform(0), s.uniform(1));
            let (w, pdf) = spherical_triangle(a, b, c, u).expect("a proper triangle");
            // pdf = 1/Ω of the same Ω: two f64 roundings of ε/2 each
            assert!(
                (pdf * solid_angle - 1.0).abs() <= f64::EPSILON,
                "{name}: pdf {pdf}"
            );
            let (b1, b2) = barycentrics(&v, p, w);
            assert!(
                b1 >= -1e-6 && b2 >= -1e-6 && b1 + b2 <= 1.0 + 1e-6,
                "{name}: direction {w} misses the triangle ({b1}, {b2})"
            );
            observed[bin_of(b1, b2, k)] += 1;
        }
        let expected: Vec<f64> = bins
            .iter()
            .map(|omega| omega / integral * samples as f64)
            .collect();
        let (statistic, dof) = chi2(&observed, &expected);
        // significance 1e-4 per triangle (z = 3.72)
        let limit = chi2_quantile(dof, 3.72);
        assert!(
            statistic < limit,
            "{name} (Ω = {solid_angle:.4} sr): χ² = {statistic:.1} > {limit:.1} with {dof} degrees of freedom"
        );
    }
}
