//! Error of an image against a reference.
//!
//! For an image x and a reference r of n pixels × 3 channels:
//!
//! ```text
//! MSE    = 1/3n Σ (x − r)²
//! RMSE   = √MSE                                   (radiance units, W·m⁻²·sr⁻¹)
//! relMSE = 1/3n Σ (x − r)² / (r² + ε),  ε = 10⁻²  (unitless)
//! ```
//!
//! relMSE weighs dark and bright pixels alike; ε keeps black pixels of the
//! reference from dividing by zero. For an unbiased estimator both fall as
//! 1/N with the sample count N (RMSE as 1/√N): the slope −1/2 of the course.

use glam::Vec3;

use crate::course::error::RELMSE_EPSILON;

/// A converged image to measure error against (linear radiance, row-major from the top).
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceImage {
    pub width: u32,
    pub height: u32,
    pub radiance: Vec<Vec3>,
    /// Where it comes from, for labels: "1024 spp, mis, sobol" or a file name.
    pub label: String,
}

/// Error of one image against a reference.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImageError {
    pub rmse: f64,
    pub relmse: f64,
}

/// Error of `image` against `reference` (same size; `None` if sizes differ or
/// the images are empty).
pub fn image_error(image: &[Vec3], reference: &[Vec3]) -> Option<ImageError> {
    if image.len() != reference.len() || image.is_empty() {
        return None;
    }
    let (mut squared, mut relative) = (0.0f64, 0.0f64);
    for (x, r) in image.iter().zip(reference) {
        for c in 0..3 {
            let (x, r) = (x[c] as f64, r[c] as f64);
            let e2 = (x - r) * (x - r);
            squared += e2;
            relative += e2 / (r * r + RELMSE_EPSILON);
        }
    }
    let n = 3.0 * image.len() as f64;
    Some(ImageError {
        rmse: (squared / n).sqrt(),
        relmse: relative / n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_of_a_known_offset() {
        let reference = vec![Vec3::splat(1.0), Vec3::ZERO];
        let image = vec![Vec3::splat(1.5), Vec3::splat(0.5)];
        let e = image_error(&image, &reference).unwrap();
        assert!((e.rmse - 0.5).abs() < 1e-12);
        let expected = 0.5 * (0.25 / (1.0 + RELMSE_EPSILON) + 0.25 / RELMSE_EPSILON);
        assert!((e.relmse - expected).abs() < 1e-9);
        assert!(image_error(&image, &reference[..1]).is_none());
        assert_eq!(image_error(&reference, &reference).unwrap().rmse, 0.0);
    }
}
