//! A second set of settings, written as what it changes: the B side of the
//! viewer's A/B comparison, and a lesson step's `[steps.settings.split]`.
//!
//! [`SettingsOverride`] holds optional values of the render settings a
//! lecturer compares — the terms, the light mode, the BRDF, the integrator
//! and the estimators' choices; [`SettingsOverride::apply`] gives B's
//! settings from A's. Its values are written with the command line's names
//! (`lights = "area"`, `terms = "L0,L1"`), in a lesson file as in any other
//! serde format, and an unknown one is refused with the list of choices.
//!
//! [`differences`] names, setting by setting, what differs between two
//! [`RenderSettings`] (the seed aside): the labels of the two halves of a
//! split ("point lights" | "extended lights").

use std::fmt::Display;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::course::Choice;
use crate::course::{
    BrdfOverride, Integrator, LightMode, LightSampling, LightSelection, MisHeuristic,
    RenderSettings, Sampler, TermSet,
};
use crate::course::{IndirectSampling, Term};

/// What B changes from A; every value left out is A's.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SettingsOverride {
    #[serde(with = "named", skip_serializing_if = "Option::is_none")]
    pub terms: Option<TermSet>,
    /// `lights` in files, as on the command line.
    #[serde(
        rename = "lights",
        with = "named",
        skip_serializing_if = "Option::is_none"
    )]
    pub light_mode: Option<LightMode>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub light_radius: Option<f32>,
    #[serde(with = "named", skip_serializing_if = "Option::is_none")]
    pub brdf: Option<BrdfOverride>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phong_exponent: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phong_specular: Option<f32>,
    /// The index of refraction of `brdf = "glass"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub glass_ior: Option<f32>,
    #[serde(with = "named", skip_serializing_if = "Option::is_none")]
    pub integrator: Option<Integrator>,
    #[serde(with = "named", skip_serializing_if = "Option::is_none")]
    pub light_sampling: Option<LightSampling>,
    #[serde(with = "named", skip_serializing_if = "Option::is_none")]
    pub mis_heuristic: Option<MisHeuristic>,
    #[serde(with = "named", skip_serializing_if = "Option::is_none")]
    pub indirect_sampling: Option<IndirectSampling>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub light_samples: Option<u32>,
    /// Continuations per first hit (turns the splitting pilot off).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub indirect_samples: Option<u32>,
    #[serde(with = "named", skip_serializing_if = "Option::is_none")]
    pub light_selection: Option<LightSelection>,
    #[serde(with = "named", skip_serializing_if = "Option::is_none")]
    pub sampler: Option<Sampler>,
}

impl SettingsOverride {
    /// B's settings: `a` with every value this override sets.
    pub fn apply(&self, a: &RenderSettings) -> RenderSettings {
        fn set<T: Copy>(target: &mut T, value: Option<T>) {
            if let Some(value) = value {
                *target = value;
            }
        }
        let mut b = a.clone();
        set(&mut b.terms, self.terms);
        set(&mut b.light_mode, self.light_mode);
        if self.light_radius.is_some() {
            b.light_radius = self.light_radius;
        }
        set(&mut b.brdf, self.brdf);
        set(&mut b.phong_exponent, self.phong_exponent);
        set(&mut b.phong_specular, self.phong_specular);
        set(&mut b.glass_ior, self.glass_ior);
        set(&mut b.integrator, self.integrator);
        set(&mut b.light_sampling, self.light_sampling);
        set(&mut b.mis_heuristic, self.mis_heuristic);
        set(&mut b.indirect_sampling, self.indirect_sampling);
        set(&mut b.light_samples, self.light_samples);
        if let Some(count) = self.indirect_samples {
            b.indirect_samples = count;
            b.auto_indirect_samples = false;
        }
        set(&mut b.light_selection, self.light_selection);
        set(&mut b.sampler, self.sampler);
        b
    }

    /// Whether it changes nothing.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// What it sets, in words ("extended lights, mirror"); "same settings" if nothing.
    pub fn describe(&self) -> String {
        let applied = self.apply(&RenderSettings::default());
        let words: Vec<String> = phrases(&applied)
            .into_iter()
            .filter(|(setting, _)| self.sets(*setting))
            .map(|(_, phrase)| phrase)
            .collect();
        if words.is_empty() {
            SAME.into()
        } else {
            words.join(", ")
        }
    }

    /// Whether it sets `setting`.
    fn sets(&self, setting: Setting) -> bool {
        match setting {
            Setting::Terms => self.terms.is_some(),
            Setting::Lights => self.light_mode.is_some(),
            Setting::LightRadius => self.light_radius.is_some(),
            Setting::Brdf => self.brdf.is_some(),
            Setting::PhongExponent => self.phong_exponent.is_some(),
            Setting::PhongSpecular => self.phong_specular.is_some(),
            Setting::GlassIor => self.glass_ior.is_some(),
            Setting::Integrator => self.integrator.is_some(),
            Setting::LightSampling => self.light_sampling.is_some(),
            Setting::MisHeuristic => self.mis_heuristic.is_some(),
            Setting::IndirectSampling => self.indirect_sampling.is_some(),
            Setting::LightSamples => self.light_samples.is_some(),
            Setting::IndirectSamples => self.indirect_samples.is_some(),
            Setting::LightSelection => self.light_selection.is_some(),
            Setting::Sampler => self.sampler.is_some(),
            Setting::MaxBounces | Setting::Adaptive => false,
        }
    }
}

/// The words for two settings that do not differ (but in their seed).
pub const SAME: &str = "same settings";

/// The settings [`differences`] compares, in the order it names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    Terms,
    Lights,
    LightRadius,
    Brdf,
    PhongExponent,
    PhongSpecular,
    GlassIor,
    Integrator,
    LightSampling,
    MisHeuristic,
    IndirectSampling,
    LightSamples,
    IndirectSamples,
    LightSelection,
    Sampler,
    MaxBounces,
    Adaptive,
}

/// A setting whose value differs between A and B, each value in words.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Difference {
    pub setting: Setting,
    pub a: String,
    pub b: String,
}

/// Every setting of `a` and `b` that differs, but the seed and the size
/// (B draws another noise of the same image size).
pub fn differences(a: &RenderSettings, b: &RenderSettings) -> Vec<Difference> {
    phrases(a)
        .into_iter()
        .zip(phrases(b))
        .filter(|((_, a), (_, b))| a != b)
        .map(|((setting, a), (_, b))| Difference { setting, a, b })
        .collect()
}

/// The labels of A's and B's halves: each side's values of the settings
/// that differ ("point lights" and "extended lights"), or [`SAME`] twice.
pub fn side_labels(a: &RenderSettings, b: &RenderSettings) -> (String, String) {
    let differences = differences(a, b);
    if differences.is_empty() {
        return (SAME.into(), SAME.into());
    }
    let join = |side: fn(&Difference) -> &String| {
        differences
            .iter()
            .map(side)
            .cloned()
            .collect::<Vec<_>>()
            .join(", ")
    };
    (join(|d| &d.a), join(|d| &d.b))
}

/// Terms joined by '+': "L0+L1+L2".
pub fn terms_phrase(terms: TermSet) -> String {
    terms.iter().map(Term::label).collect::<Vec<_>>().join("+")
}

/// Each compared setting of `s` in words.
fn phrases(s: &RenderSettings) -> Vec<(Setting, String)> {
    let count = |n: u32, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    vec![
        (Setting::Terms, terms_phrase(s.terms)),
        (
            Setting::Lights,
            match s.light_mode {
                LightMode::Authored => "authored lights",
                LightMode::Point => "point lights",
                LightMode::Area => "extended lights",
            }
            .into(),
        ),
        (
            Setting::LightRadius,
            match s.light_radius {
                Some(r) => format!("light radius {r} m"),
                None => "light radius 2% of the scene".into(),
            },
        ),
        (
            Setting::Brdf,
            match s.brdf {
                BrdfOverride::Authored => "authored materials",
                BrdfOverride::Lambert => "Lambert",
                BrdfOverride::Phong => "Phong",
                BrdfOverride::Mirror => "mirror",
                BrdfOverride::Glass => "glass",
            }
            .into(),
        ),
        (
            Setting::PhongExponent,
            format!("Phong n = {}", s.phong_exponent),
        ),
        (
            Setting::PhongSpecular,
            format!("Phong ks = {}", s.phong_specular),
        ),
        (Setting::GlassIor, format!("glass η = {}", s.glass_ior)),
        (
            Setting::Integrator,
            format!("{} integrator", s.integrator.label()),
        ),
        (
            Setting::LightSampling,
            format!("{} light sampling", s.light_sampling.label()),
        ),
        (
            Setting::MisHeuristic,
            format!("{} heuristic", s.mis_heuristic.label()),
        ),
        (
            Setting::IndirectSampling,
            format!("{} indirect sampling", s.indirect_sampling.label()),
        ),
        (
            Setting::LightSamples,
            count(s.light_samples, "light sample"),
        ),
        (
            Setting::IndirectSamples,
            if s.auto_indirect_samples {
                "auto indirect samples".into()
            } else {
                count(s.indirect_samples, "indirect sample")
            },
        ),
        (
            Setting::LightSelection,
            format!("{} light selection", s.light_selection.label()),
        ),
        (Setting::Sampler, format!("{} sampler", s.sampler.label())),
        (Setting::MaxBounces, count(s.max_bounces, "bounce")),
        (
            Setting::Adaptive,
            match &s.adaptive {
                Some(a) => format!("adaptive {}%", 100.0 * a.threshold),
                None => "not adaptive".into(),
            },
        ),
    ]
}

/// Serde for a value written as on the command line: its `Display` out,
/// its `FromStr` in (whose error lists the choices).
pub mod named {
    use super::*;

    pub fn serialize<S: Serializer, T: Display>(
        value: &Option<T>,
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        match value {
            Some(value) => serializer.collect_str(value),
            None => serializer.serialize_none(),
        }
    }

    pub fn deserialize<'de, D, T>(deserializer: D) -> Result<Option<T>, D::Error>
    where
        D: Deserializer<'de>,
        T: FromStr,
        T::Err: Display,
    {
        Option::<String>::deserialize(deserializer)?
            .map(|text| text.parse().map_err(serde::de::Error::custom))
            .transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apply_sets_what_the_override_says_and_keeps_the_rest() {
        let a = RenderSettings {
            light_mode: LightMode::Point,
            auto_indirect_samples: true,
            seed: 7,
            ..RenderSettings::default()
        };
        let over = SettingsOverride {
            light_mode: Some(LightMode::Area),
            brdf: Some(BrdfOverride::Mirror),
            indirect_samples: Some(2),
            ..Default::default()
        };
        let b = over.apply(&a);
        assert_eq!(b.light_mode, LightMode::Area);
        assert_eq!(b.brdf, BrdfOverride::Mirror);
        assert_eq!((b.indirect_samples, b.auto_indirect_samples), (2, false));
        assert_eq!(
            RenderSettings {
                light_mode: a.light_mode,
                brdf: a.brdf,
                indirect_samples: a.indirect_samples,
                auto_indirect_samples: a.auto_indirect_samples,
                ..b.clone()
            },
            a,
            "the rest is A's"
        );
        assert_eq!(SettingsOverride::default().apply(&a), a);
        assert!(SettingsOverride::default().is_empty() && !over.is_empty());
    }

    #[test]
    fn describe_names_what_is_set_and_labels_name_what_differs() {
        let over = SettingsOverride {
            light_mode: Some(LightMode::Area),
            brdf: Some(BrdfOverride::Mirror),
            terms: Some(TermSet::only(Term::L0).with(Term::L1, true)),
            light_samples: Some(4),
            ..Default::default()
        };
        assert_eq!(
            over.describe(),
            "L0+L1, extended lights, mirror, 4 light samples"
        );
        assert_eq!(SettingsOverride::default().describe(), SAME);

        let a = RenderSettings {
            light_mode: LightMode::Point,
            ..RenderSettings::default()
        };
        let b = SettingsOverride {
            light_mode: Some(LightMode::Area),
            ..Default::default()
        }
        .apply(&a);
        assert_eq!(
            side_labels(&a, &b),
            ("point lights".into(), "extended lights".into())
        );
        // the seed is not a difference: B always draws another noise
        let reseeded = RenderSettings {
            seed: 1,
            ..a.clone()
        };
        assert_eq!(side_labels(&a, &reseeded), (SAME.into(), SAME.into()));
        // an override of A's own value changes nothing
        let same = SettingsOverride {
            light_mode: Some(LightMode::Point),
            ..Default::default()
        };
        assert!(differences(&a, &same.apply(&a)).is_empty());
        let lecture = SettingsOverride {
            integrator: Some(Integrator::Lecture),
            brdf: Some(BrdfOverride::Lambert),
            ..Default::default()
        };
        assert_eq!(
            side_labels(&a, &lecture.apply(&a)),
            (
                "authored materials, fast integrator".into(),
                "Lambert, lecture integrator".into()
            )
        );
    }

    #[test]
    fn values_are_written_with_the_command_lines_names() {
        let over = SettingsOverride {
            terms: Some(TermSet::COURSE),
            light_mode: Some(LightMode::Area),
            light_sampling: Some(LightSampling::SolidAngle),
            light_samples: Some(2),
            ..Default::default()
        };
        let json = serde_json::to_string(&over).unwrap();
        assert_eq!(
            json,
            r#"{"terms":"L0,L1,L2","lights":"area","light_sampling":"solid-angle","light_samples":2}"#
        );
        assert_eq!(
            serde_json::from_str::<SettingsOverride>(&json).unwrap(),
            over
        );
        let parsed: SettingsOverride =
            toml::from_str("lights = \"point\"\nbrdf = \"Mirror\"\nintegrator = \"lecture\"")
                .unwrap();
        assert_eq!(parsed.light_mode, Some(LightMode::Point));
        assert_eq!(parsed.brdf, Some(BrdfOverride::Mirror));
        assert_eq!(parsed.integrator, Some(Integrator::Lecture));
    }

    #[test]
    fn an_unknown_value_or_key_is_refused_with_the_choices() {
        let error = toml::from_str::<SettingsOverride>("brdf = \"velvet\"")
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("unknown value 'velvet'")
                && error.contains("authored, lambert, phong, mirror"),
            "{error}"
        );
        let error = toml::from_str::<SettingsOverride>("terms = \"L4\"")
            .unwrap_err()
            .to_string();
        assert!(error.contains("unknown term 'L4'"), "{error}");
        let error = toml::from_str::<SettingsOverride>("colour = \"red\"")
            .unwrap_err()
            .to_string();
        assert!(error.contains("unknown field `colour`"), "{error}");
    }
}
