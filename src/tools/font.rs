//! The fonts of the tools' images, embedded in the binary (`assets/fonts/`,
//! their licences beside them), so that no system font or fontconfig is
//! needed:
//!
//! * Hack Regular (MIT/Bitstream Vera licence): the bench's plots register
//!   it with plotters; the strips rasterize it with ab_glyph.
//! * DejaVu Sans (Bitstream Vera licence, DejaVu changes in the public
//!   domain): the slides' titles, formulas and captions, rasterized with
//!   ab_glyph. It has the French accents and the lessons' mathematics
//!   (subscripts, Greek letters, ∫, Σ, ≈, ∈, arrows).

use std::sync::LazyLock;

use ab_glyph::{Font, FontRef, GlyphId, PxScale, ScaleFont};

/// The TrueType file of Hack Regular.
pub const HACK_REGULAR: &[u8] = include_bytes!("../../assets/fonts/Hack-Regular.ttf");

/// The TrueType file of DejaVu Sans (the viewer draws the lessons with it too).
pub const DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// [`HACK_REGULAR`] parsed once.
pub fn hack_regular() -> &'static FontRef<'static> {
    static FONT: LazyLock<FontRef<'static>> = LazyLock::new(|| {
        FontRef::try_from_slice(HACK_REGULAR).expect("the embedded font is a valid TrueType file")
    });
    &FONT
}

/// [`DEJAVU_SANS`] parsed once.
pub fn dejavu_sans() -> &'static FontRef<'static> {
    static FONT: LazyLock<FontRef<'static>> = LazyLock::new(|| {
        FontRef::try_from_slice(DEJAVU_SANS).expect("the embedded font is a valid TrueType file")
    });
    &FONT
}

/// The glyphs of `text` in `font` at `scale`, each with its pen position
/// from the start (advances and kerning), and the width of the whole; '?'
/// for the characters the font lacks.
pub fn set_text(font: &FontRef<'static>, text: &str, scale: PxScale) -> (Vec<(GlyphId, f32)>, f32) {
    let scaled = font.as_scaled(scale);
    let mut glyphs = Vec::with_capacity(text.len());
    let mut x = 0.0;
    for c in text.chars() {
        let id = match font.glyph_id(c) {
            GlyphId(0) => font.glyph_id('?'),
            id => id,
        };
        if let Some(&(previous, _)) = glyphs.last() {
            x += scaled.kern(previous, id);
        }
        glyphs.push((id, x));
        x += scaled.h_advance(id);
    }
    (glyphs, x)
}

#[cfg(test)]
mod tests {
    use ab_glyph::Font;

    #[test]
    fn the_embedded_font_has_every_printable_ascii_character() {
        let font = super::hack_regular();
        for c in '!'..='~' {
            assert_ne!(font.glyph_id(c).0, 0, "{c:?} has no glyph");
        }
    }

    /// Every character of the built-in lessons' texts, in both languages,
    /// has a glyph in DejaVu Sans: no formula prints a '?'.
    #[test]
    fn dejavu_sans_has_every_character_of_the_built_in_lessons() {
        let font = super::dejavu_sans();
        for (name, _) in crate::lesson::BUILTIN {
            let lesson = crate::lesson::Lesson::load(name).unwrap();
            let mut texts = vec![lesson.title.fr.clone(), lesson.title.en.clone()];
            for step in &lesson.steps {
                texts.extend([step.formula.clone(), step.title.fr.clone()]);
                texts.extend([step.title.en.clone(), step.caption.fr.clone()]);
                texts.push(step.caption.en.clone());
            }
            for c in texts
                .iter()
                .flat_map(|t| t.chars())
                .filter(|c| !c.is_whitespace())
            {
                assert_ne!(font.glyph_id(c).0, 0, "{name}: {c:?} has no glyph");
            }
        }
    }
}
