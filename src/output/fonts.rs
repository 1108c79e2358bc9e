//! The plot font, embedded: DejaVu Sans (Bitstream Vera licence, `assets/fonts/`) is compiled
//! into the binary and registered with plotters' `ab_glyph` renderer as `"sans-serif"`, so PNGs
//! need no fontconfig, freetype or installed font.

use std::sync::Once;

/// The family name every plot uses.
pub const FONT: &str = "sans-serif";

static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Registers the embedded font (once per process; later calls do nothing).
pub fn register() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // the embedded file is a valid TrueType font; a failure would only mean no text
        let _ =
            plotters::style::register_font(FONT, plotters::style::FontStyle::Normal, DEJAVU_SANS);
    });
}
