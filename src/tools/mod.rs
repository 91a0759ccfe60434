//! The command line's tools beyond `render`: the benchmark (`lumiere
//! bench`), the numerical stress suite (`lumiere stress`), the convergence
//! strips (`lumiere strip`) and the slides of a lesson (`lumiere lesson
//! --export`).

pub mod bench;
pub mod font;
pub mod slides;
pub mod stress;
pub mod strip;
