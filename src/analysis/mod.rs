//! Looking at a render: error metrics against a reference, convergence
//! curves, the noise views, the pixel probe, the path view of one sample,
//! the integrand over the hemisphere at a point and the sources' domains
//! there, and the convergence capture behind the viewer's plot.

pub mod capture;
pub mod chi2;
pub mod convergence;
pub mod domains;
pub mod hemisphere;
pub mod hemisphere_colour;
pub mod metrics;
pub mod noise;
pub mod path_view;
pub mod probe;
pub mod sampling_lab;
pub mod strategy_samples;
