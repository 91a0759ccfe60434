//! Looking at a render: error metrics against a reference, convergence
//! curves, the noise views, the pixel probe, the path view of one sample,
//! and the convergence capture behind the viewer's plot.

pub mod capture;
pub mod convergence;
pub mod hemisphere;
pub mod metrics;
pub mod noise;
pub mod path_view;
pub mod probe;
