//! How far an estimate is from the truth, in the course's measure.

/// ε of relMSE, (x − r)² / (r² + ε), and of a relative standard error's
/// denominator: keeps black pixels from dividing by zero.
pub const RELMSE_EPSILON: f64 = 1e-2;
