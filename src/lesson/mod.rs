//! Lessons: the ordered steps a lecturer goes through in the viewer, each a
//! picture of the course with its title, formula and caption in French and
//! in English. A lesson is a TOML file (format: `docs/lessons.md`); the
//! course's lecture, `simulation-notions`, is built in.
//!
//! A step sets only what it changes from the lesson's defaults, which
//! change lumiere's: steps do not accumulate, so any step can be shown
//! first and looks the same.

mod step;

use std::path::Path;

use serde::Deserialize;
use strum::{Display, EnumIter, EnumString, IntoStaticStr};

use crate::course::unknown_choice;

pub use step::{StepSettings, StepView};

/// The course's two languages.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, EnumIter, IntoStaticStr, EnumString, Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<Lang>)]
pub enum Lang {
    Fr,
    #[default]
    En,
}

/// A text in both languages.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Text {
    pub fr: String,
    pub en: String,
}

impl Text {
    pub fn get(&self, lang: Lang) -> &str {
        match lang {
            Lang::Fr => &self.fr,
            Lang::En => &self.en,
        }
    }
}

/// One picture of the lesson and what is said over it.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Step {
    /// Lowercase letters, digits and `-`: the step's name in exported files.
    pub slug: String,
    pub title: Text,
    /// One line of Unicode maths.
    pub formula: String,
    /// One to three sentences: what to look at.
    pub caption: Text,
    /// What the step changes from the lesson's defaults.
    #[serde(default)]
    pub settings: StepSettings,
}

/// A lesson: its title, the defaults its steps start from, its steps.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lesson {
    pub name: String,
    pub title: Text,
    #[serde(default)]
    pub defaults: StepSettings,
    pub steps: Vec<Step>,
}

/// The image a step's `probe = [x, y]` is written for; on another film the
/// pixel is scaled to the same place.
pub const PROBE_FRAME: (u32, u32) = (640, 480);

/// The lessons built into lumiere: (name, TOML text).
pub const BUILTIN: &[(&str, &str)] = &[(
    "simulation-notions",
    include_str!("../../assets/lessons/simulation-notions.toml"),
)];

/// A lesson that could not be read: the file (or built-in name), and what
/// is wrong, with its line and field.
#[derive(Debug, thiserror::Error)]
#[error("{origin}: {problem}")]
pub struct LessonError {
    pub origin: String,
    pub problem: String,
}

impl Lesson {
    /// The built-in lesson `name`, or the lesson file at that path.
    pub fn load(name_or_path: &str) -> Result<Self, LessonError> {
        if let Some((_, text)) = BUILTIN.iter().find(|(name, _)| *name == name_or_path) {
            return Self::parse(text, &format!("built-in lesson {name_or_path}"));
        }
        let path = Path::new(name_or_path);
        let text = std::fs::read_to_string(path).map_err(|e| LessonError {
            origin: name_or_path.into(),
            problem: if path.extension().is_none() && !path.exists() {
                let names: Vec<&str> = BUILTIN.iter().map(|(n, _)| *n).collect();
                format!(
                    "no such lesson file, nor a built-in lesson (built in: {})",
                    names.join(", ")
                )
            } else {
                format!("cannot read: {e}")
            },
        })?;
        Self::parse(&text, name_or_path)
    }

    /// Reads a lesson from its TOML `text`; `origin` names it in errors.
    pub fn parse(text: &str, origin: &str) -> Result<Self, LessonError> {
        let fail = |problem: String| LessonError {
            origin: origin.into(),
            problem,
        };
        let lesson: Lesson = toml::from_str(text).map_err(|e| fail(describe(&e, text)))?;
        if lesson.steps.is_empty() {
            return Err(fail("the lesson has no [[steps]]".into()));
        }
        let mut slugs = std::collections::HashSet::new();
        for (i, step) in lesson.steps.iter().enumerate() {
            let at = format!("step {} ('{}')", i + 1, step.slug);
            let valid_slug = !step.slug.is_empty()
                && step
                    .slug
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-');
            if !valid_slug {
                return Err(fail(format!(
                    "{at}: slug must be lowercase letters, digits and '-'"
                )));
            }
            if !slugs.insert(step.slug.as_str()) {
                return Err(fail(format!("{at}: slug used by an earlier step")));
            }
            lesson
                .view(i, PROBE_FRAME.0, PROBE_FRAME.1)
                .map_err(|e| fail(format!("{at}: {e}")))?;
        }
        Ok(lesson)
    }

    /// What step `index` (from 0) shows on a film of `width` × `height`:
    /// lumiere's defaults, then the lesson's, then the step's. A probed
    /// pixel is given in a 640×480 image ([`PROBE_FRAME`]) and lands on the
    /// same place of the film.
    pub fn view(&self, index: usize, width: u32, height: u32) -> Result<StepView, String> {
        let mut view = StepView::new(width, height);
        self.defaults.apply(&mut view);
        self.steps[index].settings.apply(&mut view);
        view.settings.validate()?;
        if let Some(b) = view.split_settings() {
            b.validate().map_err(|e| format!("split: {e}"))?;
            if view.display.layout != crate::render::display::Layout::Single {
                return Err("a step shows either a split or the four-up layout, not both".into());
            }
        }
        if let Some((x, y)) = view.probe {
            let (frame_width, frame_height) = PROBE_FRAME;
            if x >= frame_width || y >= frame_height {
                return Err(format!(
                    "probe ({x}, {y}) lies outside the {frame_width}×{frame_height} image"
                ));
            }
            let scale = |v: u32, from: u32, to: u32| (v as u64 * to as u64 / from as u64) as u32;
            view.probe = Some((scale(x, frame_width, width), scale(y, frame_height, height)));
        }
        Ok(view)
    }
}

/// A TOML error as "line L, column C: message" (the message names the field).
fn describe(error: &toml::de::Error, text: &str) -> String {
    let message = error.message().trim_end();
    match error.span() {
        Some(span) => {
            // toml spans fall on character boundaries; a wrong one reads as the end
            let before = text.get(..span.start).unwrap_or(text);
            let line = before.matches('\n').count() + 1;
            let line_start = before.rfind('\n').map_or(0, |i| i + 1);
            let column = before[line_start..].chars().count() + 1;
            format!("line {line}, column {column}: {message}")
        }
        None => message.to_string(),
    }
}
