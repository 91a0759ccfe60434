//! The rays of one traced sample, kept to draw its path (the path view) and
//! to replay them through the BVH (the bench's throughput section).

use glam::Vec3;

use crate::course::Term;
use crate::course::TermRadiance;
use crate::geometry::Ray;
use crate::geometry::accel::Query;

/// The segments of one traced sample, for drawing its path.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PathLog {
    pub segments: Vec<PathSegment>,
}

impl PathLog {
    /// The contributions of the segments, summed per term.
    pub fn radiance(&self) -> TermRadiance {
        let mut radiance = [Vec3::ZERO; Term::COUNT];
        for segment in &self.segments {
            radiance[segment.term.index()] += segment.radiance;
        }
        radiance
    }
}

/// One ray of a traced sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathSegment {
    pub from: Vec3,
    /// The ray as traced (origin, direction, t_max): what a replay through
    /// the BVH asks again (`bench::throughput`).
    pub ray: Ray,
    /// Where the ray stopped: its hit, the light point of a shadow ray, or one
    /// scene diagonal away for a ray that left the scene.
    pub to: Vec3,
    pub kind: SegmentKind,
    /// How it was traced: what a replay through the BVH asks again.
    pub query: Query,
    /// The term its contribution is filed under (the lowest it serves).
    pub term: Term,
    /// The radiance it added to `term` (zero if none).
    pub radiance: Vec3,
    /// The weight the emission it met was counted with (the MIS weight, or
    /// 1; 0 if it met none); `None`: another strategy counts what it meets.
    /// A shadow ray's is its light sample's weight, hidden or not.
    pub weight: Option<f32>,
}

/// What a traced ray was for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentKind {
    Camera,
    /// A continuation of the path (next reflection, or a refraction
    /// through glass: `refracted`).
    Bounce {
        refracted: bool,
    },
    /// Towards a light sample.
    Shadow {
        occluded: bool,
        /// The sphere light the ray aims at, which does not block it.
        target_sphere: Option<u32>,
    },
    /// A direction traced only to find a light.
    Gather {
        hit_light: bool,
    },
}
