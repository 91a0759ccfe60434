//! The path view: the rays of one sample of a probed pixel, laid over the image.
//!
//! The integrator records every ray a sample traces ([`PathLog`]): the camera
//! ray, the shadow rays towards light samples, the directions gathered to find
//! a light and the continuations (bounces). Each is projected onto the film
//! ([`CameraRays::project_segment`]) and styled by what it did:
//!
//! ```text
//! ray               colour                           line
//! camera            white (seen end-on: a ring)      —
//! shadow, reaches   the term it adds to (L1, L2 …)   solid
//! shadow, blocked   red                              dashed
//! gathered, light   the term it adds to              solid
//! gathered, none    grey                             dashed, thin
//! bounce            the term of the vertex it reaches (its light samples add to it)
//! last bounce       the term its emission adds to (the path ends where it lands)
//! refracted bounce  as a bounce, outlined in white: it crossed glass
//! ```
//!
//! A bounce from the first hit is coloured L2: the light samples at its end
//! are the one-indirect-bounce term. The last bounce of an L0–L2 render only
//! looks for a light (the BRDF-sampled half of MIS for L2).

use std::fmt;
use std::str::FromStr;

use glam::Vec2;

use crate::course::color::luminance;
use crate::course::{Term, TermSet};
use crate::geometry::camera::CameraRays;
use crate::transport::path_log::{PathLog, PathSegment, SegmentKind};

/// What a drawn ray did, which decides its style.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayRole {
    Camera,
    /// A continuation reaching a vertex whose light samples add to `term`;
    /// `refracted` if it went through glass.
    Bounce {
        term: Term,
        refracted: bool,
    },
    /// The path's last continuation: the emission it finds adds to `term`.
    LastBounce {
        term: Term,
        refracted: bool,
    },
    /// A shadow ray that reached its light sample, adding to `term`.
    ShadowLit {
        term: Term,
    },
    /// A shadow ray blocked before its light sample.
    ShadowBlocked {
        term: Term,
    },
    /// A gathered direction that found a light, adding to `term`.
    GatherLit {
        term: Term,
    },
    /// A gathered direction that found no light.
    GatherMissed {
        term: Term,
    },
}

impl RayRole {
    /// The role of `segment` in a render of `terms`.
    pub fn of(segment: &PathSegment, terms: TermSet) -> Self {
        let term = segment.term;
        match segment.kind {
            SegmentKind::Camera => RayRole::Camera,
            SegmentKind::Bounce { refracted } if terms.contains(next_term(term)) => {
                RayRole::Bounce {
                    term: next_term(term),
                    refracted,
                }
            }
            // the path ends where this ray lands: it only looks for a light
            SegmentKind::Bounce { refracted } => RayRole::LastBounce { term, refracted },
            SegmentKind::Shadow {
                occluded: false, ..
            } => RayRole::ShadowLit { term },
            SegmentKind::Shadow { occluded: true, .. } => RayRole::ShadowBlocked { term },
            SegmentKind::Gather { hit_light: true } => RayRole::GatherLit { term },
            SegmentKind::Gather { hit_light: false } => RayRole::GatherMissed { term },
        }
    }

    /// The term whose colour the ray wears, if any (camera rays and blocked or
    /// missed rays wear their own).
    pub fn colour_term(self) -> Option<Term> {
        match self {
            RayRole::Bounce { term, .. }
            | RayRole::LastBounce { term, .. }
            | RayRole::ShadowLit { term }
            | RayRole::GatherLit { term } => Some(term),
            RayRole::Camera | RayRole::ShadowBlocked { .. } | RayRole::GatherMissed { .. } => None,
        }
    }

    /// Whether the ray went through glass (drawn outlined in white).
    pub fn is_refracted(self) -> bool {
        matches!(
            self,
            RayRole::Bounce {
                refracted: true,
                ..
            } | RayRole::LastBounce {
                refracted: true,
                ..
            }
        )
    }

    /// Whether the ray is drawn dashed: it added nothing.
    pub fn is_dashed(self) -> bool {
        matches!(
            self,
            RayRole::ShadowBlocked { .. } | RayRole::GatherMissed { .. }
        )
    }

    /// What the ray is, for the list beside the drawing.
    pub fn describe(self) -> String {
        match self {
            RayRole::Camera => "camera ray".into(),
            RayRole::Bounce { term, refracted } => {
                format!("{} to an {} vertex", bounce_word(refracted), term.label())
            }
            RayRole::LastBounce { term, refracted } => format!(
                "last {}, looks for a light ({})",
                bounce_word(refracted),
                term.label()
            ),
            RayRole::ShadowLit { term } => {
                format!("{} shadow ray, reaches the light", term.label())
            }
            RayRole::ShadowBlocked { term } => format!("{} shadow ray, blocked", term.label()),
            RayRole::GatherLit { term } => {
                format!("{} gathered direction, finds a light", term.label())
            }
            RayRole::GatherMissed { term } => {
                format!("{} gathered direction, no light", term.label())
            }
        }
    }
}

/// "bounce", or "refraction" for a continuation through glass.
fn bounce_word(refracted: bool) -> &'static str {
    if refracted { "refraction" } else { "bounce" }
}

/// The term after `term` (L3+ stays L3+).
fn next_term(term: Term) -> Term {
    Term::of_reflections(term.index() as u32 + 1)
}

/// One recorded ray as a line on the film.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathLine {
    /// Film points in pixels from the top-left corner, clipped to a margin
    /// around the image (one image size on each side).
    pub from: Vec2,
    pub to: Vec2,
    pub role: RayRole,
    /// The segment's index in the log.
    pub segment: usize,
    /// Whether `to` is the ray's own end (not a clipped point).
    pub ends_on_film: bool,
}

/// The lines of `log` (a sample of a render of `terms`) seen through
/// `camera`, in the log's order; rays wholly behind the camera or far outside
/// the image are left out.
pub fn path_lines(log: &PathLog, camera: &CameraRays, terms: TermSet) -> Vec<PathLine> {
    let size = camera.film_size();
    let (lo, hi) = (-size, 2.0 * size);
    log.segments
        .iter()
        .enumerate()
        .filter_map(|(segment, s)| {
            let (from, to) = camera.project_segment(s.from, s.to)?;
            let (from_clipped, to_clipped) = clip_to_box(from, to, lo, hi)?;
            Some(PathLine {
                from: from_clipped,
                to: to_clipped,
                role: RayRole::of(s, terms),
                segment,
                ends_on_film: to_clipped == to,
            })
        })
        .collect()
}

/// The part of segment `a`–`b` inside the box `lo`–`hi` (Liang–Barsky).
fn clip_to_box(a: Vec2, b: Vec2, lo: Vec2, hi: Vec2) -> Option<(Vec2, Vec2)> {
    if !(a.is_finite() && b.is_finite()) {
        return None;
    }
    let d = b - a;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for (p, q) in [
        (-d.x, a.x - lo.x),
        (d.x, hi.x - a.x),
        (-d.y, a.y - lo.y),
        (d.y, hi.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f32| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            a + d * t
        }
    };
    Some((at(t0), at(t1)))
}

/// Luminance a segment added to its term, W/(m²·sr).
pub fn segment_luminance(segment: &PathSegment) -> f32 {
    luminance(segment.radiance)
}

/// Which of a probed pixel's samples the path view shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathSample {
    /// The n-th sample (from 1), in the order the film summed them.
    Number(u32),
    /// The sample of largest luminance (the firefly, if any).
    Brightest,
}

impl Default for PathSample {
    fn default() -> Self {
        PathSample::Number(1)
    }
}

impl fmt::Display for PathSample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PathSample::Number(n) => write!(f, "{n}"),
            PathSample::Brightest => f.write_str("brightest"),
        }
    }
}

impl FromStr for PathSample {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        if s.eq_ignore_ascii_case("brightest") {
            return Ok(PathSample::Brightest);
        }
        match s.parse::<u32>() {
            Ok(n) if n >= 1 => Ok(PathSample::Number(n)),
            _ => Err(format!(
                "'{s}' is not a sample: expected a number from 1 or 'brightest'"
            )),
        }
    }
}

/// The colour of a ray (8-bit sRGB): its term's, red if blocked, grey if it
/// missed, white for the camera ray; the viewer and the slides draw these.
pub fn role_rgb(role: RayRole) -> [u8; 3] {
    match role {
        RayRole::Camera => [255, 255, 255],
        RayRole::ShadowBlocked { .. } => [235, 70, 60],
        RayRole::GatherMissed { .. } => [170, 170, 170],
        RayRole::Bounce { term, .. }
        | RayRole::LastBounce { term, .. }
        | RayRole::ShadowLit { term }
        | RayRole::GatherLit { term } => term_rgb(term),
    }
}

/// The outline drawn under a ray (8-bit sRGB): white for a refraction
/// through glass, else near black, so that the ray shows on any image.
pub fn outline_rgb(role: RayRole) -> [u8; 3] {
    if role.is_refracted() {
        [245, 245, 245]
    } else {
        [12, 12, 12]
    }
}

/// The colour of a term's rays and bars (8-bit sRGB).
pub fn term_rgb(term: Term) -> [u8; 3] {
    match term {
        Term::L0 => [230, 180, 60],
        Term::L1 => [90, 160, 230],
        Term::L2 => [110, 200, 120],
        Term::L3Plus => [200, 120, 200],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_keeps_the_inside_part() {
        let (lo, hi) = (Vec2::ZERO, Vec2::splat(10.0));
        let inside = (Vec2::new(1.0, 1.0), Vec2::new(9.0, 5.0));
        assert_eq!(clip_to_box(inside.0, inside.1, lo, hi), Some(inside));
        let crossing = clip_to_box(Vec2::new(-10.0, 5.0), Vec2::new(20.0, 5.0), lo, hi);
        assert_eq!(crossing, Some((Vec2::new(0.0, 5.0), Vec2::new(10.0, 5.0))));
        assert_eq!(
            clip_to_box(Vec2::new(-5.0, -5.0), Vec2::new(-1.0, 20.0), lo, hi),
            None
        );
        assert_eq!(
            clip_to_box(Vec2::new(f32::NAN, 0.0), Vec2::ONE, lo, hi),
            None
        );
    }

    #[test]
    fn samples_parse() {
        assert_eq!("3".parse(), Ok(PathSample::Number(3)));
        assert_eq!("Brightest".parse(), Ok(PathSample::Brightest));
        assert!("0".parse::<PathSample>().is_err());
        assert!("many".parse::<PathSample>().is_err());
    }
}
