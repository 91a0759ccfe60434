//! Fresnel reflectance of a smooth dielectric interface (unpolarised light).
//!
//! With η = η_t / η_i the ratio of the indices across the interface (glass
//! seen from air: η = 1.5; from inside the glass: 1/1.5), θ_i the angle of
//! incidence and θ_t the refracted angle (Snell: sin θ_t = sin θ_i / η):
//!
//! ```text
//! r_∥ = (η cos θ_i − cos θ_t) / (η cos θ_i + cos θ_t)
//! r_⊥ = (cos θ_i − η cos θ_t) / (cos θ_i + η cos θ_t)
//! F   = (r_∥² + r_⊥²) / 2,        F = 1 when sin θ_t > 1 (total internal reflection)
//! ```
//!
//! At normal incidence F = ((η − 1)/(η + 1))²; the transmitted share is 1 − F.

/// Fresnel reflectance for a direction at `cos_incident` (≥ 0) to the
/// normal, on the side where the index ratio to the other side is `eta`.
pub fn fresnel_dielectric(cos_incident: f32, eta: f32) -> f32 {
    let cos_i = cos_incident.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0; // total internal reflection
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (parallel * parallel + perpendicular * perpendicular)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_gives_the_square_of_the_index_contrast() {
        for eta in [1.33f32, 1.5, 2.4, 1.0 / 1.5] {
            let expected = ((eta - 1.0) / (eta + 1.0)).powi(2);
            assert!(
                (fresnel_dielectric(1.0, eta) - expected).abs() < 1e-6,
                "η = {eta}"
            );
        }
        assert_eq!(
            fresnel_dielectric(1.0, 1.0),
            0.0,
            "no interface, no reflection"
        );
    }

    #[test]
    fn from_the_denser_side_light_is_totally_reflected_beyond_the_critical_angle() {
        let eta: f32 = 1.0 / 1.5;
        let critical = eta.asin(); // sin θ_c = η
        assert_eq!(fresnel_dielectric((critical + 1e-3).cos(), eta), 1.0);
        // F is continuous there (cos θ_t → 0 makes both amplitudes 1) and
        // rises all the way from the normal
        assert!(fresnel_dielectric((critical - 1e-5).cos(), eta) > 0.95);
        let rising: Vec<f32> = (0..=10)
            .map(|i| fresnel_dielectric((critical * i as f32 / 10.5).cos(), eta))
            .collect();
        assert!(rising.windows(2).all(|w| w[0] < w[1]), "{rising:?}");
    }

    #[test]
    fn grazing_light_is_reflected_and_the_two_sides_agree_along_snells_pairs() {
        assert!((fresnel_dielectric(0.0, 1.5) - 1.0).abs() < 1e-6);
        // reciprocity: a ray and its refracted ray see the same reflectance
        let eta = 1.5f32;
        for degrees in [0.0f32, 20.0, 45.0, 70.0, 85.0] {
            let theta_i = degrees.to_radians();
            let theta_t = (theta_i.sin() / eta).asin();
            let outside = fresnel_dielectric(theta_i.cos(), eta);
            let inside = fresnel_dielectric(theta_t.cos(), 1.0 / eta);
            assert!(
                (outside - inside).abs() < 1e-5,
                "{degrees}°: {outside} vs {inside}"
            );
        }
    }
}
