//! The lighting terms of the course: L0 emission, L1 direct lighting, L2 one
//! indirect bounce, L3+ the rest; a set of them; one sample's radiance per term.

use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// A lighting term of the course: the light that reached the camera after
/// exactly k reflections (L3+: three or more).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Term {
    L0,
    L1,
    L2,
    L3Plus,
}

impl Term {
    pub const ALL: [Term; 4] = [Term::L0, Term::L1, Term::L2, Term::L3Plus];
    pub const COUNT: usize = 4;

    pub fn label(self) -> &'static str {
        match self {
            Term::L0 => "L0",
            Term::L1 => "L1",
            Term::L2 => "L2",
            Term::L3Plus => "L3+",
        }
    }

    /// The term a path with `reflections` reflections belongs to.
    pub fn of_reflections(reflections: u32) -> Term {
        match reflections {
            0 => Term::L0,
            1 => Term::L1,
            2 => Term::L2,
            _ => Term::L3Plus,
        }
    }

    pub fn index(self) -> usize {
        self as usize
    }

    /// One-line description (English).
    pub fn description(self) -> &'static str {
        match self {
            Term::L0 => "emission: light emitted by the surface the camera sees",
            Term::L1 => "direct lighting: light from the sources, reflected once",
            Term::L2 => "indirect lighting: light reflected twice",
            Term::L3Plus => "three reflections or more (the rest of the full solution)",
        }
    }
}

impl fmt::Display for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}

/// A set of terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct TermSet {
    bits: u8,
}

impl Default for TermSet {
    fn default() -> Self {
        TermSet::COURSE
    }
}

impl TermSet {
    pub const NONE: TermSet = TermSet { bits: 0 };
    pub const ALL: TermSet = TermSet { bits: 0b1111 };
    /// The default of the course: L0 + L1 + L2.
    pub const COURSE: TermSet = TermSet { bits: 0b0111 };

    pub fn only(term: Term) -> Self {
        Self {
            bits: 1 << term.index(),
        }
    }

    pub fn contains(self, term: Term) -> bool {
        self.bits & (1 << term.index()) != 0
    }

    /// Whether the term of paths with `reflections` reflections is in the set.
    pub fn contains_reflections(self, reflections: u32) -> bool {
        self.contains(Term::of_reflections(reflections))
    }

    pub fn with(self, term: Term, on: bool) -> Self {
        let bit = 1 << term.index();
        Self {
            bits: if on {
                self.bits | bit
            } else {
                self.bits & !bit
            },
        }
    }

    pub fn is_empty(self) -> bool {
        self.bits == 0
    }

    /// The terms in both sets.
    pub fn intersection(self, other: TermSet) -> Self {
        Self {
            bits: self.bits & other.bits,
        }
    }

    /// The terms of `self` not in `other`.
    pub fn difference(self, other: TermSet) -> Self {
        Self {
            bits: self.bits & !other.bits,
        }
    }

    pub fn iter(self) -> impl Iterator<Item = Term> {
        Term::ALL.into_iter().filter(move |&t| self.contains(t))
    }

    /// The most reflections a path needs for these terms (`u32::MAX` with L3+).
    pub fn max_reflections(self) -> Option<u32> {
        self.iter().last().map(|t| match t {
            Term::L3Plus => u32::MAX,
            t => t.index() as u32,
        })
    }

    /// The last reflection a path needs for these terms within
    /// `max_bounces` (0: none, L0 alone or no term).
    pub fn last_reflection(self, max_bounces: u32) -> u32 {
        self.max_reflections().unwrap_or(0).min(max_bounces)
    }
}

impl fmt::Display for TermSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let labels: Vec<&str> = self.iter().map(Term::label).collect();
        f.write_str(&labels.join(","))
    }
}

impl FromStr for TermSet {
    type Err = String;

    /// `L0,L1,L2`, `all`, case-insensitive; `L3` is accepted for `L3+`.
    fn from_str(s: &str) -> Result<Self, String> {
        let mut set = TermSet::NONE;
        for word in s.split(',').map(str::trim) {
            let term = match word.to_ascii_uppercase().as_str() {
                "ALL" => {
                    set = TermSet::ALL;
                    continue;
                }
                "L0" => Term::L0,
                "L1" => Term::L1,
                "L2" => Term::L2,
                "L3+" | "L3" => Term::L3Plus,
                _ => {
                    return Err(format!(
                        "unknown term '{word}' (expected L0, L1, L2, L3+ or all, separated by commas)"
                    ));
                }
            };
            set = set.with(term, true);
        }
        if set.is_empty() {
            return Err("no term selected".into());
        }
        Ok(set)
    }
}

/// Radiance of one sample, per term (W·m⁻²·sr⁻¹, linear RGB), indexed by [`Term::index`].
pub type TermRadiance = [Vec3; Term::COUNT];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn term_sets_parse_and_print() {
        assert_eq!("L0,L1,L2".parse::<TermSet>().unwrap(), TermSet::COURSE);
        assert_eq!("all".parse::<TermSet>().unwrap(), TermSet::ALL);
        assert_eq!(
            "l3+".parse::<TermSet>().unwrap(),
            TermSet::only(Term::L3Plus)
        );
        assert!("L4".parse::<TermSet>().is_err());
        assert_eq!(TermSet::ALL.to_string(), "L0,L1,L2,L3+");
        assert_eq!(TermSet::only(Term::L2).max_reflections(), Some(2));
        assert_eq!(TermSet::ALL.max_reflections(), Some(u32::MAX));
    }
}
