//! The command line's tools beyond `render`: the benchmark (`lumiere
//! bench`), the numerical stress suite (`lumiere stress`) and the
//! convergence strips for slides (`lumiere strip`).

pub mod bench;
pub mod font;
pub mod stress;
pub mod strip;
