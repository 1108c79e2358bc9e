//! The plot font, embedded: DejaVu Sans (Bitstream Vera licence, `assets/fonts/`) is compiled
//! into the binary and registered with plotters' `ab_glyph` renderer as `"sans-serif"`, so PNGs
//! need no fontconfig, freetype or installed font.

use std::sync::Once;

/// The family name every plot uses.
pub const FONT: &str = "sans-serif";

static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Registers the embedded font (once per process; later calls do nothing).
///
/// ```
/// use plotters::prelude::*;
/// celltissue::output::fonts::register();
/// celltissue::output::fonts::register(); // later calls do nothing
/// // text in the embedded font, without any installed font
/// let mut pixels = vec![255u8; 80 * 24 * 3];
/// {
///     let area = BitMapBackend::with_buffer(&mut pixels, (80, 24)).into_drawing_area();
///     let font = (celltissue::output::fonts::FONT, 16).into_font().color(&BLACK);
///     area.draw_text("μ = 1", &font, (2, 2)).unwrap();
///     area.present().unwrap();
/// }
/// assert!(pixels.iter().any(|&p| p < 100)); // the glyphs left dark pixels
/// ```
pub fn register() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // the embedded file is a valid TrueType font; a failure would only mean no text
        let _ =
            plotters::style::register_font(FONT, plotters::style::FontStyle::Normal, DEJAVU_SANS);
    });
}
