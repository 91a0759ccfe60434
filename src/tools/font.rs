//! The font of the tools' images: Hack Regular, embedded in the binary
//! (`assets/fonts/`, MIT/Bitstream Vera licence), so that no system font or
//! fontconfig is needed. The bench's plots register it with plotters; the
//! strips rasterize it with ab_glyph (antialiased coverage).

use std::sync::LazyLock;

use ab_glyph::FontRef;

/// The TrueType file of Hack Regular.
pub const HACK_REGULAR: &[u8] = include_bytes!("../../assets/fonts/Hack-Regular.ttf");

/// [`HACK_REGULAR`] parsed once.
pub fn hack_regular() -> &'static FontRef<'static> {
    static FONT: LazyLock<FontRef<'static>> = LazyLock::new(|| {
        FontRef::try_from_slice(HACK_REGULAR).expect("the embedded font is a valid TrueType file")
    });
    &FONT
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
}
